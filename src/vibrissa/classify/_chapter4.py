"""The chapter-4 line-up of classifiers (thesis 4.3, table 4.7)."""

from __future__ import annotations

from typing import Any

from sklearn.base import BaseEstimator

from vibrissa._validate import positive
from vibrissa.classify._feature import FeatureRegressionClassifier
from vibrissa.classify._naive_bayes import StationaryNaiveBayes
from vibrissa.classify._spectral import FrequencyTemplateClassifier
from vibrissa.classify._static_beam import StaticBeamClassifier
from vibrissa.classify._template import TimeTemplateClassifier

__all__ = ["CHAPTER4_KEYS", "chapter4_classifiers"]

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


def chapter4_classifiers(
    sample_rate_hz: float, whisker: dict[str, Any]
) -> dict[str, BaseEstimator]:
    """Unfitted estimators for the five methods of chapter 4 (eight variants).

    Parameters
    ----------
    sample_rate_hz : float
        Sampling rate of the trials, Hz (1000 in chapter 4).
    whisker : dict or str
        Measured whisker parameters (or their JSON), for the static beam equation;
        see :class:`StaticBeamClassifier`.

    Returns
    -------
    dict of str to estimator
        ``static_beam_measured`` / ``static_beam_fitted`` (4.3.1, measured or
        grid-fitted parameters; radius only), ``frequency`` (4.3.2), ``template``
        (4.3.3, every training trial a template), ``feature`` (4.3.4, degree 5,
        0.05 V threshold), ``naive_bayes_raw`` and ``naive_bayes_velocity``
        (4.3.5 on raw deflection and on velocity; 100 bins smoothed over 5), and,
        beyond the thesis, ``naive_bayes_velocity_robust`` (histogram range from
        the central 99 % of the training data).
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    return {
        "static_beam_measured": StaticBeamClassifier(whisker=whisker, fit_parameters=False),
        "static_beam_fitted": StaticBeamClassifier(whisker=whisker, fit_parameters=True),
        "frequency": FrequencyTemplateClassifier(sample_rate_hz=fs),
        "template": TimeTemplateClassifier(sample_rate_hz=fs, templates="all"),
        "feature": FeatureRegressionClassifier(sample_rate_hz=fs, degree=5, threshold_v=0.05),
        "naive_bayes_raw": StationaryNaiveBayes(signal="raw", sample_rate_hz=fs),
        "naive_bayes_velocity": StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs),
        # beyond the thesis: histogram range from the central 99 % of the training
        # data instead of its full range (heavy tails coarsen the thesis' bins)
        "naive_bayes_velocity_robust": StationaryNaiveBayes(
            signal="velocity", sample_rate_hz=fs, value_range="robust"
        ),
    }
