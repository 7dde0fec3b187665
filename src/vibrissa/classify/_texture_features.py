"""Chapter-5 contact features f1-f5 and a per-target polynomial regression (thesis 5.3.3).

* ``f1`` peak deflection magnitude, V (eq. 5.2) -> speed;
* ``f2`` slope of the initial deflection ``f1 / t(f1)``, V/s (eq. 5.3) -> angle,
  with ``t(f1)`` the time from contact onset (first sample whose deflection
  reaches ``onset_fraction x f1``) to the peak, since the trials are aligned so
  that the peak itself is at ``t = 0``;
* ``f3`` modulation centroid, Hz: the frequency of the largest DFT magnitude
  between 6 Hz and 1 kHz of the notch-filtered deflection (eq. 5.4; the bins
  below 6 Hz are set to zero as in the thesis);
* ``f4`` modulation energy: that largest magnitude (eq. 5.5);
* ``f5`` total power: the sum of the DFT magnitudes from 6 Hz to 1 kHz (eq. 5.6).

:class:`FeaturePolynomialClassifier` fits, for every target column, a polynomial
of total degree ``degree`` in the features chosen for that column (the thesis:
degree 2 for f1 -> speed, f2 -> angle and each of f3, f4, f5 -> texture; degree 4
for the combined f3-f5 texture model) and snaps the estimate to the nearest
class value. It differs from chapter 4's
:class:`~vibrissa.classify.FeatureRegressionClassifier`, whose two features are
shared by every target, in that each target has its own feature set.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import combinations_with_replacement
from typing import Any

import numpy as np

from vibrissa import signal as vsig
from vibrissa.classify._base import TrialClassifier, target_column

__all__ = [
    "FEATURE_NAMES",
    "FeaturePolynomialClassifier",
    "chapter5_features",
    "modulation_features",
    "polynomial_terms",
]

#: Names of the chapter-5 features, in the column order of :func:`chapter5_features`.
FEATURE_NAMES = ("f1", "f2", "f3", "f4", "f5")


def modulation_features(
    x: np.ndarray,
    sample_rate_hz: float,
    low_hz: float = 6.0,
    high_hz: float = 1000.0,
) -> np.ndarray:
    """Features f3, f4, f5 (eqs. 5.4-5.6) of already filtered signals.

    Parameters
    ----------
    x : ndarray of shape (..., n_timepoints)
        Deflection signals (rest level removed, notch applied), time last.
    sample_rate_hz : float
        Sampling rate, Hz.
    low_hz, high_hz : float
        Band kept, Hz (thesis: bins below 6 Hz zeroed, up to 1 kHz).

    Returns
    -------
    ndarray of shape (..., 3)
        ``f3`` (Hz), ``f4`` and ``f5`` (units of ``x``, unnormalised DFT sums).
    """
    spec = vsig.magnitude_spectrum(x)
    freqs = vsig.spectrum_frequencies(np.shape(x)[-1], sample_rate_hz)
    band = (freqs >= low_hz) & (freqs <= high_hz)
    if not band.any():
        raise ValueError(
            f"no DFT bin between {low_hz} and {high_hz} Hz for {np.shape(x)[-1]} samples "
            f"(n_features = {np.shape(x)[-1]} per channel) "
            f"at {sample_rate_hz} Hz"
        )
    spec = np.where(band, spec, 0.0)
    k = np.argmax(spec, axis=-1)
    f4 = np.take_along_axis(spec, k[..., None], axis=-1)[..., 0]
    return np.stack([freqs[k], f4, spec.sum(axis=-1)], axis=-1)


def chapter5_features(
    X: np.ndarray,
    sample_rate_hz: float,
    notch_hz: float | None,
    notch_quality: float = 5.0,
    channel: int = 0,
    rest_v: float | None = 2.5,
    onset_fraction: float = 0.1,
) -> np.ndarray:
    """The five features of thesis 5.3.3 for each trial.

    Parameters
    ----------
    X : ndarray of shape (n_trials, n_channels, n_timepoints)
        Hall-sensor trials, V, aligned to the peak deflection.
    sample_rate_hz : float
        Sampling rate, Hz (4 kHz in chapter 5).
    notch_hz : float or None
        Whisker resonance removed before f3-f5, Hz (``None``: no notch).
    notch_quality : float
        Quality factor of the notch.
    channel : int
        Channel carrying the deflection (0: ``x``).
    rest_v : float or None
        Sensor rest output, V; ``None`` subtracts each trial's mean instead.
    onset_fraction : float
        Contact onset for f2: first sample reaching this fraction of f1.

    Returns
    -------
    ndarray of shape (n_trials, 5)
        Columns ``f1`` (V), ``f2`` (V/s), ``f3`` (Hz), ``f4``, ``f5``.
    """
    if not 0.0 < float(onset_fraction) < 1.0:
        raise ValueError(f"onset_fraction must lie in (0, 1), got {onset_fraction!r}")
    x = np.asarray(X, dtype=float)[:, channel]
    x = x - (x.mean(axis=-1, keepdims=True) if rest_v is None else float(rest_v))
    d = np.abs(x)
    peak = np.argmax(d, axis=-1)
    f1 = d[np.arange(d.shape[0]), peak]
    idx = np.arange(d.shape[-1])
    reach = (d >= onset_fraction * f1[:, None]) & (idx[None, :] <= peak[:, None])
    onset = np.argmax(reach, axis=-1)
    rise_s = np.maximum(peak - onset, 1) / float(sample_rate_hz)
    f2 = f1 / rise_s
    if notch_hz is not None:
        x = vsig.notch(x, notch_hz, sample_rate_hz, quality=notch_quality)
    mod = modulation_features(x, sample_rate_hz)
    return np.column_stack([f1, f2, mod])


def polynomial_terms(n_variables: int, degree: int) -> np.ndarray:
    """Exponents of every monomial of total degree ``<= degree`` in ``n_variables``.

    Parameters
    ----------
    n_variables, degree : int

    Returns
    -------
    ndarray of shape (n_terms, n_variables)
        Row ``i`` holds the exponent of each variable in term ``i``; the first row
        is the constant term.
    """
    rows = []
    for t in range(degree + 1):
        for combo in combinations_with_replacement(range(n_variables), t):
            e = np.zeros(n_variables, dtype=int)
            for v in combo:
                e[v] += 1
            rows.append(e)
    return np.array(rows, dtype=int).reshape(-1, n_variables)


def _check_features(features: Any) -> tuple[tuple[str, ...], ...]:
    if isinstance(features, str) or not isinstance(features, Sequence) or not features:
        raise ValueError(f"features must be a sequence of feature-name tuples, got {features!r}")
    out = []
    for group in features:
        g = (group,) if isinstance(group, str) else tuple(group)
        if not g or any(f not in FEATURE_NAMES for f in g):
            raise ValueError(
                f"each target's features must be a non-empty subset of {FEATURE_NAMES}, got "
                f"{group!r}"
            )
        out.append(g)
    return tuple(out)


class FeaturePolynomialClassifier(TrialClassifier):
    """Per-target polynomial regression on the chapter-5 features (thesis 5.3.3).

    For target column ``k`` of ``y`` (angle, speed, texture code) a polynomial of
    total degree ``degree[k]`` in the features ``features[k]`` is fitted by linear
    least squares (the thesis' ``polyfitn``); the estimate is snapped to the
    nearest class value of that column (the thesis rounds to the nearest integer).
    The winning joint class maximises ``-sum_k z_k^2 / 2`` with ``z_k`` the
    estimate's distance to the class value in units of the training residual of
    target ``k``; on a full grid of classes this is each target rounded
    separately.

    Parameters
    ----------
    sample_rate_hz : float, default=4000.0
        Sampling rate, Hz.
    notch_hz : float or None, default=13.0
        Whisker resonance notched out before f3-f5, Hz (the simulated whisker's
        first mode; thesis 30 Hz for its whisker).
    features : sequence of tuples of str, default=(("f2",), ("f1",), ("f3",))
        Features of each target column, in the order of ``y``'s columns (the
        chapter-5 order is angle, speed, texture).
    degree : int or sequence of int, default=2
        Total polynomial degree, one for all targets or one per target.
    notch_quality : float, default=5.0
        Quality factor of the notch.
    channel : int, default=0
        Channel carrying the deflection.
    rest_v : float or None, default=2.5
        Sensor rest output, V.
    onset_fraction : float, default=0.1
        Contact onset for f2 (fraction of the peak).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes, n_targets) or (n_classes,)
    feature_mean_, feature_scale_ : ndarray of shape (5,)
        Standardisation of f1-f5 before the polynomials (conditioning only).
    terms_ : list of ndarray
        Exponents of each target's polynomial.
    coef_ : list of ndarray
        Least-squares coefficients of each target.
    residual_std_ : ndarray of shape (n_targets,)
        RMS training residual per target, floored at half the smallest gap between
        its class values.
    n_channels_, n_timepoints_, n_features_in_ : int
    """

    def __init__(
        self,
        sample_rate_hz: float = 4000.0,
        notch_hz: float | None = 13.0,
        features: Sequence[Sequence[str]] = (("f2",), ("f1",), ("f3",)),
        degree: int | Sequence[int] = 2,
        notch_quality: float = 5.0,
        channel: int = 0,
        rest_v: float | None = 2.5,
        onset_fraction: float = 0.1,
    ) -> None:
        self.sample_rate_hz = sample_rate_hz
        self.notch_hz = notch_hz
        self.features = features
        self.degree = degree
        self.notch_quality = notch_quality
        self.channel = channel
        self.rest_v = rest_v
        self.onset_fraction = onset_fraction

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.classifier_tags.poor_score = True
        return tags

    def _all_features(self, X: np.ndarray) -> np.ndarray:
        if isinstance(self.channel, bool) or not 0 <= int(self.channel) < X.shape[1]:
            raise ValueError(f"channel must lie in [0, {X.shape[1] - 1}], got {self.channel!r}")
        return chapter5_features(
            X,
            self.sample_rate_hz,
            self.notch_hz,
            self.notch_quality,
            int(self.channel),
            self.rest_v,
            self.onset_fraction,
        )

    def _design(self, F: np.ndarray, k: int) -> np.ndarray:
        cols = [FEATURE_NAMES.index(f) for f in self.feature_groups_[k]]
        z = (F[:, cols] - self.feature_mean_[cols]) / self.feature_scale_[cols]
        return np.prod(z[:, None, :] ** self.terms_[k][None, :, :], axis=2)

    def _class_values(self) -> np.ndarray:
        cv = self.classes_ if self.classes_.ndim == 2 else self.classes_[:, None]
        return np.column_stack([target_column(cv, k, "y") for k in range(cv.shape[1])])

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        groups = _check_features(self.features)
        cv = self._class_values()
        if cv.shape[1] != len(groups):
            raise ValueError(
                f"features has {len(groups)} target groups but y has {cv.shape[1]} columns"
            )
        deg = self.degree
        degs = [deg] * len(groups) if isinstance(deg, int | np.integer) else list(deg)
        if len(degs) != len(groups) or any(
            isinstance(d, bool) or not isinstance(d, int | np.integer) or d < 0 for d in degs
        ):
            raise ValueError(
                f"degree must be a non-negative integer or one per target, got {deg!r}"
            )
        self.feature_groups_ = groups
        F = self._all_features(X)
        scale = F.std(axis=0)
        self.feature_mean_ = F.mean(axis=0)
        self.feature_scale_ = np.where(scale > 0, scale, 1.0)
        self.terms_ = [polynomial_terms(len(g), int(d)) for g, d in zip(groups, degs, strict=True)]
        Y = cv[y_idx]
        self.coef_, rms = [], []
        for k in range(len(groups)):
            A = self._design(F, k)
            c, *_ = np.linalg.lstsq(A, Y[:, k], rcond=None)
            self.coef_.append(c)
            rms.append(np.sqrt(np.mean((Y[:, k] - A @ c) ** 2)))
        floors = [
            0.5 * np.min(np.diff(v)) if len(v) > 1 else 0.5
            for v in (np.unique(cv[:, k]) for k in range(cv.shape[1]))
        ]
        self.residual_std_ = np.maximum(np.asarray(rms), floors)

    def _estimates(self, X: np.ndarray) -> np.ndarray:
        F = self._all_features(X)
        return np.column_stack([self._design(F, k) @ self.coef_[k] for k in range(len(self.coef_))])

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        est = self._estimates(X)
        cv = self._class_values()
        z = (est[:, None, :] - cv[None, :, :]) / self.residual_std_[None, None, :]
        return -0.5 * np.sum(z * z, axis=2)

    def predict_targets(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Continuous regression estimates of each target before snapping to a class.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_targets)
        """
        return self._estimates(self._fitted_input(X, sample_rate_hz))
