"""Hand-made features of a contact (thesis 4.3.4, eqs. 4.5-4.8).

Both features work on the deflection magnitude ``|x - rest_v|`` so that
deflections in the ``-x`` direction count like those in ``+x`` (the thesis
flipped its clockwise trials into the same direction before analysis, 4.2).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from vibrissa._validate import finite, non_negative, positive

__all__ = ["contact_duration", "peak_magnitude"]


def _deflection(x: np.ndarray, rest_v: float | None) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] == 0:
        raise ValueError("x must have a non-empty (time) last axis")
    if rest_v is None:
        return np.abs(arr)
    return np.abs(arr - finite("rest_v", rest_v))


def peak_magnitude(x: np.ndarray, rest_v: float | None = 2.5) -> np.ndarray:
    """Feature f1: peak deflection magnitude, ``max_t |x(t) - rest_v|`` (eq. 4.5).

    Parameters
    ----------
    x
        Hall-sensor signal(s), V, time last.
    rest_v
        Rest output subtracted first, V (2.5 V for the thesis' sensor); ``None``
        if ``x`` is already a deflection.

    Returns
    -------
    numpy.ndarray
        Peak magnitude, V, shape ``x.shape[:-1]``.
    """
    return _deflection(x, rest_v).max(axis=-1)


def contact_duration(
    x: np.ndarray,
    sample_rate_hz: float,
    threshold_v: float = 0.05,
    rest_v: float | None = 2.5,
    mode: Literal["first", "peak"] = "first",
) -> np.ndarray:
    """Feature f2: deflection duration above a threshold, seconds (eqs. 4.6-4.8).

    Parameters
    ----------
    x
        Hall-sensor signal(s), V, time last.
    sample_rate_hz
        Sampling rate, Hz.
    threshold_v
        Threshold ``gamma`` on the deflection magnitude, V (thesis: 0.05 V).
    rest_v
        Rest output subtracted first, V; ``None`` if ``x`` is already a deflection.
    mode
        ``"first"`` follows eqs. 4.6-4.7 literally: ``t1`` is the first sample at
        or above the threshold, ``t2`` the first later sample at or below it.
        ``"peak"`` measures the run of samples at or above the threshold that
        contains the peak deflection (robust to an early noise crossing).

    Returns
    -------
    numpy.ndarray
        ``f2 = t2 - t1`` in seconds, shape ``x.shape[:-1]``; 0 when the threshold
        is never reached; a deflection still above threshold at the end of the
        trace counts up to the end.
    """
    fs = positive("sample_rate_hz", sample_rate_hz)
    gamma = non_negative("threshold_v", threshold_v)
    d = _deflection(x, rest_v)
    n = d.shape[-1]
    idx = np.arange(n)
    above = d >= gamma
    if mode == "first":
        has = above.any(axis=-1)
        t1 = np.argmax(above, axis=-1)
        later_below = (d <= gamma) & (idx > t1[..., None])
        t2 = np.where(later_below.any(axis=-1), np.argmax(later_below, axis=-1), n)
        samples = np.where(has, t2 - t1, 0)
    elif mode == "peak":
        p = np.argmax(d, axis=-1)[..., None]
        below = ~above
        before = below & (idx <= p)
        last_before = n - 1 - np.argmax(before[..., ::-1], axis=-1)
        start = np.where(before.any(axis=-1), last_before + 1, 0)
        after = below & (idx >= p)
        end = np.where(after.any(axis=-1), np.argmax(after, axis=-1), n)
        samples = np.maximum(end - start, 0)
    else:
        raise ValueError(f"mode must be 'first' or 'peak', got {mode!r}")
    return samples / fs
