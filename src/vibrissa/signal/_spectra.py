"""Magnitude spectra along the last axis (thesis 4.3.2, eq. 4.3)."""

from __future__ import annotations

import numpy as np

from vibrissa._validate import positive

__all__ = ["magnitude_spectrum", "spectrum_frequencies"]


def magnitude_spectrum(x: np.ndarray, detrend: bool = False) -> np.ndarray:
    """``|X(k)|`` of the discrete Fourier transform, non-negative frequencies only.

    Eq. 4.3 of the thesis; for a real signal the negative-frequency half is the
    mirror image, so :func:`numpy.fft.rfft` holds all the information.

    Parameters
    ----------
    x
        Real signal(s), time last, length ``n``.
    detrend
        Subtract each trace's mean first (removes the DC bin, e.g. the 2.5 V
        Hall rest level). The thesis keeps it (``False``).

    Returns
    -------
    numpy.ndarray
        Shape ``x.shape[:-1] + (n // 2 + 1,)``, units of ``x`` (unnormalised sum).
    """
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        raise ValueError("x must have at least one (time) axis, got a scalar")
    if detrend:
        arr = arr - arr.mean(axis=-1, keepdims=True)
    return np.abs(np.fft.rfft(arr, axis=-1))


def spectrum_frequencies(n_timepoints: int, sample_rate_hz: float) -> np.ndarray:
    """Frequencies (Hz) of the bins returned by :func:`magnitude_spectrum`.

    Parameters
    ----------
    n_timepoints
        Length of the transformed signal, samples.
    sample_rate_hz
        Sampling rate, Hz.

    Returns
    -------
    numpy.ndarray
        ``n_timepoints // 2 + 1`` frequencies from 0 to Nyquist, Hz.
    """
    if isinstance(n_timepoints, bool) or not isinstance(n_timepoints, int | np.integer):
        raise TypeError(f"n_timepoints must be an integer, got {n_timepoints!r}")
    if n_timepoints < 1:
        raise ValueError(f"n_timepoints must be >= 1, got {n_timepoints}")
    return np.fft.rfftfreq(int(n_timepoints), d=1.0 / positive("sample_rate_hz", sample_rate_hz))
