"""Tests of vibrissa.signal.ring_down: frequency and damping of a free decay."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.signal import ring_down


def _decay(f_hz: float, zeta: float, dt_s: float, duration_s: float = 1.0) -> np.ndarray:
    t = np.arange(0, duration_s, dt_s)
    wn = 2 * math.pi * f_hz
    wd = wn * math.sqrt(1 - zeta * zeta)
    return np.exp(-zeta * wn * t) * np.cos(wd * t)


def test_ring_down_on_synthetic_decay() -> None:
    dt, f, z = 1e-4, 20.0, 0.04
    r = ring_down(_decay(f, z, dt), dt)
    wd = 2 * math.pi * f * math.sqrt(1 - z * z)
    assert r["frequency_hz"] == pytest.approx(wd / (2 * math.pi), rel=1e-3)
    assert r["damping_ratio"] == pytest.approx(z, rel=0.01)
    assert r["n_peaks"] == 10 and r["first_peak"] == 2
    assert len(r["peak_times_s"]) == len(r["peak_values"]) == 10


def test_ring_down_without_enough_half_cycles() -> None:
    dt = 1e-4
    assert ring_down(np.zeros(100), dt)["damping_ratio"] is None
    assert ring_down(np.array([]), dt)["frequency_hz"] is None
    short = ring_down(_decay(20.0, 0.04, dt, duration_s=0.06), dt)
    assert short["frequency_hz"] is None and short["n_peaks"] < 3
