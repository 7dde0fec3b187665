"""Chapter 5: surface angle, contact speed and texture classified simultaneously.

The chapter-4 estimators are reused with the chapter-5 preprocessing as a
:class:`SignalTransform` step of a :class:`sklearn.pipeline.Pipeline`
(templates on raw, low-pass, high-pass, velocity and acceleration signals, 5.3.1;
spectral templates, 5.3.2; naive Bayes on acceleration, 5.3.4). New here are the
combined classifier of 5.3.5/5.4.5 (:class:`SpeedFirstClassifier`) and, beyond
the thesis, naive Bayes with the joint likelihood of an amplitude histogram and a
normalised template (:class:`JointLikelihoodNaiveBayes`, end of 5.5).

Labels
------
The chapter-4 base class encodes joint classes with ``numpy.unique(axis=0)``,
which does not accept object arrays that mix numbers and strings. Chapter-5
labels are therefore numeric rows ``[angle_deg, speed_mm_s, texture_code]`` where
``texture_code`` is the index of the texture in :data:`TEXTURE_CODES` (smooth to
coarse, so a signed texture error counts grades, as the thesis' tables do). This
is the one place the code is defined; use :func:`encode_texture` /
:func:`decode_texture` to convert.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin, clone
from sklearn.pipeline import Pipeline
from sklearn.utils.validation import check_is_fitted, validate_data

from vibrissa import signal as vsig
from vibrissa._validate import positive
from vibrissa.classify._base import SampleRateMixin, TrialClassifier, sample_rate_fit_params
from vibrissa.classify._naive_bayes import StationaryNaiveBayes
from vibrissa.classify._spectral import FrequencyTemplateClassifier
from vibrissa.classify._template import TimeTemplateClassifier, nearest_template_scores
from vibrissa.classify._texture_features import FeaturePolynomialClassifier
from vibrissa.classify._windows import trials_3d
from vibrissa.data.schema import TEXTURE_CODES, decode_texture, encode_texture, parse_whisker

__all__ = [
    "CHAPTER5_KEYS",
    "CHAPTER5_TARGETS",
    "TEXTURE_CODES",
    "JointLikelihoodNaiveBayes",
    "SignalTransform",
    "SpeedFirstClassifier",
    "chapter5_classifiers",
    "decode_texture",
    "encode_texture",
    "joint_log_scores",
    "resonance_hz",
]

#: Columns of the chapter-5 label rows ``y``.
CHAPTER5_TARGETS = ("angle_deg", "speed_mm_s", "texture")


def resonance_hz(whisker: Mapping[str, Any] | str) -> float:
    """The whisker's resonance in chapter-5 recordings, Hz (the notch frequency of 5.3.1).

    The thesis notches "the resonant frequency of the whisker", 30 Hz, found by
    inspecting the FFT of recordings in which the surface holds the whisker's tip.
    That is the first mode of the tip-pinned whisker (``docs/physics.md``): the key
    ``tip_pinned_frequency_hz`` when the whisker attribute has it (simulated
    datasets), else the first free natural frequency ``natural_frequencies_hz[0]``
    (e.g. imported recordings whose mapping gives only that).

    Parameters
    ----------
    whisker : dict or str
        The Dataset attribute ``whisker`` (JSON or parsed).

    Returns
    -------
    float
    """
    w = parse_whisker(whisker)
    if w.get("tip_pinned_frequency_hz"):
        return positive("tip_pinned_frequency_hz", float(w["tip_pinned_frequency_hz"]))
    f = w.get("natural_frequencies_hz")
    if not f:
        raise ValueError(
            "whisker parameters lack 'tip_pinned_frequency_hz' and 'natural_frequencies_hz' "
            "(the notch frequency)"
        )
    return positive("natural_frequencies_hz[0]", float(f[0]))


def _input_ndim(X: Any) -> int:
    """Number of dimensions of an input as given (before it becomes 3-D)."""
    nd = getattr(X, "ndim", None)
    return int(nd) if nd is not None else np.asarray(X).ndim


_KINDS = ("raw", "lowpass", "highpass", "velocity", "acceleration", "causal_velocity")


class SignalTransform(SampleRateMixin, TransformerMixin, BaseEstimator):
    """Chapter-5 preprocessing of trials ``(n, channels, time)`` as a Pipeline step (5.3.1).

    ``fit`` validates the parameters and records the shape of a trial and the sample
    rate (``sample_rate_hz_``); ``transform`` refuses trials of another shape (as every
    scikit-learn transformer does) and, when given one, another rate. In a Pipeline
    the steps after it see ``sample_rate_hz / downsample``
    (:func:`~vibrissa.classify.sample_rate_fit_params` passes them that rate).

    Parameters
    ----------
    kind : {"raw", "lowpass", "highpass", "velocity", "acceleration"}, default="raw"
        ``lowpass``: Butterworth ``lowpass_order`` at ``lowpass_hz`` (thesis: 3rd
        order, 20 Hz); ``highpass``: order ``highpass_order`` at ``highpass_hz``
        (10th order, 35 Hz); ``velocity``/``acceleration``: Gaussian-smoothed
        first/second derivative (:func:`vibrissa.signal.velocity`);
        ``causal_velocity``: the thesis author's naive-Bayes velocity (first
        difference and a causal 101-tap Gaussian of sigma 15 samples,
        :func:`vibrissa.signal.causal_gaussian_velocity`; 4.3.5 and docs/methods.md).
    sample_rate_hz : float, default=4000.0
        Sampling rate of the input, Hz.
    notch_hz : float or None, default=None
        Resonance removed by an IIR notch after the filter (thesis: with the
        low- and high-pass filters), Hz; ``None`` for none.
    notch_quality : float, default=5.0
        Quality factor of the notch (bandwidth ``notch_hz / notch_quality``).
    lowpass_hz, lowpass_order, highpass_hz, highpass_order
        Butterworth settings.
    derivative_sigma_samples : float, default=3.0
        Gaussian smoothing of the derivatives, samples.
    downsample : int, default=1
        Keep every ``downsample``-th sample afterwards. Only alias-free after a
        low-pass well below the new Nyquist frequency (e.g. 20 Hz -> 200 Hz with
        ``downsample=20`` at 4 kHz); it makes templates 20 times cheaper.
    """

    def __init__(
        self,
        kind: Literal[
            "raw", "lowpass", "highpass", "velocity", "acceleration", "causal_velocity"
        ] = "raw",
        sample_rate_hz: float = 4000.0,
        notch_hz: float | None = None,
        notch_quality: float = 5.0,
        lowpass_hz: float = 20.0,
        lowpass_order: int = 3,
        highpass_hz: float = 35.0,
        highpass_order: int = 10,
        derivative_sigma_samples: float = 3.0,
        downsample: int = 1,
    ) -> None:
        self.kind = kind
        self.sample_rate_hz = sample_rate_hz
        self.notch_hz = notch_hz
        self.notch_quality = notch_quality
        self.lowpass_hz = lowpass_hz
        self.lowpass_order = lowpass_order
        self.highpass_hz = highpass_hz
        self.highpass_order = highpass_order
        self.derivative_sigma_samples = derivative_sigma_samples
        self.downsample = downsample

    def _check_params(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"kind must be one of {_KINDS}, got {self.kind!r}")
        ds = self.downsample
        if isinstance(ds, bool) or not isinstance(ds, int | np.integer) or ds < 1:
            raise ValueError(f"downsample must be a positive integer, got {ds!r}")
        positive("sample_rate_hz", self.sample_rate_hz)

    def _rate_after(self, sample_rate_hz: float) -> float:
        ds = self.downsample
        ok = not isinstance(ds, bool) and isinstance(ds, int | np.integer) and ds >= 1
        return sample_rate_hz / int(ds) if ok else sample_rate_hz

    def fit(self, X: Any, y: Any = None, sample_rate_hz: float | None = None) -> SignalTransform:
        """Validate the parameters and record the shape of a trial and the rate.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        y : ignored
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not the constructor's.

        Returns
        -------
        self
        """
        self._check_params()
        rate = self._fit_rate(sample_rate_hz)
        X3 = self._as3d(X)
        if _input_ndim(X) == 2:
            validate_data(self, X, reset=True, dtype=np.float64, ensure_all_finite=True)
        else:
            # n_features_in_ counts samples of a 2-D input; of 3-D, channels x time
            if hasattr(self, "feature_names_in_"):
                del self.feature_names_in_
            self.n_features_in_ = X3.shape[1] * X3.shape[2]
        self.n_channels_, self.n_timepoints_ = X3.shape[1], X3.shape[2]
        self.sample_rate_hz_ = rate
        self.fitted_ = True
        return self

    @staticmethod
    def _as3d(X: Any) -> np.ndarray:
        return trials_3d(X)

    def _check_shape(self, X: Any) -> np.ndarray:
        X3 = self._as3d(X)
        if _input_ndim(X) == 2 and self.n_channels_ == 1:
            validate_data(self, X, reset=False, dtype=np.float64, ensure_all_finite=True)
        name = type(self).__name__
        if X3.shape[1] != self.n_channels_:
            raise ValueError(
                f"X has {X3.shape[1]} channels, but {name} is expecting "
                f"{self.n_channels_} channels as input"
            )
        if X3.shape[2] != self.n_timepoints_:
            raise ValueError(
                f"X has {X3.shape[2]} timepoints (features), but {name} is "
                f"expecting {self.n_timepoints_} timepoints as input"
            )
        return X3

    def transform(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Filter (and optionally notch and downsample) every trial along time.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_channels, n_timepoints // downsample (rounded up))
        """
        self._check_predict_rate(sample_rate_hz)
        self._check_params()
        X = self._check_shape(X)
        fs = float(self.sample_rate_hz)
        if self.kind == "lowpass":
            X = vsig.lowpass(X, self.lowpass_hz, fs, order=self.lowpass_order)
        elif self.kind == "highpass":
            X = vsig.highpass(X, self.highpass_hz, fs, order=self.highpass_order)
        elif self.kind == "velocity":
            X = vsig.velocity(X, fs, sigma_samples=self.derivative_sigma_samples)
        elif self.kind == "acceleration":
            X = vsig.acceleration(X, fs, sigma_samples=self.derivative_sigma_samples)
        elif self.kind == "causal_velocity":
            X = vsig.causal_gaussian_velocity(X, fs)
        if self.notch_hz is not None:
            X = vsig.notch(X, self.notch_hz, fs, quality=self.notch_quality)
        if self.downsample > 1:
            X = np.ascontiguousarray(X[..., :: int(self.downsample)])
        return X

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.requires_fit = True
        return tags


def joint_log_scores(estimator: Any, X: Any) -> np.ndarray:
    """Per-class log scores of a fitted estimator, on the log-probability scale.

    :class:`TrialClassifier` subclasses (also as the last step of a Pipeline) give
    their unnormalised joint scores (no softmax underflow for over-confident naive
    Bayes); any other estimator the log of ``predict_proba`` (floored at 1e-300).

    Parameters
    ----------
    estimator : fitted estimator or Pipeline
    X : array-like of shape (n_trials, n_channels, n_timepoints)

    Returns
    -------
    ndarray of shape (n_trials, n_classes)
    """
    est = estimator
    if isinstance(est, Pipeline):
        for _, step in est.steps[:-1]:
            if step is not None and step != "passthrough":
                X = step.transform(X)
        est = est.steps[-1][1]
    if isinstance(est, TrialClassifier):
        check_is_fitted(est)
        return est._joint_scores(est._check_X(X, reset=False))
    return np.log(np.maximum(est.predict_proba(X), 1e-300))


class SpeedFirstClassifier(TrialClassifier):
    """The combined classifier of thesis 5.3.5 / 5.4.5: speed first, then the rest.

    The speed of a trial is estimated by ``speed_estimator`` (thesis: the f1
    feature classifier), then the trial is classified by ``estimator`` (thesis:
    naive Bayes on velocity) among the joint classes with that speed only (32 of
    352 in the thesis). The thesis then fixes the angle as well and classifies
    among the 4 textures; for a classifier that scores joint classes this gives
    the texture of the winning (angle, texture) pair, so the two texture results
    are identical (as they are in 5.4.5: kappa 0.18 and 0.18).

    Parameters
    ----------
    speed_estimator : estimator, optional
        Fitted on the speed column only (``y[:, [speed_column]]``); default
        :class:`FeaturePolynomialClassifier` on f1, degree 2.
    estimator : estimator, optional
        Scores the joint classes; default :class:`StationaryNaiveBayes` on
        velocity.
    speed_column : int, default=1
        Column of ``y`` holding the speed. A 1-D ``y`` (or one of a single column)
        is taken as the speeds themselves (``speed_column`` is then not used): the
        speed stage decides.
    sample_rate_hz : float, default=4000.0
        Sampling rate of the trials, Hz (also of the default estimators). Given
        estimators built for another rate are refused at ``fit``.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes, n_targets)
    sample_rate_hz_ : float
        The rate it was fitted at, Hz (both stages were fitted at it).
    speed_estimator_ : estimator or None
        ``None`` when the training data hold a single speed (then it is fixed).
    estimator_ : estimator
    n_channels_, n_timepoints_, n_features_in_ : int
    """

    def __init__(
        self,
        speed_estimator: Any = None,
        estimator: Any = None,
        speed_column: int = 1,
        sample_rate_hz: float = 4000.0,
    ) -> None:
        self.speed_estimator = speed_estimator
        self.estimator = estimator
        self.speed_column = speed_column
        self.sample_rate_hz = sample_rate_hz

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.classifier_tags.poor_score = True
        return tags

    def _rate_parts(self) -> list[tuple[str, Any]]:
        return [
            (k, e)
            for k, e in (("speed_estimator", self.speed_estimator), ("estimator", self.estimator))
            if e is not None
        ]

    def _speed_column(self) -> int:
        """Column of ``classes_`` (as 2-D) holding the speed; 0 for a single column."""
        single = self.classes_.ndim == 1 or self.classes_.shape[1] == 1
        return 0 if single else int(self.speed_column)

    def _class_speeds(self) -> np.ndarray:
        cls = self.classes_ if self.classes_.ndim == 2 else self.classes_[:, None]
        try:
            return cls[:, self._speed_column()].astype(float)
        except (TypeError, ValueError):
            raise ValueError(
                f"the speed labels must be numeric (mm/s), got values like {cls[:3, 0]!r}"
            ) from None

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        col = self.speed_column
        if (
            self.classes_.ndim == 2
            and self.classes_.shape[1] > 1
            and (
                isinstance(col, bool)
                or not isinstance(col, int | np.integer)
                or not 0 <= int(col) < self.classes_.shape[1]
            )
        ):
            raise ValueError(
                f"speed_column must lie in [0, {self.classes_.shape[1] - 1}], got {col!r}"
            )
        speeds = np.unique(self._class_speeds())
        fs = float(self.sample_rate_hz)
        y_rows = self.classes_[y_idx]
        est = (
            StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs)
            if self.estimator is None
            else self.estimator
        )
        self.estimator_ = clone(est).fit(X, y_rows, **sample_rate_fit_params(est, fs))
        if not np.array_equal(self.estimator_.classes_, self.classes_):
            raise ValueError("estimator must keep the joint classes of y (rows of classes_)")
        if len(speeds) < 2:
            self.speed_estimator_ = None
            return
        sp = (
            FeaturePolynomialClassifier(sample_rate_hz=fs, features=(("f1",),), degree=2)
            if self.speed_estimator is None
            else self.speed_estimator
        )
        y_speed = (
            y_rows[:, [self._speed_column()]] if y_rows.ndim == 2 else y_rows[:, None]
        ).astype(float)
        self.speed_estimator_ = clone(sp).fit(X, y_speed, **sample_rate_fit_params(sp, fs))

    def predict_speed(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Speed class of each trial from the speed stage.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials,)
        """
        return self._speeds(self._fitted_input(X, sample_rate_hz))

    def _speeds(self, X: np.ndarray) -> np.ndarray:
        if self.speed_estimator_ is None:
            return np.full(X.shape[0], self._class_speeds()[0])
        pred = np.asarray(self.speed_estimator_.predict(X), dtype=float)
        return pred.reshape(X.shape[0], -1)[:, 0]

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        s = joint_log_scores(self.estimator_, X)
        v = self._speeds(X)
        cls_speed = self._class_speeds()
        allowed = np.isclose(cls_speed[None, :], v[:, None], rtol=0, atol=1e-9)
        return np.where(allowed, s, -np.inf)


class JointLikelihoodNaiveBayes(TrialClassifier):
    """Naive Bayes with the joint likelihood of an amplitude histogram and a template.

    Beyond the thesis (its proposal at the end of 5.5): the stationary naive Bayes
    likelihood discards the order of the samples. Here each joint class has two
    likelihoods, combined as independent evidence::

        log P(x | C) = log P_hist(x | C) + template_weight * log N(s(x); T_C, sigma^2 I)

    where ``log P_hist`` is :class:`StationaryNaiveBayes`'s summed log-likelihood
    (``histogram``), ``s(x)`` the trial after ``template_signal`` (default: 20 Hz
    low-pass, 200 Hz samples), ``T_C`` the class-mean of ``s`` over the training
    trials of ``C`` (the normalised template) and ``sigma^2`` the pooled
    within-class variance of ``s`` per channel.

    Parameters
    ----------
    histogram : StationaryNaiveBayes, optional
        Default: naive Bayes on velocity at ``sample_rate_hz``.
    template_signal : transformer, optional
        Default: ``SignalTransform("lowpass", sample_rate_hz, downsample=20)``.
    template_weight : float, default=1.0
        Weight of the template log-likelihood (0: plain naive Bayes).
    sample_rate_hz : float, default=4000.0
        Sampling rate of the trials, Hz (also of the defaults). A given
        ``histogram`` or ``template_signal`` built for another rate is refused at
        ``fit``.
    variance_floor : float, default=1e-12
        Lower bound on ``sigma^2``.

    Attributes
    ----------
    sample_rate_hz_ : float
        The rate it was fitted at, Hz.
    histogram_ : StationaryNaiveBayes
    template_signal_ : transformer
    templates_ : ndarray of shape (n_classes, n_channels * n_template_samples)
    variance_ : ndarray of shape (n_channels,)
    classes_, n_channels_, n_timepoints_, n_features_in_
    """

    def __init__(
        self,
        histogram: Any = None,
        template_signal: Any = None,
        template_weight: float = 1.0,
        sample_rate_hz: float = 4000.0,
        variance_floor: float = 1e-12,
    ) -> None:
        self.histogram = histogram
        self.template_signal = template_signal
        self.template_weight = template_weight
        self.sample_rate_hz = sample_rate_hz
        self.variance_floor = variance_floor

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.classifier_tags.poor_score = True
        return tags

    def _rate_parts(self) -> list[tuple[str, Any]]:
        return [
            (k, e)
            for k, e in (("histogram", self.histogram), ("template_signal", self.template_signal))
            if e is not None
        ]

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        w = float(self.template_weight)
        if not np.isfinite(w) or w < 0:
            raise ValueError(f"template_weight must be >= 0, got {self.template_weight!r}")
        fs = float(self.sample_rate_hz)
        hist = (
            StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs)
            if self.histogram is None
            else self.histogram
        )
        ts = (
            SignalTransform("lowpass", sample_rate_hz=fs, downsample=20)
            if self.template_signal is None
            else self.template_signal
        )
        self.histogram_ = clone(hist).fit(X, y_idx, **sample_rate_fit_params(hist, fs))
        self.template_signal_ = clone(ts).fit(X, **sample_rate_fit_params(ts, fs))
        S = self.template_signal_.transform(X)
        n, c, t = S.shape
        k = len(self.classes_)
        counts = np.bincount(y_idx, minlength=k).astype(float)
        means = np.zeros((k, c, t))
        np.add.at(means, y_idx, S)
        means /= counts[:, None, None]
        resid = S - means[y_idx]
        dof = max(n - k, 1)
        var = np.sum(resid**2, axis=(0, 2)) / (dof * t)
        self.variance_ = np.maximum(var, float(self.variance_floor))
        self.templates_ = means.reshape(k, -1)
        self.n_template_samples_ = t

    def template_log_likelihood(self, X: np.ndarray) -> np.ndarray:
        """``log N(s(x); T_C, sigma^2 I)`` of each trial under each class (with constants).

        Parameters
        ----------
        X : ndarray of shape (n_trials, n_channels, n_timepoints)

        Returns
        -------
        ndarray of shape (n_trials, n_classes)
        """
        S = self.template_signal_.transform(X)
        scale = 1.0 / np.sqrt(self.variance_)[None, :, None]
        F = (S * scale).reshape(S.shape[0], -1)
        T = (self.templates_.reshape(len(self.classes_), *S.shape[1:]) * scale).reshape(
            len(self.classes_), -1
        )
        sse = nearest_template_scores(F, T, np.arange(len(self.classes_)), len(self.classes_))
        const = -0.5 * self.n_template_samples_ * np.sum(np.log(2 * np.pi * self.variance_))
        return const - 0.5 * sse

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        h = self.histogram_._joint_scores(X)
        w = float(self.template_weight)
        return h if w == 0 else h + w * self.template_log_likelihood(X)


#: Keys of :func:`chapter5_classifiers`, in the thesis' order, then the additions.
CHAPTER5_KEYS = (
    "template_raw",
    "template_lowpass",
    "template_highpass",
    "template_velocity",
    "template_acceleration",
    "frequency",
    "feature",
    "feature_f4",
    "feature_f5",
    "feature_f345",
    "naive_bayes_raw",
    "naive_bayes_velocity",
    "naive_bayes_acceleration",
    "combined",
    "naive_bayes_velocity_robust",
    "joint_likelihood_nb",
    "minirocket",
)


def chapter5_classifiers(
    sample_rate_hz: float,
    whisker: Mapping[str, Any] | str | None = None,
    notch_hz: float | None = None,
) -> dict[str, BaseEstimator]:
    """Unfitted estimators of chapter 5 (5.3.1-5.3.5) and four additions beyond it.

    Parameters
    ----------
    sample_rate_hz : float
        Sampling rate of the trials, Hz (4 kHz in chapter 5).
    whisker : dict or str, optional
        The Dataset's ``whisker`` attribute; :func:`resonance_hz` of it is the
        notch frequency of 5.3.1 (the tip-pinned first mode where recorded).
    notch_hz : float, optional
        Explicit notch frequency instead (one of ``whisker`` / ``notch_hz``).

    Returns
    -------
    dict of str to estimator
        Keys :data:`CHAPTER5_KEYS`; labels are rows ``[angle_deg, speed_mm_s,
        texture_code]`` (see :data:`TEXTURE_CODES`). Every step is built for
        ``sample_rate_hz`` (after a downsampling step, for the reduced rate) and
        refuses data at another rate (:func:`~vibrissa.classify.check_sample_rate`).
    """
    from vibrissa.classify._rocket import MiniRocketClassifier

    fs = positive("sample_rate_hz", sample_rate_hz)
    if notch_hz is None:
        if whisker is None:
            raise ValueError("give whisker (with natural_frequencies_hz) or notch_hz")
        notch_hz = resonance_hz(whisker)
    f0 = positive("notch_hz", notch_hz)
    lp_down = max(1, int(fs // 200))  # 20 Hz low-pass -> 200 Hz samples
    nb_thesis = dict(
        n_bins=500,
        smoothing_sigma=1.0,
        smoothing_radius_bins=10,
        likelihood_floor=float(np.finfo(float).eps),
        sample_rate_hz=fs,
    )

    def tmpl(kind: str, notch: float | None = None, down: int = 1) -> Pipeline:
        return Pipeline(
            [
                (
                    "signal",
                    SignalTransform(kind, sample_rate_hz=fs, notch_hz=notch, downsample=down),
                ),
                ("template", TimeTemplateClassifier(sample_rate_hz=fs / down, cutoff_hz=None)),
            ]
        )

    def feat(texture: tuple[str, ...], degree: int = 2) -> FeaturePolynomialClassifier:
        return FeaturePolynomialClassifier(
            sample_rate_hz=fs,
            notch_hz=f0,
            features=(("f2",), ("f1",), texture),
            degree=(2, 2, degree),
        )

    return {
        "template_raw": TimeTemplateClassifier(sample_rate_hz=fs, cutoff_hz=None),
        "template_lowpass": tmpl("lowpass", f0, lp_down),
        "template_highpass": tmpl("highpass", f0),
        "template_velocity": tmpl("velocity"),
        "template_acceleration": tmpl("acceleration"),
        "frequency": Pipeline(
            [
                ("signal", SignalTransform("raw", sample_rate_hz=fs, notch_hz=f0)),
                (
                    "template",
                    FrequencyTemplateClassifier(
                        sample_rate_hz=fs, cutoff_hz=None, max_frequency_hz=1000.0
                    ),
                ),
            ]
        ),
        "feature": feat(("f3",)),
        "feature_f4": feat(("f4",)),
        "feature_f5": feat(("f5",)),
        "feature_f345": feat(("f3", "f4", "f5"), degree=4),
        # 5.3.4: "the methodology remains principally the same" as 4.3.5, so the
        # chapter-4 author's settings (docs/methods.md): 500 bins, sigma 1 bin
        # truncated at 10, log(l + eps); raw over rest +/- 2.5 V (the text's range),
        # velocity over +/-0.1 V per sample; acceleration (no code, no range given)
        # over the training data's full range (the text's 4.3.5 reading)
        "naive_bayes_raw": StationaryNaiveBayes(signal="raw", value_range=(0.0, 5.0), **nb_thesis),
        "naive_bayes_velocity": Pipeline(
            [
                ("signal", SignalTransform("causal_velocity", sample_rate_hz=fs)),
                (
                    "naive_bayes",
                    StationaryNaiveBayes(
                        signal="raw", value_range=(-0.1 * fs, 0.1 * fs), **nb_thesis
                    ),
                ),
            ]
        ),
        "naive_bayes_acceleration": Pipeline(
            [
                ("signal", SignalTransform("acceleration", sample_rate_hz=fs)),
                ("naive_bayes", StationaryNaiveBayes(signal="raw", value_range=None, **nb_thesis)),
            ]
        ),
        "combined": SpeedFirstClassifier(
            speed_estimator=FeaturePolynomialClassifier(
                sample_rate_hz=fs, notch_hz=f0, features=(("f1",),), degree=2
            ),
            estimator=StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs),
            speed_column=1,
            sample_rate_hz=fs,
        ),
        "naive_bayes_velocity_robust": StationaryNaiveBayes(
            signal="velocity", sample_rate_hz=fs, value_range="robust"
        ),
        "joint_likelihood_nb": JointLikelihoodNaiveBayes(
            template_signal=SignalTransform("lowpass", sample_rate_hz=fs, downsample=lp_down),
            sample_rate_hz=fs,
        ),
        "minirocket": MiniRocketClassifier(sample_rate_hz=fs),
    }
