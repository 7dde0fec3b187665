"""The chapter-4 line-up of classifiers (thesis 4.3, table 4.7), as the thesis author ran them.

Every setting of the thesis presets below was read from the text (4.3) and checked
against the author's published analysis code (``mathewzilla/old_matlab``,
``T_RO_and_Frontiers/``); where the two disagree the code's setting is used,
because it is the code that produced the thesis' numbers. ``docs/methods.md``
tabulates every setting with its source. The presets take the dataset's whole
recording per trial (``vibrissa generate radial-distance`` keeps 0.6 s before and
0.7 s after the peak) and cut their own window after filtering, as the author's
code did.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from sklearn.base import BaseEstimator
from sklearn.pipeline import Pipeline

from vibrissa._validate import positive
from vibrissa.classify._feature import FeatureRegressionClassifier
from vibrissa.classify._naive_bayes import StationaryNaiveBayes
from vibrissa.classify._spectral import FrequencyTemplateClassifier
from vibrissa.classify._static_beam import StaticBeamClassifier
from vibrissa.classify._template import TimeTemplateClassifier
from vibrissa.classify._windows import RecordingWindow

__all__ = [
    "CHAPTER4_KEYS",
    "CHAPTER4_ONE_SET",
    "chapter4_classifiers",
    "onset_window",
    "peak_window",
]

#: Keys of :func:`chapter4_classifiers`, in the thesis' order of presentation.
CHAPTER4_KEYS = (
    "static_beam_measured",
    "static_beam_fitted",
    "frequency",
    "template",
    "feature",
    "naive_bayes_raw",
    "naive_bayes_velocity",
    "naive_bayes_velocity_robust",
)

#: Classifiers the author trained on *one* complete set (``data_train{2,:}``, the
#: third recorded set) although three were loaded: the template (method 1 of
#: ``train_template.m``), frequency (method 7) and feature (``train_feature.m``)
#: code each keep only that set. Naive Bayes concatenated all three training sets
#: per class; the static beam equation is not trained.
CHAPTER4_ONE_SET = ("frequency", "template", "feature")

#: Rest output of the Hall sensor, V (2.5 V, 3.2.3).
_REST_V = 2.5


def _samples(n_at_1khz: int, fs: float) -> int:
    """A sample count of the 1-kHz code at another rate."""
    return int(round(n_at_1khz * fs / 1000.0))


def onset_window(
    fs: float,
    signal: Literal["raw", "velocity", "lowpass"] = "raw",
    start_at_1khz: int = 0,
    n_at_1khz: int = 750,
    **kwargs: Any,
) -> RecordingWindow:
    """The author's window: 750 samples (at 1 kHz) from 100 before ``x`` exceeds 0.1 V.

    Parameters
    ----------
    fs : float
        Sampling rate, Hz.
    signal : {"raw", "velocity", "lowpass"}
        Filter run over the whole recording first (see :class:`RecordingWindow`).
    start_at_1khz, n_at_1khz : int
        A sub-window of it, in 1-kHz samples (the frequency method used samples
        501-750: ``start_at_1khz=500, n_at_1khz=250``).
    **kwargs
        Further :class:`RecordingWindow` parameters.
    """
    return RecordingWindow(
        align="onset",
        offset_samples=_samples(-99 + start_at_1khz, fs),
        n_samples=_samples(n_at_1khz, fs),
        channels=(0,),
        signal=signal,
        sample_rate_hz=fs,
        rest_v=_REST_V,
        onset_threshold_v=0.1,
        **kwargs,
    )


def peak_window(fs: float, half_width_s: float = 0.325) -> RecordingWindow:
    """The text's window: both channels, ``half_width_s`` either side of the peak (4.2)."""
    n = int(round(half_width_s * fs))
    return RecordingWindow(
        align="peak",
        offset_samples=-n,
        n_samples=2 * n + 1,
        channels=None,
        sample_rate_hz=fs,
        rest_v=_REST_V,
    )


def chapter4_classifiers(
    sample_rate_hz: float,
    whisker: dict[str, Any] | str,
    preset: Literal["thesis", "vibrissa"] = "thesis",
) -> dict[str, BaseEstimator]:
    """Unfitted estimators for the five methods of chapter 4 (eight variants).

    Parameters
    ----------
    sample_rate_hz : float
        Sampling rate of the trials, Hz (1000 in chapter 4).
    whisker : dict or str
        Measured whisker parameters (or their JSON), for the static beam equation;
        see :class:`StaticBeamClassifier`.
    preset : {"thesis", "vibrissa"}, default="thesis"
        ``"thesis"``: each method as the author ran it (settings in
        ``docs/methods.md``), on the ``x`` channel of the author's onset window.
        ``"vibrissa"``: the estimators' own defaults on both channels of the text's
        +/-325 ms window about the peak (the line-up before the author's code was
        read; kept for comparison).

    Returns
    -------
    dict of str to estimator
        Every step is built for ``sample_rate_hz`` and refuses data at another
        rate (:func:`~vibrissa.classify.check_sample_rate`).
        Keys :data:`CHAPTER4_KEYS`. Thesis preset: ``static_beam_measured`` /
        ``static_beam_fitted`` (4.3.1; radius only); ``frequency`` (4.3.2:
        ``|Re DFT|`` of window samples 501-750, DC bin zeroed, L1 distance);
        ``template`` (4.3.3: causal 10th-order 20 Hz Butterworth, L1 distance);
        ``feature`` (4.3.4: peak and supra-0.05 V width about the peak, degree-4
        polynomials, training widths smoothed over 5 neighbours and floored at
        0.35 s); ``naive_bayes_raw`` (4.3.5: 500 bins over rest +/- 2.5 V) and
        ``naive_bayes_velocity`` (first difference, causal 101-tap Gaussian of
        sigma 15 samples, 500 bins over +/-0.1 V per sample, sigma 1 bin truncated
        at 10, ``log(l + eps)``); and, beyond the thesis,
        ``naive_bayes_velocity_robust`` (the estimator's defaults on the peak window).
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    if preset not in ("thesis", "vibrissa"):
        raise ValueError(f"preset must be 'thesis' or 'vibrissa', got {preset!r}")
    robust = Pipeline(
        [
            ("window", peak_window(fs)),
            ("naive_bayes", StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs)),
        ]
    )
    if preset == "vibrissa":

        def peak(est: BaseEstimator) -> Pipeline:
            return Pipeline([("window", peak_window(fs)), ("classifier", est)])

        return {
            "static_beam_measured": peak(StaticBeamClassifier(whisker=whisker, sample_rate_hz=fs)),
            "static_beam_fitted": peak(
                StaticBeamClassifier(whisker=whisker, fit_parameters=True, sample_rate_hz=fs)
            ),
            "frequency": peak(FrequencyTemplateClassifier(sample_rate_hz=fs)),
            "template": peak(TimeTemplateClassifier(sample_rate_hz=fs)),
            "feature": peak(FeatureRegressionClassifier(sample_rate_hz=fs, degree=5)),
            "naive_bayes_raw": peak(StationaryNaiveBayes(signal="raw", sample_rate_hz=fs)),
            "naive_bayes_velocity": peak(
                StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs)
            ),
            "naive_bayes_velocity_robust": robust,
        }

    eps = float(np.finfo(float).eps)
    nb_thesis = dict(
        n_bins=500,
        smoothing_sigma=1.0,
        smoothing_radius_bins=10,
        likelihood_floor=eps,
        sample_rate_hz=fs,
        signal="raw",
    )
    return {
        "static_beam_measured": Pipeline(
            [
                ("window", onset_window(fs)),
                (
                    "classifier",
                    StaticBeamClassifier(whisker=whisker, fit_parameters=False, sample_rate_hz=fs),
                ),
            ]
        ),
        "static_beam_fitted": Pipeline(
            [
                ("window", onset_window(fs)),
                (
                    "classifier",
                    StaticBeamClassifier(whisker=whisker, fit_parameters=True, sample_rate_hz=fs),
                ),
            ]
        ),
        "frequency": Pipeline(
            [
                ("window", onset_window(fs, start_at_1khz=500, n_at_1khz=250)),
                (
                    "classifier",
                    FrequencyTemplateClassifier(
                        sample_rate_hz=fs,
                        cutoff_hz=None,
                        spectrum="abs_real",
                        one_sided=False,
                        zero_dc=True,
                        distance="l1",
                    ),
                ),
            ]
        ),
        "template": Pipeline(
            [
                ("window", onset_window(fs, signal="lowpass", lowpass_hz=20.0, lowpass_order=10)),
                (
                    "classifier",
                    TimeTemplateClassifier(sample_rate_hz=fs, cutoff_hz=None, distance="l1"),
                ),
            ]
        ),
        "feature": Pipeline(
            [
                ("window", onset_window(fs)),
                (
                    "classifier",
                    FeatureRegressionClassifier(
                        sample_rate_hz=fs,
                        threshold_v=0.05,
                        degree=4,
                        duration_mode="peak",
                        duration_smoothing_span=5,
                        min_duration_s=0.35,
                    ),
                ),
            ]
        ),
        "naive_bayes_raw": Pipeline(
            [
                ("window", onset_window(fs)),
                (
                    "naive_bayes",
                    StationaryNaiveBayes(value_range=(_REST_V - 2.5, _REST_V + 2.5), **nb_thesis),
                ),
            ]
        ),
        "naive_bayes_velocity": Pipeline(
            [
                (
                    "window",
                    onset_window(
                        fs,
                        signal="velocity",
                        velocity_sigma_samples=15.0,
                        velocity_half_width_samples=50,
                    ),
                ),
                (
                    "naive_bayes",
                    StationaryNaiveBayes(value_range=(-0.1 * fs, 0.1 * fs), **nb_thesis),
                ),
            ]
        ),
        "naive_bayes_velocity_robust": robust,
    }
