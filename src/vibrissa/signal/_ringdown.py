"""Damped frequency and damping ratio of a free ring-down (``vibrissa whisker ring``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["ring_down"]


def ring_down(
    signal: np.ndarray, dt_s: float, max_half_cycles: int = 10, skip_half_cycles: int = 2
) -> dict[str, Any]:
    """Damped frequency and damping ratio of a free decay.

    Zero crossings of ``signal`` (about its rest value 0) are found with a small
    hysteresis (so high-mode ripple near zero is not counted) and located by
    linear interpolation; the damped frequency is ``1 / (2 x mean half period)``.
    The largest ``|signal|`` of each complete half cycle (refined by a parabola
    through the three samples around it) gives one peak; a least-squares line
    through ``log|peak|`` against peak time over ``max_half_cycles`` half cycles
    gives the decay rate ``sigma``, and ``zeta = sigma / sqrt(sigma^2 + omega_d^2)``.
    The first ``skip_half_cycles`` complete half cycles are left out of the fit
    when there are enough: after releasing a statically deflected tip the higher
    bending modes still beat with the first one there (they decay faster), which
    biases the decrement upward by ~5 %.

    Parameters
    ----------
    signal : numpy.ndarray
        Samples of the decaying signal, shape (n,), resting at 0.
    dt_s : float
        Sample interval (s).
    max_half_cycles : int, default=10
        Half cycles used in the fit.
    skip_half_cycles : int, default=2
        Complete half cycles skipped before the fit window (ignored if fewer than
        ``skip_half_cycles + 3`` are found).

    Returns
    -------
    dict
        ``frequency_hz`` and ``damping_ratio`` (``None`` if fewer than three
        complete half cycles are found), ``n_peaks`` used in the fit, ``first_peak``
        (index of the first half cycle fitted), ``peak_times_s`` and ``peak_values``
        of the fitted peaks.
    """
    s = np.asarray(signal, dtype=float)
    amp = float(np.max(np.abs(s))) if s.size else 0.0
    empty: dict[str, Any] = {
        "frequency_hz": None,
        "damping_ratio": None,
        "n_peaks": 0,
        "first_peak": 0,
        "peak_times_s": [],
        "peak_values": [],
    }
    if not amp > 0:
        return empty
    h = 0.005 * amp
    crossings: list[float] = []
    state = 0
    last_sign_change = -1
    for i in range(1, s.size):
        if (s[i - 1] > 0) != (s[i] > 0):
            last_sign_change = i - 1
        new = 1 if s[i] > h else (-1 if s[i] < -h else state)
        if state != 0 and new != state and last_sign_change >= 0:
            j = last_sign_change
            frac = s[j] / (s[j] - s[j + 1]) if s[j] != s[j + 1] else 0.5
            crossings.append((j + frac) * dt_s)
        state = new
    cross = np.asarray(crossings)
    times: list[float] = []
    peaks: list[float] = []
    for a, b in zip(cross[:-1], cross[1:], strict=True):
        i0, i1 = int(math.ceil(a / dt_s)), int(math.floor(b / dt_s))
        if i1 < i0:
            continue
        seg = np.abs(s[i0 : i1 + 1])
        k = i0 + int(np.argmax(seg))
        t_k, p_k = k * dt_s, abs(s[k])
        if 0 < k < s.size - 1:
            y0, y1, y2 = abs(s[k - 1]), abs(s[k]), abs(s[k + 1])
            den = y0 - 2 * y1 + y2
            if den < 0:
                off = 0.5 * (y0 - y2) / den
                if abs(off) <= 1:
                    t_k = (k + off) * dt_s
                    p_k = y1 - 0.25 * (y0 - y2) * off
        times.append(t_k)
        peaks.append(p_k)
        if len(peaks) >= skip_half_cycles + max_half_cycles:
            break
    if len(peaks) < 3:
        return {**empty, "n_peaks": len(peaks), "peak_times_s": times, "peak_values": peaks}
    first = skip_half_cycles if len(peaks) >= skip_half_cycles + 3 else 0
    t_fit = np.asarray(times[first : first + max_half_cycles])
    p_fit = np.asarray(peaks[first : first + max_half_cycles])
    n = t_fit.size
    half_period = float(np.mean(np.diff(cross[first : first + n + 1])))
    wd = math.pi / half_period
    sigma = -float(np.polyfit(t_fit, np.log(p_fit), 1)[0])
    zeta = sigma / math.hypot(sigma, wd)
    return {
        "frequency_hz": wd / (2 * math.pi),
        "damping_ratio": zeta,
        "n_peaks": n,
        "first_peak": first,
        "peak_times_s": t_fit.tolist(),
        "peak_values": p_fit.tolist(),
    }
