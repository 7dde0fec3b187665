"""Feature-based classification: f1 peak magnitude, f2 duration, polynomial regression (4.3.4)."""

from __future__ import annotations

from typing import Literal

import numpy as np

from vibrissa import signal as vsig
from vibrissa.classify._base import TrialClassifier, target_column

__all__ = [
    "FeatureRegressionClassifier",
    "contact_features",
    "moving_average_shrinking",
    "polynomial_powers",
]


def contact_features(
    X: np.ndarray,
    sample_rate_hz: float,
    threshold_v: float = 0.05,
    channel: int = 0,
    rest_v: float | None = 2.5,
    duration_mode: Literal["first", "peak"] = "first",
) -> np.ndarray:
    """The two features of thesis 4.3.4 for each trial.

    Parameters
    ----------
    X : ndarray of shape (n_trials, n_channels, n_timepoints)
        Hall-sensor trials, V.
    sample_rate_hz : float
        Sampling rate, Hz.
    threshold_v : float
        Threshold ``gamma`` of eqs. 4.6-4.7, V.
    channel : int
        Channel carrying the deflection (0: ``x``).
    rest_v : float or None
        Sensor rest output, V (2.5 V).
    duration_mode : {"first", "peak"}
        See :func:`vibrissa.signal.contact_duration`.

    Returns
    -------
    ndarray of shape (n_trials, 2)
        Columns ``f1`` (peak deflection magnitude, V, eq. 4.5) and ``f2``
        (deflection duration, s, eq. 4.8).
    """
    x = X[:, channel]
    f1 = vsig.peak_magnitude(x, rest_v=rest_v)
    f2 = vsig.contact_duration(
        x, sample_rate_hz, threshold_v=threshold_v, rest_v=rest_v, mode=duration_mode
    )
    return np.column_stack([f1, f2])


def moving_average_shrinking(x: np.ndarray, span: int) -> np.ndarray:
    """Moving average of odd ``span`` whose window shrinks to fit at the ends.

    MATLAB's ``smooth(x, span)``: ``y[i]`` is the mean of ``x[i-k:i+k+1]`` with
    ``k = min((span - 1) // 2, i, n - 1 - i)`` (an even span is reduced by one).

    Parameters
    ----------
    x : ndarray of shape (n,)
    span : int

    Returns
    -------
    ndarray of shape (n,)
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    half = (int(span) - 1) // 2
    i = np.arange(n)
    k = np.minimum(half, np.minimum(i, n - 1 - i))
    c = np.concatenate([[0.0], np.cumsum(x)])
    return (c[i + k + 1] - c[i - k]) / (2 * k + 1)


def polynomial_powers(degree: int) -> np.ndarray:
    """Exponents ``(i, j)`` of the terms ``f1^i f2^j`` with ``i + j <= degree``.

    Parameters
    ----------
    degree : int

    Returns
    -------
    ndarray of shape (n_terms, 2)
        ``(degree + 1)(degree + 2) / 2`` rows, ordered by total degree.
    """
    return np.array(
        [(t - j, j) for t in range(degree + 1) for j in range(t + 1)], dtype=int
    ).reshape(-1, 2)


class FeatureRegressionClassifier(TrialClassifier):
    """Two hand-made features and a polynomial regression per target (thesis 4.3.4).

    ``f1`` is the peak deflection magnitude (eq. 4.5), which codes radial distance
    at a given speed; ``f2`` the time the deflection stays above a threshold
    (eqs. 4.6-4.8), which codes speed. For each target column (e.g. radial
    distance and speed) a full two-variable polynomial of total degree ``degree``
    in ``(f1, f2)`` is fitted by linear least squares (the thesis used
    ``polyfitn`` with degree 5). A prediction is then snapped to a class: the
    thesis rounds each estimate to the nearest integer; here the winning joint
    class is the one nearest to the estimates in residual-standardised distance,
    which on a full grid of labels is each target rounded to its nearest class
    value.

    Parameters
    ----------
    sample_rate_hz : float, default=1000.0
        Sampling rate, Hz.
    threshold_v : float, default=0.05
        Duration threshold ``gamma``, V (thesis: 0.05 V).
    degree : int, default=5
        Total degree of the polynomial.
    channel : int, default=0
        Channel carrying the deflection.
    rest_v : float or None, default=2.5
        Sensor rest output subtracted before the features, V.
    duration_mode : {"first", "peak"}, default="first"
        ``"first"``: eqs. 4.6-4.7 literally; ``"peak"``: the supra-threshold run
        containing the peak (what the author's code measured).
    duration_smoothing_span : int, default=1
        Training only: moving average of ``f2`` over this many neighbouring
        training trials, ordered by label (last column of ``y`` slowest, e.g.
        speed, then radial distance), with the span shrinking at the ends as
        MATLAB's ``smooth``. The author's code smoothed its training widths with
        ``smooth`` (span 5) in exactly that order; 1 disables it.
    min_duration_s : float or None, default=None
        Training only, after the smoothing: an ``f2`` below this is replaced by the
        previous trial's (in the same order). The author's code did this below
        350 samples (0.35 s at 1 kHz); ``None`` disables it.

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,) or (n_classes, n_targets)
    powers_ : ndarray of shape (n_terms, 2)
        Exponents of ``f1`` and ``f2`` of each term.
    feature_mean_, feature_scale_ : ndarray of shape (2,)
        Standardisation of ``(f1, f2)`` before the polynomial (conditioning only;
        the fitted function is the same polynomial).
    coef_ : ndarray of shape (n_targets, n_terms)
        Least-squares coefficients on the standardised features.
    residual_std_ : ndarray of shape (n_targets,)
        RMS training residual of each target, floored at half the smallest gap
        between its class values; scales the class scores.
    n_channels_, n_timepoints_, n_features_in_ : int

    Notes
    -----
    ``predict_proba`` treats the regression residuals as independent Gaussians
    with standard deviations ``residual_std_``.
    """

    def __init__(
        self,
        sample_rate_hz: float = 1000.0,
        threshold_v: float = 0.05,
        degree: int = 5,
        channel: int = 0,
        rest_v: float | None = 2.5,
        duration_mode: Literal["first", "peak"] = "first",
        duration_smoothing_span: int = 1,
        min_duration_s: float | None = None,
    ) -> None:
        self.sample_rate_hz = sample_rate_hz
        self.threshold_v = threshold_v
        self.degree = degree
        self.channel = channel
        self.rest_v = rest_v
        self.duration_mode = duration_mode
        self.duration_smoothing_span = duration_smoothing_span
        self.min_duration_s = min_duration_s

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        # Built for whisker time series: no accuracy promise on generic tabular data.
        tags.classifier_tags.poor_score = True
        return tags

    def _features(self, X: np.ndarray) -> np.ndarray:
        if isinstance(self.channel, bool) or not 0 <= int(self.channel) < X.shape[1]:
            raise ValueError(f"channel must lie in [0, {X.shape[1] - 1}], got {self.channel!r}")
        return contact_features(
            X,
            self.sample_rate_hz,
            threshold_v=self.threshold_v,
            channel=int(self.channel),
            rest_v=self.rest_v,
            duration_mode=self.duration_mode,
        )

    def _design(self, X: np.ndarray, features: np.ndarray | None = None) -> np.ndarray:
        f = self._features(X) if features is None else features
        z = (f - self.feature_mean_) / self.feature_scale_
        return np.prod(z[:, None, :] ** self.powers_[None, :, :], axis=2)

    def _training_durations(self, f2: np.ndarray, labels: np.ndarray) -> np.ndarray:
        """The author's training-time treatment of ``f2`` (smoothing, floor), in label order."""
        span = self.duration_smoothing_span
        if isinstance(span, bool) or not isinstance(span, int | np.integer) or span < 1:
            raise ValueError(f"duration_smoothing_span must be a positive integer, got {span!r}")
        floor = self.min_duration_s
        if floor is not None and not (np.isfinite(floor) and floor >= 0):
            raise ValueError(f"min_duration_s must be >= 0 or None, got {floor!r}")
        if span == 1 and floor is None:
            return f2
        order = np.lexsort(labels.T) if labels.ndim == 2 else np.argsort(labels, kind="stable")
        g = moving_average_shrinking(f2[order], int(span))
        if floor is not None:
            for i in range(1, g.size):
                if g[i] < floor:
                    g[i] = g[i - 1]
        out = np.empty_like(f2)
        out[order] = g
        return out

    def _class_values(self) -> np.ndarray:
        cv = self.classes_ if self.classes_.ndim == 2 else self.classes_[:, None]
        return np.column_stack([target_column(cv, k, "y") for k in range(cv.shape[1])])

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        deg = self.degree
        if isinstance(deg, bool) or not isinstance(deg, int | np.integer) or deg < 0:
            raise ValueError(f"degree must be a non-negative integer, got {deg!r}")
        cv = self._class_values()
        f = self._features(X)
        f[:, 1] = self._training_durations(f[:, 1], cv[y_idx])
        scale = f.std(axis=0)
        self.feature_mean_ = f.mean(axis=0)
        self.feature_scale_ = np.where(scale > 0, scale, 1.0)
        self.powers_ = polynomial_powers(int(deg))
        A = self._design(X, f)
        Y = cv[y_idx]
        coef, *_ = np.linalg.lstsq(A, Y, rcond=None)
        self.coef_ = coef.T
        rms = np.sqrt(np.mean((Y - A @ coef) ** 2, axis=0))
        floors = np.array(
            [
                0.5 * np.min(np.diff(v)) if len(v) > 1 else 0.5
                for v in (np.unique(cv[:, k]) for k in range(cv.shape[1]))
            ]
        )
        self.residual_std_ = np.maximum(rms, floors)

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        est = self._design(X) @ self.coef_.T  # (n_trials, n_targets)
        cv = self._class_values()
        scores = np.zeros((est.shape[0], cv.shape[0]))
        for k in range(cv.shape[1]):
            z = (est[:, k, None] - cv[None, :, k]) / self.residual_std_[k]
            scores -= 0.5 * z * z
        return scores

    def predict_targets(self, X: np.ndarray, sample_rate_hz: float | None = None) -> np.ndarray:
        """Continuous regression estimates before snapping to a class.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_targets)
            Polynomial estimates of each target (e.g. mm and mm/s).
        """
        return self._design(self._fitted_input(X, sample_rate_hz)) @ self.coef_.T
