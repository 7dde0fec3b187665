"""`vibrissa reproduce floor-texture` (thesis 6.2): JSON contract of a real quick run, and
bad input refused with one line and exit status 2 before any simulation."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()
CONDITIONS = ["clockwise", "anticlockwise", "spot"]


@pytest.fixture(scope="module")
def floor_run(tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("floor") / "out"
    res = runner.invoke(
        app,
        [
            "reproduce",
            "floor-texture",
            "--quick",
            "--json",
            "--floors",
            "vinyl,rough-carpet",
            "--out",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    return out, json.loads(res.stdout)


def test_floor_texture_json_contract(floor_run):
    out, d = floor_run
    assert d["experiment"] == "floor-texture" and d["chapter"] == 6 and d["quick"] is True
    assert list(d["confusion"]) == CONDITIONS
    for c in CONDITIONS:
        cm = d["confusion"][c]
        # two floors asked for, in the thesis' order (rough carpet, then vinyl)
        assert len(cm) == 2 and all(len(row) == 2 for row in cm)
        # counts, averaged over the seeds of the run (--n-seeds)
        assert all(isinstance(v, int | float) and v >= 0 for row in cm for v in row)
        assert 0.0 <= d["mean_correct"][c] <= 1.0
        assert 0.0 <= d["naive_bayes"]["mean_correct"][c] <= 1.0
    assert set(d["cross_condition"]) == {"cw_on_ccw", "ccw_on_cw"}
    assert all(0.0 <= v <= 1.0 for v in d["cross_condition"].values())
    assert d["meta"]["options"]["floors"] == ["vinyl", "rough-carpet"]
    saved = json.loads((out / "results.json").read_text())
    assert saved["meta"]["floors"] == ["rough-carpet", "vinyl"]
    assert saved["confusion"] == d["confusion"]
    assert (out / "report.md").read_text().startswith("# Thesis 6.2")
    assert (out / "report.html").read_text().startswith("<!DOCTYPE html>")
    for fig in ("confusion", "templates", "signals", "trajectories"):
        assert (out / "figures" / f"{fig}.png").stat().st_size > 1000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["--floors", "vinyl,shag"],
            "error: --floors: unknown floor texture 'shag'; choose from "
            "rough-carpet, vinyl, smooth-carpet, tarmac",
        ),
        (["--floors", "vinyl"], "error: --floors needs at least 2 of"),
        (["--floors", "vinyl,vinyl"], "error: --floors: each name once"),
        (["--seed", "-1"], "error: --seed: expected a non-negative integer, got -1"),
    ],
)
def test_bad_input_fails_with_one_line_before_any_simulation(tmp_path, args, message):
    out = tmp_path / "out"
    res = runner.invoke(app, ["reproduce", "floor-texture", "--quick", "--out", str(out), *args])
    assert res.exit_code == 2
    assert message in res.output
    assert len(res.output.strip().splitlines()) == 1
    assert not out.exists()  # nothing created, nothing simulated


def test_listed_with_its_trials():
    res = runner.invoke(app, ["reproduce", "--list", "--json"])
    entry = {e["name"]: e for e in json.loads(res.stdout)["experiments"]}["floor-texture"]
    assert entry["trials"] == {"quick": 24, "full": 48}
    assert "--floors" in entry["options"]
