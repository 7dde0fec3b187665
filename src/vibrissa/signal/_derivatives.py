"""Gaussian-smoothed time derivatives along the last axis.

The stationary naive Bayes classifier of the thesis works on whisker velocity,
obtained "by taking their numerical derivative and Gaussian smoothing to reduce
noise" (4.3.5). Here the two steps are done at once by convolving with the
derivative of a Gaussian (:func:`scipy.ndimage.gaussian_filter1d` with
``order=1`` or ``order=2``), which is the exact derivative of the
Gaussian-smoothed signal.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import correlate1d

from vibrissa._validate import positive

__all__ = ["DEFAULT_SIGMA_SAMPLES", "acceleration", "smooth", "velocity"]

#: Smoothing width used when neither ``sigma_samples`` nor ``sigma_s`` is given.
DEFAULT_SIGMA_SAMPLES = 3.0


def _sigma_samples(
    sigma_samples: float | None, sigma_s: float | None, sample_rate_hz: float
) -> float:
    if sigma_s is not None and sigma_samples is not None:
        raise ValueError("give either sigma_samples or sigma_s, not both")
    if sigma_s is not None:
        return positive("sigma_s", sigma_s) * sample_rate_hz
    if sigma_samples is None:
        return DEFAULT_SIGMA_SAMPLES
    return positive("sigma_samples", sigma_samples)


def _gauss(
    x: np.ndarray,
    order: int,
    sample_rate_hz: float,
    sigma_samples: float | None,
    sigma_s: float | None,
) -> np.ndarray:
    fs = positive("sample_rate_hz", sample_rate_hz)
    sig = _sigma_samples(sigma_samples, sigma_s, fs)
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        raise ValueError("x must have at least one (time) axis, got a scalar")
    out = correlate1d(arr, _kernel(sig, order), axis=-1, mode="nearest")
    return out * fs**order


def _kernel(sigma: float, order: int) -> np.ndarray:
    """Sampled Gaussian (derivative) kernel for ``correlate1d``, moment-normalised."""
    radius = max(1, int(np.ceil(4.0 * sigma)))
    j = np.arange(-radius, radius + 1, dtype=float)
    g = np.exp(-0.5 * (j / sigma) ** 2)
    if order == 0:
        return g / g.sum()
    if order == 1:  # sum k = 0, sum k j = 1: exact on straight lines
        return j * g / np.sum(j * j * g)
    m2 = np.sum(j * j * g) / g.sum()  # order 2: sum k = 0, sum k j^2 = 2
    k = (j * j - m2) * g
    return 2.0 * k / np.sum(k * j * j)


def smooth(
    x: np.ndarray,
    sample_rate_hz: float = 1.0,
    sigma_samples: float | None = None,
    sigma_s: float | None = None,
) -> np.ndarray:
    """Gaussian smoothing along the last axis.

    Parameters
    ----------
    x
        Signal(s), time last.
    sample_rate_hz
        Sampling rate, Hz (only used to convert ``sigma_s``).
    sigma_samples, sigma_s
        Standard deviation of the Gaussian kernel in samples, or in seconds;
        give at most one (default: 3 samples).

    Returns
    -------
    numpy.ndarray
        Smoothed signal, same shape and units as ``x``. Edges use ``mode="nearest"``.
    """
    return _gauss(x, 0, sample_rate_hz, sigma_samples, sigma_s)


def velocity(
    x: np.ndarray,
    sample_rate_hz: float,
    sigma_samples: float | None = None,
    sigma_s: float | None = None,
) -> np.ndarray:
    """Gaussian-smoothed first derivative along the last axis (thesis 4.3.5).

    Parameters
    ----------
    x
        Signal(s), time last, e.g. Hall-sensor volts.
    sample_rate_hz
        Sampling rate, Hz; the result is per second (V/s for volts).
    sigma_samples
        Standard deviation of the smoothing Gaussian in samples. When neither
        this nor ``sigma_s`` is given, 3 samples (3 ms at 1 kHz).
    sigma_s
        The same in seconds (converted with ``sample_rate_hz``); give at most
        one of the two.

    Returns
    -------
    numpy.ndarray
        ``d/dt`` of the Gaussian-smoothed signal, same shape as ``x``, units of
        ``x`` per second.
    """
    return _gauss(x, 1, sample_rate_hz, sigma_samples, sigma_s)


def acceleration(
    x: np.ndarray,
    sample_rate_hz: float,
    sigma_samples: float | None = None,
    sigma_s: float | None = None,
) -> np.ndarray:
    """Gaussian-smoothed second derivative along the last axis.

    Parameters
    ----------
    x
        Signal(s), time last.
    sample_rate_hz
        Sampling rate, Hz; the result is per second squared.
    sigma_samples, sigma_s
        Standard deviation of the smoothing Gaussian in samples (default 3) or
        seconds, as for :func:`velocity`.

    Returns
    -------
    numpy.ndarray
        ``d^2/dt^2`` of the Gaussian-smoothed signal, same shape as ``x``.
    """
    return _gauss(x, 2, sample_rate_hz, sigma_samples, sigma_s)
