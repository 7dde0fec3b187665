"""The fitted classifiers of the framework: "where" (radial distance) and "what" (angle, texture).

A model is a fitted vibrissa classifier (``predict_proba`` over joint label rows
``classes_``) with the sample rate it was fitted at and the stream channels it
reads. :func:`model_windows` turns detector windows (stream rate, every channel)
into the model's input (its rate, its channels); the same function prepares the
training set (:func:`fit_where`, :func:`fit_what`) and the live contacts
(:class:`vibrissa.framework.TactilePipeline`), so the two always agree.

The default estimators are the best of those *measured* in chapters 4 and 5 that
give posteriors (see :func:`default_where_estimator`, :func:`default_what_estimator`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any

import numpy as np
from scipy.signal import firwin, resample_poly
from sklearn.base import clone

from vibrissa._validate import finite, positive
from vibrissa.classify import (
    MiniRocketClassifier,
    StationaryNaiveBayes,
    sample_rate_fit_params,
)

__all__ = [
    "WhatModel",
    "WhereModel",
    "default_what_estimator",
    "default_where_estimator",
    "fit_what",
    "fit_where",
    "model_windows",
]


def _check_fitted(name: str, estimator: Any) -> np.ndarray:
    """The ``classes_`` rows of a fitted classifier with ``predict_proba``."""
    if not callable(getattr(estimator, "predict_proba", None)):
        raise TypeError(f"{name} must have predict_proba, got {type(estimator).__name__}")
    classes = getattr(estimator, "classes_", None)
    if classes is None:
        raise ValueError(f"{name} must be fitted (it has no classes_)")
    c = np.asarray(classes)
    if c.ndim != 2:
        raise ValueError(f"{name}.classes_ must hold joint label rows (2-D), got shape {c.shape}")
    return c


def _column(name: str, value: Any, n_targets: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise TypeError(f"{name} must be an int, got {value!r}")
    if not 0 <= value < n_targets:
        raise ValueError(f"{name} must lie in [0, {n_targets - 1}], got {value!r}")
    return int(value)


def _channels(value: Any) -> tuple[int, ...] | None:
    if value is None:
        return None
    if not isinstance(value, tuple) or not value:
        raise TypeError(f"channels must be a non-empty tuple of ints or None, got {value!r}")
    for c in value:
        if isinstance(c, bool) or not isinstance(c, int | np.integer) or c < 0:
            raise ValueError(f"channels must hold non-negative ints, got {value!r}")
    return value


@dataclass(frozen=True)
class WhereModel:
    """A fitted "where" classifier: radial distance (and speed) of a contact (chapter 4).

    Attributes
    ----------
    estimator : estimator
        Fitted classifier with ``predict_proba`` and ``classes_`` rows.
    sample_rate_hz : float
        The rate it was fitted at, Hz.
    tip_radial_distance_mm : float
        Classes with radial distance ``>=`` this are "tip" contacts (e.g. the
        whisker's length minus 5 mm).
    radial_column : int, default=0
        Column of ``classes_`` holding radial distance, mm.
    speed_column : int or None, default=1
        Column holding speed, mm/s (``None``: the model has no speed).
    channels : tuple of int or None, default=None
        Stream channels it reads (``None``: all).
    """

    estimator: Any
    sample_rate_hz: float
    tip_radial_distance_mm: float
    radial_column: int = 0
    speed_column: int | None = 1
    channels: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        """Check the model, naming the attribute that is wrong."""
        classes = _check_fitted("estimator", self.estimator)
        positive("sample_rate_hz", self.sample_rate_hz)
        finite("tip_radial_distance_mm", self.tip_radial_distance_mm)
        _column("radial_column", self.radial_column, classes.shape[1])
        if self.speed_column is not None:
            _column("speed_column", self.speed_column, classes.shape[1])
        _channels(self.channels)

    @property
    def classes(self) -> np.ndarray:
        """The estimator's joint class rows, as float."""
        return np.asarray(self.estimator.classes_, dtype=float)

    def predict_proba(self, windows: np.ndarray, stream_rate_hz: float) -> np.ndarray:
        """Posterior over :attr:`classes` of detector windows ``(n, n_channels, n_time)``."""
        X = model_windows(windows, stream_rate_hz, self.sample_rate_hz, self.channels)
        return np.asarray(self.estimator.predict_proba(X), dtype=float)


@dataclass(frozen=True)
class WhatModel:
    """A fitted "what" classifier: surface angle and texture of a tip contact (chapter 5).

    Attributes
    ----------
    estimator : estimator
        Fitted classifier with ``predict_proba`` and ``classes_`` rows.
    sample_rate_hz : float
        The rate it was fitted at, Hz.
    angle_column : int, default=0
        Column of ``classes_`` holding the surface angle, degrees.
    texture_column : int, default=2
        Column holding texture codes (:data:`vibrissa.data.schema.TEXTURE_CODES`).
    channels : tuple of int or None, default=None
        Stream channels it reads (``None``: all).
    """

    estimator: Any
    sample_rate_hz: float
    angle_column: int = 0
    texture_column: int = 2
    channels: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        """Check the model, naming the attribute that is wrong."""
        classes = _check_fitted("estimator", self.estimator)
        positive("sample_rate_hz", self.sample_rate_hz)
        _column("angle_column", self.angle_column, classes.shape[1])
        _column("texture_column", self.texture_column, classes.shape[1])
        _channels(self.channels)

    @property
    def classes(self) -> np.ndarray:
        """The estimator's joint class rows, as float."""
        return np.asarray(self.estimator.classes_, dtype=float)

    def surface_classes(self) -> tuple[np.ndarray, np.ndarray]:
        """Distinct ``(angle_deg, texture_code)`` rows and the row of each joint class.

        Returns
        -------
        rows : ndarray of shape (n_surfaces, 2)
        index : ndarray of shape (n_classes,)
            Row of ``rows`` for each of the estimator's classes.
        """
        c = self.classes[:, [self.angle_column, self.texture_column]]
        rows, index = np.unique(c, axis=0, return_inverse=True)
        return rows, np.asarray(index).ravel()

    def predict_proba(self, windows: np.ndarray, stream_rate_hz: float) -> np.ndarray:
        """Posterior over :attr:`classes` of detector windows ``(n, n_channels, n_time)``."""
        X = model_windows(windows, stream_rate_hz, self.sample_rate_hz, self.channels)
        return np.asarray(self.estimator.predict_proba(X), dtype=float)


def _ratio(stream_rate_hz: float, model_rate_hz: float) -> tuple[int, int]:
    """``(up, down)`` with ``model / stream = up / down`` exactly (to 1e-9)."""
    frac = Fraction(model_rate_hz / stream_rate_hz).limit_denominator(10_000)
    if abs(float(frac) * stream_rate_hz - model_rate_hz) > 1e-9 * model_rate_hz:
        raise ValueError(
            f"model_rate_hz / stream_rate_hz ({model_rate_hz:g} / {stream_rate_hz:g}) is not "
            "a ratio of integers up to 10000"
        )
    return frac.numerator, frac.denominator


@lru_cache(maxsize=32)
def _fir(up: int, down: int) -> np.ndarray:
    """The anti-aliasing filter :func:`scipy.signal.resample_poly` designs by default.

    Designed once per ratio (designing it took most of the time of resampling one
    contact); the results are those of ``resample_poly(x, up, down)``.
    """
    max_rate = max(up, down)
    h = firwin(2 * 10 * max_rate + 1, 1.0 / max_rate, window=("kaiser", 5.0))
    h.setflags(write=False)
    return h


def model_windows(
    windows: Any,
    stream_rate_hz: float,
    model_rate_hz: float,
    channels: tuple[int, ...] | None = None,
) -> np.ndarray:
    """Detector windows resampled to a model's rate and cut to its channels.

    Parameters
    ----------
    windows : array-like of shape (n, n_channels, n_time)
        At the stream's rate (e.g. :attr:`DetectedContact.window` stacked).
    stream_rate_hz, model_rate_hz : float
        Rates of the windows and of the model, Hz. Equal rates change nothing;
        otherwise :func:`scipy.signal.resample_poly` with the rational ratio
        ``model / stream``.
    channels : tuple of int or None
        Channels kept, in this order (``None``: all).

    Returns
    -------
    ndarray of shape (n, n_model_channels, n_model_time), float64
    """
    X = np.asarray(windows, dtype=float)
    if X.ndim != 3:
        raise ValueError(f"windows must have shape (n, n_channels, n_time), got {X.shape}")
    fs = positive("stream_rate_hz", stream_rate_hz)
    fm = positive("model_rate_hz", model_rate_hz)
    ch = _channels(channels)
    if ch is not None:
        if max(ch) >= X.shape[1]:
            raise ValueError(f"channels {ch} name a channel beyond the {X.shape[1]} of windows")
        X = X[:, list(ch), :]
    up, down = _ratio(fs, fm)
    if up == down:
        return np.ascontiguousarray(X)
    return np.ascontiguousarray(resample_poly(X, up, down, axis=-1, window=_fir(up, down)))


def _labels(labels: Any, n: int) -> np.ndarray:
    y = np.asarray(labels, dtype=float)
    if y.ndim != 2 or y.shape[0] != n:
        raise ValueError(f"labels must have shape ({n}, n_targets), got {y.shape}")
    if not np.all(np.isfinite(y)):
        raise ValueError("labels contain NaN or infinite values")
    return y


def _fit(
    estimator: Any,
    windows: Any,
    labels: Any,
    stream_rate_hz: float,
    model_rate_hz: float,
    channels: tuple[int, ...] | None,
) -> Any:
    X = model_windows(windows, stream_rate_hz, model_rate_hz, channels)
    y = _labels(labels, X.shape[0])
    est = clone(estimator)
    return est.fit(X, y, **sample_rate_fit_params(est, float(model_rate_hz)))


def fit_where(
    estimator: Any,
    windows: Any,
    labels: Any,
    stream_rate_hz: float,
    model_rate_hz: float,
    tip_radial_distance_mm: float,
    *,
    radial_column: int = 0,
    speed_column: int | None = 1,
    channels: tuple[int, ...] | None = None,
) -> WhereModel:
    """Fit a clone of ``estimator`` on detector windows and wrap it as a :class:`WhereModel`.

    Parameters
    ----------
    estimator : estimator
        Unfitted classifier of joint label rows (e.g. :func:`default_where_estimator`),
        built for ``model_rate_hz``.
    windows : array-like of shape (n, n_channels, n_time)
        Detector windows at the stream's rate (:func:`contact_windows`).
    labels : array-like of shape (n, n_targets)
        Radial distance (mm) in ``radial_column``, speed (mm/s) in ``speed_column``.
    stream_rate_hz, model_rate_hz : float
        Rate of the windows and rate the model is fitted at, Hz.
    tip_radial_distance_mm : float
        See :class:`WhereModel`.
    radial_column, speed_column, channels
        See :class:`WhereModel`.

    Returns
    -------
    WhereModel
    """
    est = _fit(estimator, windows, labels, stream_rate_hz, model_rate_hz, channels)
    return WhereModel(
        est,
        float(model_rate_hz),
        float(tip_radial_distance_mm),
        radial_column,
        speed_column,
        channels,
    )


def fit_what(
    estimator: Any,
    windows: Any,
    labels: Any,
    stream_rate_hz: float,
    model_rate_hz: float,
    *,
    angle_column: int = 0,
    texture_column: int = 2,
    channels: tuple[int, ...] | None = None,
) -> WhatModel:
    """Fit a clone of ``estimator`` on detector windows and wrap it as a :class:`WhatModel`.

    Parameters
    ----------
    estimator : estimator
        Unfitted classifier of joint label rows (e.g. :func:`default_what_estimator`),
        built for ``model_rate_hz``.
    windows : array-like of shape (n, n_channels, n_time)
        Detector windows at the stream's rate.
    labels : array-like of shape (n, n_targets)
        Angle (degrees) in ``angle_column``, texture code in ``texture_column``.
    stream_rate_hz, model_rate_hz : float
        Rate of the windows and rate the model is fitted at, Hz.
    angle_column, texture_column, channels
        See :class:`WhatModel`.

    Returns
    -------
    WhatModel
    """
    est = _fit(estimator, windows, labels, stream_rate_hz, model_rate_hz, channels)
    return WhatModel(est, float(model_rate_hz), angle_column, texture_column, channels)


def default_where_estimator(sample_rate_hz: float) -> StationaryNaiveBayes:
    """The best measured chapter-4 classifier of radial distance: naive Bayes on velocity.

    ``docs/runs/chapter4.json``, key
    ``classifiers.naive_bayes_velocity_robust.radius_mm.std``: 3.32 mm, the smallest
    radial-distance error of the eight chapter-4 classifiers (``template`` 3.68 mm,
    ``naive_bayes_raw`` 3.76 mm, the static beam 17-18 mm; ``docs/methods.md``). It is
    :class:`~vibrissa.classify.StationaryNaiveBayes` with its defaults on the
    whisker velocity (the chapter-4 line-up cuts the +/-325 ms peak window first;
    here the detector's onset window is the input). Its posteriors are nearly
    one-hot (a sum of log-likelihoods over hundreds of samples), so ``p_tip`` is
    close to 0 or 1.

    Parameters
    ----------
    sample_rate_hz : float
        The rate the model will be fitted at, Hz.

    Returns
    -------
    StationaryNaiveBayes
        Unfitted.
    """
    return StationaryNaiveBayes(
        signal="velocity", sample_rate_hz=positive("sample_rate_hz", sample_rate_hz)
    )


def default_what_estimator(sample_rate_hz: float) -> MiniRocketClassifier:
    """The best measured chapter-5 classifier of texture with posteriors: MiniRocket.

    ``docs/runs/chapter5.json``, key ``classifiers.minirocket.kappa.texture``: 0.716,
    the highest texture kappa of the chapter-5 line-up (next ``joint_likelihood_nb``
    0.384, ``naive_bayes_velocity_robust`` 0.373; the thesis' own methods at most
    0.337, ``derived.thesis_methods_texture_kappa_max``), with angle kappa 0.495
    (``classifiers.minirocket.kappa.angle``; ``frequency`` 0.591 is better on angle but
    0.320 on texture). Its logistic head gives calibrated posteriors, which evidence
    accumulation needs (``docs/chapter5.md``: sequential texture kappa 0.99 after 10
    contacts, ``sequential."10"``, with MiniRocket as base).

    Parameters
    ----------
    sample_rate_hz : float
        The rate the model will be fitted at, Hz.

    Returns
    -------
    MiniRocketClassifier
        Unfitted, ``pool`` 8 as in chapter 5 (4 kHz -> 500 Hz), scaled to the rate.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    pool = max(1, int(round(8 * fs / 4000.0)))
    return MiniRocketClassifier(pool=pool, sample_rate_hz=fs)
