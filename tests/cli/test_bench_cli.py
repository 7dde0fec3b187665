"""Tests of `vibrissa bench physics` (runs a shortened scenario; no timing asserted)."""

from __future__ import annotations

import json
import os

from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()


def test_bench_physics_json_short():
    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    res = runner.invoke(
        app, ["bench", "physics", "--json", "--duration-s", "0.2", "--repeats", "1"]
    )
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    for key in (
        "real_time_factor",
        "scenario",
        "preset",
        "radial_distance_mm",
        "speed_mm_s",
        "dt_s",
        "n_elements",
        "wall_seconds",
        "peak_memory_mb",
        "peak_memory_method",
        "n_steps",
    ):
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
    # pinned to one CPU where the platform can pin (issue 32), and unpinned after
    if hasattr(os, "sched_getaffinity"):
        assert d["pinned_cpu"] in cpus
        assert os.sched_getaffinity(0) == cpus  # restored
    else:
        assert d["pinned_cpu"] is None


def test_bench_physics_text_and_bad_dt():
    res = runner.invoke(app, ["bench", "physics", "--duration-s", "0.05", "--repeats", "1"])
    assert res.exit_code == 0, res.output
    assert "real-time factor" in res.stdout
    assert "pinned to CPU" in res.stdout or "not pinned" in res.stdout
    res = runner.invoke(app, ["bench", "physics", "--dt-ms", "0.3", "--duration-s", "0.05"])
    assert res.exit_code == 2
    assert "--dt-ms" in res.stderr
    res = runner.invoke(app, ["bench", "physics", "--repeats", "0", "--duration-s", "0.05"])
    assert res.exit_code == 2
    assert "--repeats" in res.stderr
