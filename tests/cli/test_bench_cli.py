"""Tests of `vibrissa bench physics` (runs a shortened scenario; no timing asserted)."""

from __future__ import annotations

import json

import numpy as np
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.cli.bench import STANDARD, standard_trajectory
from vibrissa.whisker.geometry import PRESETS
from vibrissa.whisker.rod import RodModel

runner = CliRunner()


def test_bench_physics_json_short():
    res = runner.invoke(
        app, ["bench", "physics", "--json", "--duration-s", "0.2", "--repeats", "1"]
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    for key in ("real_time_factor", "scenario", "preset", "radial_distance_mm", "speed_mm_s",
                "dt_s", "n_elements", "wall_seconds", "peak_memory_mb", "peak_memory_method",
                "n_steps"):
        assert key in d
    assert d["real_time_factor"] > 0
    assert d["preset"] == "xy-robot"
    assert d["radial_distance_mm"] == 140.0
    assert d["speed_mm_s"] == 100.0
    assert d["dt_s"] == 2.5e-4
    assert d["n_steps"] == 800
    assert d["peak_memory_mb"] > 0
    assert "tracemalloc" in d["peak_memory_method"]
    assert d["peak_hall_x_v"] > 2.5  # the pole reached the whisker


def test_bench_physics_text_and_bad_dt():
    res = runner.invoke(app, ["bench", "physics", "--duration-s", "0.05", "--repeats", "1"])
    assert res.exit_code == 0, res.output
    assert "real-time factor" in res.stdout
    res = runner.invoke(app, ["bench", "physics", "--dt-ms", "0.3", "--duration-s", "0.05"])
    assert res.exit_code == 2
    assert "--dt-ms" in res.stderr


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
