"""Tests of vibrissa.whisker.benchmark: the standard scenario and its validation."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.whisker.benchmark import STANDARD, physics_benchmark, standard_trajectory
from vibrissa.whisker.geometry import PRESETS
from vibrissa.whisker.rod import RodModel


def test_standard_trajectory_shape():
    model = RodModel(PRESETS["xy-robot"])
    traj = standard_trajectory(model)
    t = traj.time_s
    x = traj.position_mm[:, 0]
    assert t[-1] >= STANDARD["duration_s"]
    assert np.all(traj.position_mm[:, 1] == STANDARD["radial_distance_mm"])
    shaft_r = float(model.geometry.radius_m(0.14)) * 1e3
    assert x[0] == -(1.0 + 0.5 + shaft_r)
    i_adv = np.searchsorted(t, 0.3)
    assert abs(x[i_adv] - x[0] - 30.0) < 1e-9
    assert abs(x[-1] - (x[0] + 30.0 - 36.0)) < 1e-9
    assert traj.velocity_mm_s[10, 0] == 100.0
    assert traj.velocity_mm_s[np.searchsorted(t, 0.31), 0] == -720.0
    assert traj.velocity_mm_s[-1, 0] == 0.0


def test_physics_benchmark_short_run():
    out = physics_benchmark(duration_s=0.05, repeats=1, measure_memory=False)
    assert out["n_steps"] == 200 and out["n_samples"] == 201  # 4 kHz at dt 0.25 ms
    assert out["real_time_factor"] > 0
    assert out["peak_memory_mb"] is None and out["peak_memory_method"] is None
    assert out["hall_gain_n_elements"] == out["n_elements"]
    for key in ("free_flight", "whisking_in_air", "contact"):
        assert out[f"{key}_real_time_factor"] > 0
    assert "whisk" in out["whisking_in_air_scenario"]


def test_the_whisk_in_air_turns_the_housing_through_its_amplitude():
    from vibrissa.whisker.benchmark import WHISK_DEG, WHISK_HZ, whisk_in_air

    bm = whisk_in_air(1.5)
    angle, rate = bm.sample(np.arange(0.0, 1.5, 1e-3))
    assert np.degrees(angle.max()) == pytest.approx(WHISK_DEG, rel=1e-3)
    assert angle.min() == pytest.approx(0.0, abs=1e-9)
    # back at full retraction after one whisk period; the rate is the angle's derivative
    assert bm.sample(np.array([1.0 / WHISK_HZ]))[0][0] == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(np.gradient(angle, 1e-3)[5:-5], rate[5:-5], atol=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"dt_s": 3e-4}, "dt_s"),
        ({"duration_s": 0.001}, "duration_s"),
        ({"repeats": 0}, "repeats"),
        ({"n_elements": 2}, "n_elements"),
    ],
)
def test_physics_benchmark_rejects_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        physics_benchmark(**kwargs)
