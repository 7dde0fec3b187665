"""Tests of vibrissa.experiments.ringdown: the ring-down test measures the model's own mode."""

from __future__ import annotations

import pytest

from vibrissa.experiments.ringdown import ring_down_test
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel


def test_the_measured_decay_is_the_first_modes():
    """Released from a tip deflection, the low-passed base signal rings at the model's
    first damped frequency and decays at its configured damping ratio."""
    geom = preset("xy-robot")
    model = RodModel(geom, n_elements=12)
    out = ring_down_test(model, tip_deflection_mm=5.0, duration_s=1.0, dt_s=2.5e-4)
    assert out["signal"] == "magnet tan_x" and out["lowpass_hz"] is not None
    assert out["frequency_hz"] == pytest.approx(out["model_damped_frequency_hz"], rel=0.03)
    assert out["damping_ratio"] == pytest.approx(geom.damping_ratio, rel=0.15)
    assert out["n_peaks_fitted"] >= 5


def test_unfiltered_says_so():
    model = RodModel(preset("xy-robot"), n_elements=12)
    out = ring_down_test(model, tip_deflection_mm=5.0, duration_s=0.5, dt_s=2.5e-4, lowpass=False)
    assert out["lowpass_hz"] is None and out["frequency_hz"] is not None
