"""Causal (one-pass) preprocessing and onset/peak windows, as the thesis author's code ran it.

The thesis' chapter-4 analysis filtered each whole recording *causally* (MATLAB
``filter``) and only then cut a fixed window starting 100 samples before the
deflection first exceeded 0.1 V (see ``docs/methods.md``). The zero-phase filters
of :mod:`vibrissa.signal._filters` keep a trial aligned to its peak; these keep the
author's delays, so that a thesis preset sees the same signal the thesis' numbers
came from.
"""

from __future__ import annotations

import numpy as np
from scipy import signal as _sig

from vibrissa._validate import finite, positive

__all__ = [
    "causal_gaussian_kernel",
    "causal_gaussian_velocity",
    "causal_lowpass",
    "cut_windows",
    "onset_index",
    "peak_index",
]


def causal_gaussian_kernel(sigma_samples: float = 15.0, half_width_samples: int = 50) -> np.ndarray:
    """Normalised Gaussian FIR taps ``exp(-k^2 / (2 sigma^2))``, ``k = -h..h``, summing to 1.

    Parameters
    ----------
    sigma_samples : float
        Standard deviation, samples (the author's code: 15).
    half_width_samples : int
        ``h``: the kernel has ``2 h + 1`` taps (the author's code: 50, i.e. 101 taps).

    Returns
    -------
    numpy.ndarray of shape (2 h + 1,)
    """
    s = positive("sigma_samples", sigma_samples)
    h = half_width_samples
    if isinstance(h, bool) or not isinstance(h, int | np.integer) or h < 0:
        raise ValueError(f"half_width_samples must be a non-negative integer, got {h!r}")
    k = np.arange(-int(h), int(h) + 1, dtype=float)
    g = np.exp(-(k * k) / (2.0 * s * s))
    return g / g.sum()


def causal_gaussian_velocity(
    x: np.ndarray,
    sample_rate_hz: float,
    sigma_samples: float = 15.0,
    half_width_samples: int = 50,
) -> np.ndarray:
    """Velocity as the thesis author computed it: first difference, then a causal Gaussian FIR.

    ``v[0] = x[1] - x[0]`` (the first difference repeated, as the author's
    ``[d(1); d]``), ``v[n] = x[n] - x[n-1]``, filtered with
    :func:`causal_gaussian_kernel` by a one-pass FIR (initial state zero), times
    ``sample_rate_hz`` so the result is in units per second. The filter delays the
    signal by ``half_width_samples``.

    Parameters
    ----------
    x : numpy.ndarray
        Signal(s), any shape, time last (V).
    sample_rate_hz : float
        Sampling rate, Hz.
    sigma_samples, half_width_samples
        See :func:`causal_gaussian_kernel`.

    Returns
    -------
    numpy.ndarray
        Same shape as ``x``, V/s.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] < 2:
        raise ValueError("x needs at least 2 samples along its last (time) axis")
    d = np.diff(arr, axis=-1)
    d = np.concatenate([d[..., :1], d], axis=-1)
    taps = causal_gaussian_kernel(sigma_samples, half_width_samples)
    return _sig.lfilter(taps, [1.0], d, axis=-1) * fs


def causal_lowpass(
    x: np.ndarray, cutoff_hz: float, sample_rate_hz: float, order: int = 10
) -> np.ndarray:
    """One-pass (causal) Butterworth low-pass, in second-order sections, initial state zero.

    The author's template classifier used MATLAB ``butter(10, 20/(fs/2))`` and
    ``filter`` in transfer-function form; second-order sections give the same
    filter without the transfer function's rounding at order 10 and a low cut-off.

    Parameters
    ----------
    x : numpy.ndarray
        Signal(s), time last.
    cutoff_hz : float
        -3 dB cut-off, Hz (below Nyquist).
    sample_rate_hz : float
        Sampling rate, Hz.
    order : int
        Butterworth order.

    Returns
    -------
    numpy.ndarray
        Same shape as ``x``.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    c = positive("cutoff_hz", cutoff_hz)
    if c >= fs / 2:
        raise ValueError(f"cutoff_hz ({c} Hz) must be below the Nyquist frequency ({fs / 2} Hz)")
    if isinstance(order, bool) or not isinstance(order, int | np.integer) or order < 1:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    sos = _sig.butter(int(order), c, btype="lowpass", fs=fs, output="sos")
    return _sig.sosfilt(sos, np.asarray(x, dtype=float), axis=-1)


def _deviation(x: np.ndarray, rest_v: float) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] == 0:
        raise ValueError("x must have a non-empty (time) last axis")
    return arr - finite("rest_v", rest_v)


def onset_index(x: np.ndarray, threshold_v: float = 0.1, rest_v: float = 2.5) -> np.ndarray:
    """First sample at which ``x - rest_v`` exceeds ``threshold_v`` (``-1`` where it never does).

    Parameters
    ----------
    x : numpy.ndarray
        Signal(s) of one channel, V, time last.
    threshold_v : float
        Onset threshold above rest, V (the author's code: 0.1 V).
    rest_v : float
        Sensor output at rest, V.

    Returns
    -------
    numpy.ndarray of int, shape ``x.shape[:-1]``
    """
    above = (_deviation(x, rest_v)) > finite("threshold_v", threshold_v)
    first = np.argmax(above, axis=-1)
    return np.where(above.any(axis=-1), first, -1)


def peak_index(x: np.ndarray, rest_v: float = 2.5) -> np.ndarray:
    """Sample of the largest deflection ``|x - rest_v|`` (first one on ties).

    Parameters
    ----------
    x : numpy.ndarray
        Signal(s) of one channel, V, time last.
    rest_v : float
        Sensor output at rest, V.

    Returns
    -------
    numpy.ndarray of int, shape ``x.shape[:-1]``
    """
    return np.argmax(np.abs(_deviation(x, rest_v)), axis=-1)


def cut_windows(X: np.ndarray, starts: np.ndarray, n_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Cut ``n_samples`` from each trial starting at its own ``starts[i]``.

    Samples before the start or past the end of a recording repeat its first or
    last sample (a recording at rest before contact reads its rest level).

    Parameters
    ----------
    X : numpy.ndarray of shape (n_trials, n_channels, n_timepoints)
    starts : array-like of int, shape (n_trials,)
        First sample of each window (may be negative or run past the end).
    n_samples : int
        Window length.

    Returns
    -------
    windows : numpy.ndarray of shape (n_trials, n_channels, n_samples)
    n_padded : numpy.ndarray of int, shape (n_trials,)
        Samples of each window that lay outside its recording.
    """
    arr = np.asarray(X, dtype=float)
    if arr.ndim != 3:
        raise ValueError(f"X must have shape (n_trials, n_channels, n_timepoints), got {arr.shape}")
    if isinstance(n_samples, bool) or not isinstance(n_samples, int | np.integer) or n_samples < 1:
        raise ValueError(f"n_samples must be a positive integer, got {n_samples!r}")
    s = np.asarray(starts, dtype=np.int64).reshape(-1)
    if s.shape[0] != arr.shape[0]:
        raise ValueError(f"starts has {s.shape[0]} entries for {arr.shape[0]} trials")
    n_t = arr.shape[2]
    idx = s[:, None] + np.arange(int(n_samples))[None, :]
    outside = (idx < 0) | (idx >= n_t)
    idx = np.clip(idx, 0, n_t - 1)
    win = np.take_along_axis(arr, idx[:, None, :], axis=2)
    return win, outside.sum(axis=1)
