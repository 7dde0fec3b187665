"""Zero-phase IIR filters along the last (time) axis.

Every filter is designed with :func:`scipy.signal.butter` / :func:`scipy.signal.iirnotch`
and applied forward and backward (zero phase), so filtered trials stay aligned to
their peak deflection (thesis 4.2). Butterworth filters use second-order sections
(``output="sos"`` + :func:`scipy.signal.sosfiltfilt`), which stay numerically stable
at high order and low normalised cut-off where a ``(b, a)`` design does not.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from scipy import signal as _sig

from vibrissa._validate import positive

__all__ = ["bandpass", "highpass", "lowpass", "notch"]


def _check_order(order: int) -> int:
    if isinstance(order, bool) or not isinstance(order, int | np.integer) or order < 1:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    return int(order)


def _check_cutoff(name: str, cutoff_hz: float, sample_rate_hz: float) -> float:
    c = positive(name, cutoff_hz)
    nyquist = sample_rate_hz / 2.0
    if c >= nyquist:
        raise ValueError(
            f"{name} ({c} Hz) must be below the Nyquist frequency ({nyquist} Hz) "
            f"of sample_rate_hz={sample_rate_hz}"
        )
    return c


def _as_signal(x: np.ndarray) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        raise ValueError("x must have at least one (time) axis, got a scalar")
    return arr


def _sosfiltfilt(sos: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``sosfiltfilt`` along the last axis with the pad length clamped to short signals."""
    n = x.shape[-1]
    if n < 2:
        return x.copy()
    ntaps = 2 * len(sos) + 1
    ntaps -= min(int((sos[:, 2] == 0).sum()), int((sos[:, 5] == 0).sum()))
    padlen = min(3 * ntaps, n - 1)
    return _sig.sosfiltfilt(sos, x, axis=-1, padlen=padlen)


def _butter(
    x: np.ndarray,
    cutoff: float | tuple[float, float],
    btype: Literal["lowpass", "highpass", "bandpass"],
    sample_rate_hz: float,
    order: int,
) -> np.ndarray:
    sos = _sig.butter(order, cutoff, btype=btype, fs=sample_rate_hz, output="sos")
    return _sosfiltfilt(sos, _as_signal(x))


def lowpass(x: np.ndarray, cutoff_hz: float, sample_rate_hz: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass filter along the last axis.

    The template classifier of the thesis low-pass filters the raw Hall-sensor
    signal before comparing it with templates (4.3.3).

    Parameters
    ----------
    x
        Signal(s), any shape; time is the last axis.
    cutoff_hz
        -3 dB cut-off frequency of one pass, Hz; must lie below Nyquist.
    sample_rate_hz
        Sampling rate of ``x``, Hz.
    order
        Butterworth order of one pass (the forward-backward filter has twice the
        attenuation slope).

    Returns
    -------
    numpy.ndarray
        Filtered signal, same shape as ``x``, float64. NaN samples propagate.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    c = _check_cutoff("cutoff_hz", cutoff_hz, fs)
    return _butter(x, c, "lowpass", fs, _check_order(order))


def highpass(x: np.ndarray, cutoff_hz: float, sample_rate_hz: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth high-pass filter along the last axis.

    Parameters
    ----------
    x
        Signal(s), any shape; time is the last axis.
    cutoff_hz
        -3 dB cut-off frequency, Hz; must lie below Nyquist.
    sample_rate_hz
        Sampling rate of ``x``, Hz.
    order
        Butterworth order of one pass.

    Returns
    -------
    numpy.ndarray
        Filtered signal, same shape as ``x``.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    c = _check_cutoff("cutoff_hz", cutoff_hz, fs)
    return _butter(x, c, "highpass", fs, _check_order(order))


def bandpass(
    x: np.ndarray,
    low_cutoff_hz: float,
    high_cutoff_hz: float,
    sample_rate_hz: float,
    order: int = 4,
) -> np.ndarray:
    """Zero-phase Butterworth band-pass filter along the last axis.

    Parameters
    ----------
    x
        Signal(s), any shape; time is the last axis.
    low_cutoff_hz, high_cutoff_hz
        Lower and upper -3 dB edges, Hz, ``0 < low < high < Nyquist``.
    sample_rate_hz
        Sampling rate of ``x``, Hz.
    order
        Butterworth order of the prototype (the band-pass has ``2 * order`` poles).

    Returns
    -------
    numpy.ndarray
        Filtered signal, same shape as ``x``.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    lo = _check_cutoff("low_cutoff_hz", low_cutoff_hz, fs)
    hi = _check_cutoff("high_cutoff_hz", high_cutoff_hz, fs)
    if lo >= hi:
        raise ValueError(f"low_cutoff_hz ({lo}) must be below high_cutoff_hz ({hi})")
    return _butter(x, (lo, hi), "bandpass", fs, _check_order(order))


def notch(
    x: np.ndarray, notch_hz: float, sample_rate_hz: float, quality: float = 30.0
) -> np.ndarray:
    """Zero-phase IIR notch (:func:`scipy.signal.iirnotch`) along the last axis.

    Useful to remove a whisker resonance or mains hum (50 Hz) from Hall-sensor traces.

    Parameters
    ----------
    x
        Signal(s), any shape; time is the last axis.
    notch_hz
        Centre frequency to remove, Hz, below Nyquist.
    sample_rate_hz
        Sampling rate of ``x``, Hz.
    quality
        Quality factor ``Q = notch_hz / bandwidth`` (-3 dB bandwidth).

    Returns
    -------
    numpy.ndarray
        Filtered signal, same shape as ``x``.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    f0 = _check_cutoff("notch_hz", notch_hz, fs)
    q = positive("quality", quality)
    b, a = _sig.iirnotch(f0, q, fs=fs)
    sos = _sig.tf2sos(b, a)  # a single biquad: identical response, sos-based filtering
    return _sosfiltfilt(sos, _as_signal(x))
