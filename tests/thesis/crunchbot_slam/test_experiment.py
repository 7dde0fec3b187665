"""`vibrissa reproduce crunchbot-slam` (thesis 6.5): the JSON contract of issue 16, the
robot named, the report's sections and the options."""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.thesis.crunchbot_slam.experiment import resolved_options

runner = CliRunner()
MODES = ("blob", "geometric", "template")


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("crunch") / "out"
    res = runner.invoke(
        app,
        [
            "reproduce",
            "crunchbot-slam",
            "--quick",
            "--json",
            "--workers",
            "1",
            "--runs",
            "2",
            "--seconds",
            "20",
            "--particles",
            "30",
            "--out",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    return out, json.loads(res.stdout)


def test_json_contract_of_issue_16(quick):
    _, s = quick
    for m in MODES:
        assert set(s["map_error"][m]) == {"mean", "std"}
        assert 0 <= s["map_error"][m]["mean"] <= 1
        assert set(s["trajectory_error_mm"][m]) == {"mean", "std"}
        assert s["trajectory_error_mm"][m]["mean"] >= 0
    assert abs(s["map_error"]["random"] - 0.5) < 0.01
    assert 0 < s["map_error"]["random_smoothed"] < 0.5
    assert set(s["radial_distance_error_mm"]) == {"w1", "w2", "w3", "w4", "combined"}
    fit = s["radial_distance_fit_residual_mm"]  # the thesis' quantity, from the training
    assert set(fit) == {"w1", "w2", "w3", "w4"} and all(0 < v < 50 for v in fit.values())
    assert 0 <= s["floor_texture"]["accuracy"] <= 1
    assert set(s["classifier_latency_ms"]) == {"floor_texture", "radial_distance", "surface_angle"}
    for v in s["classifier_latency_ms"].values():
        assert set(v) == {"median", "p99"}
    assert s["meta"]["real_time_factor"] > 0 and math.isfinite(s["meta"]["real_time_factor"])
    assert s["meta"]["n_runs"] == 2 and s["meta"]["particles"] == 30


def test_the_simulated_robot_is_said_in_meta_and_report(quick):
    out, s = quick
    res = json.loads((out / "results.json").read_text())
    assert res["meta"]["robot"] == s["meta"]["robot"] == "simulated-physics"
    assert res["meta"]["synthetic"] is False
    md = (out / "report.md").read_text()
    assert "**Synthetic robot" not in md
    assert "share each run's sensor log" in md
    assert ("ordering template < geometric < blob holds" in md) == res["ordering"][
        "template_lt_geometric_lt_blob"
    ]
    for fig in ("average_maps", "trajectory", "texture_trace"):
        assert (out / "figures" / f"{fig}.png").stat().st_size > 0
    # numbers in the prose come from the run
    assert f"{res['map_error']['blob']['mean']:.3f}" in md


def test_options_default_by_grid_and_refuse_non_positive_integers():
    assert resolved_options(False, {}) == {"runs": 20, "seconds": 360, "particles": 100}
    assert resolved_options(True, {"runs": (5.0,)})["runs"] == 5
    for bad in ((0.0,), (-1.0,), (2.5,), (1.0, 2.0)):
        with pytest.raises(ValueError, match="--particles must be a positive integer"):
            resolved_options(True, {"particles": bad})


def test_bad_particles_exit_2_before_any_work(tmp_path):
    res = runner.invoke(
        app,
        [
            "reproduce",
            "crunchbot-slam",
            "--quick",
            "--particles",
            "0",
            "--out",
            str(tmp_path / "o"),
        ],
    )
    assert res.exit_code == 2 and "--particles" in res.stderr
    assert not (tmp_path / "o").exists()
