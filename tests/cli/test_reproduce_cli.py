"""Tests of `vibrissa reproduce NAME` and `--list` (quick grids, real runs).

One real quick run per command (module fixtures) backs the JSON-contract checks;
bad arguments must fail with one line and exit status 2 before any work is done.
"""

from __future__ import annotations

import json
import re
import signal
import sys
from pathlib import Path

import pytest
from console import interrupt_once_a_shard_exists
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()
CONTACTS = ["1", "2", "3", "5", "10"]


def _run(args: list[str]) -> dict:
    res = runner.invoke(app, ["reproduce", *args])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


@pytest.fixture(scope="module")
def angle_texture(tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("ch5") / "out"
    return out, _run(
        ["angle-texture", "--quick", "--json", "--no-figures", "--workers", "1", "--out", str(out)]
    )


@pytest.fixture(scope="module")
def radial_distance(tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("ch4") / "out"
    return out, _run(
        [
            "radial-distance",
            "--quick",
            "--json",
            "--no-figures",
            "--n-seeds",
            "1",
            "--workers",
            "1",
            "--out",
            str(out),
        ]
    )


def test_angle_texture_json_contract(angle_texture):
    out, d = angle_texture
    assert d["chapter"] == 5 and d["quick"] is True
    assert len(d["classifiers"]) >= 16
    for name, e in d["classifiers"].items():
        assert set(e["kappa"]) == {"angle", "speed", "texture", "texture_alone"}, name
        for k in e["kappa"].values():
            assert -1.0 <= k <= 1.0
        assert e["classify_seconds"] > 0
    assert list(d["sequential"]) == CONTACTS
    assert all(-1.0 <= v <= 1.0 for v in d["sequential"].values())
    assert d["meta"]["dataset"]["reused"] is False
    assert d["experiment"] == "angle-texture"
    assert (out / "report.md").read_text().startswith("# Chapter 5")
    assert (out / "report.html").read_text().startswith("<!DOCTYPE html>")
    saved = json.loads((out / "results.json").read_text())
    assert saved["sequential"] == d["sequential"]


def test_angle_texture_reuses_its_dataset(angle_texture):
    out, first = angle_texture
    again = _run(["angle-texture", "--quick", "--json", "--no-figures", "--out", str(out)])
    assert again["meta"]["dataset"]["reused"] is True
    assert again["meta"]["dataset"]["path"] == first["meta"]["dataset"]["path"]
    # same data, same seed: the deterministic classifiers agree exactly
    assert (
        again["classifiers"]["template_raw"]["kappa"]
        == first["classifiers"]["template_raw"]["kappa"]
    )


def test_radial_distance_json_contract(radial_distance):
    out, d = radial_distance
    assert d["chapter"] == 4 and d["protocol"] == "radial-distance"
    assert "template" in d["classifiers"]
    e = d["classifiers"]["template"]
    assert e["radius_mm"]["std"] >= 0 and e["classify_seconds"] > 0
    assert d["training_fractions"]
    assert (out / "report.md").exists() and (out / "results.json").exists()


def test_corrupt_cached_dataset_is_regenerated(radial_distance):
    out, first = radial_distance
    cached = Path(first["meta"]["dataset"]["path"])
    cached.write_bytes(cached.read_bytes()[: cached.stat().st_size // 3])  # truncated
    res = runner.invoke(
        app,
        [
            "reproduce",
            "radial-distance",
            "--quick",
            "--json",
            "--no-figures",
            "--n-seeds",
            "1",
            "--workers",
            "1",
            "--out",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    again = json.loads(res.stdout)
    assert again["meta"]["dataset"]["reused"] is False
    # the statement said "reused" before the file was read; the console corrects it
    assert (
        "could not be trusted (unreadable, changed since written, or without vibrissa" in res.stderr
    )
    # regenerated with the same seed: the same trials, so the same errors
    for key in ("radius_mm", "speed_mm_s"):
        assert again["classifiers"]["template"][key] == first["classifiers"]["template"][key]


@pytest.mark.parametrize("command", ["angle-texture", "radial-distance"])
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--seed", "-1"], "error: --seed: expected a non-negative integer, got -1"),
        (["--workers", "0"], "error: --workers: expected a positive integer, got 0"),
    ],
)
def test_bad_arguments_fail_before_any_work(tmp_path, command, args, message):
    out = tmp_path / "out"
    res = runner.invoke(app, ["reproduce", command, "--quick", "--out", str(out), *args])
    assert res.exit_code == 2
    assert message in res.output
    assert "Traceback" not in res.output
    assert not out.exists()  # nothing created, nothing simulated


def test_out_is_a_file_and_results_survive(tmp_path):
    f = tmp_path / "report-here"
    f.write_text("keep me")
    res = runner.invoke(app, ["reproduce", "angle-texture", "--quick", "--out", str(f)])
    assert res.exit_code == 2 and "is a file, not a directory" in res.output
    assert f.read_text() == "keep me"
    out = tmp_path / "old"
    out.mkdir()
    (out / "results.json").write_text('{"earlier": true}')
    res = runner.invoke(
        app, ["reproduce", "radial-distance", "--quick", "--n-seeds", "0", "--out", str(out)]
    )
    assert res.exit_code == 2 and "--n-seeds: expected a positive integer" in res.output
    assert (out / "results.json").read_text() == '{"earlier": true}'
    assert not (out / "data").exists()


def test_list_names_every_experiment_with_trial_counts():
    res = runner.invoke(app, ["reproduce", "--list", "--json"])
    assert res.exit_code == 0, res.output
    exps = {e["name"]: e for e in json.loads(res.stdout)["experiments"]}
    assert {"radial-distance", "angle-texture"} <= set(exps)
    assert exps["radial-distance"]["trials"] == {"quick": 80, "full": 10504}
    assert exps["angle-texture"]["trials"] == {"quick": 144, "full": 1408}
    for e in exps.values():
        assert e["description"] and "\n" not in e["description"]
        assert isinstance(e["chapter"], int)
    text = runner.invoke(app, ["reproduce", "--list"])
    assert text.exit_code == 0
    assert all(name in text.stdout for name in exps)


def test_every_registered_experiment_has_a_command():
    from vibrissa.reproduce import experiments

    for name in experiments():
        res = runner.invoke(app, ["reproduce", name, "--help"])
        assert res.exit_code == 0 and "--quick" in res.output, name


def test_unknown_experiment_is_a_usage_error():
    res = runner.invoke(app, ["reproduce", "no-such-experiment"])
    assert res.exit_code == 2


# ----------------------------------------------------------------- issue 13, finding 7
def test_a_reused_dataset_is_stated_before_the_evaluation(radial_distance):
    out, first = radial_distance
    res = runner.invoke(
        app,
        [
            "reproduce",
            "radial-distance",
            "--quick",
            "--json",
            "--no-figures",
            "--n-seeds",
            "1",
            "--workers",
            "1",
            "--out",
            str(out),
        ],
    )
    assert res.exit_code == 0, res.output
    assert res.stderr.splitlines()[0] == (
        f"radial-distance: 80 trials (quick grid), seed 0, simulated dataset reused from "
        f"{first['meta']['dataset']['path']}; then the evaluation -> {out}"
    )


def test_an_interrupted_reproduction_says_what_it_kept(tmp_path):
    """The old main was killed silently by SIGTERM (status -15)."""
    from vibrissa.reproduce import dataset_path, get_experiment

    out = tmp_path / "out"
    data = dataset_path(get_experiment("radial-distance").protocol(True, 0), out)
    parts = data.with_name(data.name + ".parts")
    code, err = interrupt_once_a_shard_exists(
        [
            "reproduce",
            "radial-distance",
            "--quick",
            "--no-figures",
            "--n-seeds",
            "1",
            "--workers",
            "2",
            "--out",
            str(out),
        ],
        parts,
        signal.SIGTERM,
    )
    assert code == 143, err
    assert "Traceback" not in err
    lines = err.splitlines()
    assert re.fullmatch(
        r"radial-distance: 80 trials \(quick grid\), seed 0, simulating about "
        r"\d+ (s|min|h) on 2 cores, about [\d.]+ MB; then the evaluation -> .*",
        lines[0],
    ), lines[0]
    m = re.fullmatch(
        rf"interrupted: (\d+) of 80 trials kept in {re.escape(str(parts))}/; "
        "rerun the same command to resume",
        lines[-1],
    )
    assert m, err
    kept = sorted(parts.glob("chunk-*.npz"))
    assert int(m.group(1)) == sum(min(32, 80 - 32 * int(p.stem[6:])) for p in kept) > 0
    assert not data.exists() and not (out / "results.json").exists()


@pytest.mark.parametrize("name", ["radial-distance", "crunchbot-slam"])
def test_a_scheduler_without_dask_is_refused_in_one_line_before_any_work(
    tmp_path, monkeypatch, name
):
    for module in ("dask", "distributed", "dask.distributed"):  # as in a plain pip install
        monkeypatch.setitem(sys.modules, module, None)
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "reproduce",
            name,
            "--quick",
            "--no-figures",
            "--out",
            str(out),
            "--scheduler",
            "tcp://127.0.0.1:1",
        ],
    )
    assert res.exit_code == 2, res.output
    assert res.output.strip() == (
        "error: --scheduler: needs the 'distributed' extra (pip install 'vibrissa[distributed]')"
    )
    assert not (out / "data").exists() and not (out / "results.json").exists()


def test_a_directory_named_like_a_run_file_is_refused_naming_out(tmp_path):
    """Issue 33: a results.json that is a directory was refused only after the work."""
    out = tmp_path / "o"
    (out / "results.json").mkdir(parents=True)
    res = runner.invoke(app, ["reproduce", "scratchbot", "--quick", "--out", str(out)])
    assert res.exit_code == 2
    assert res.stderr.startswith("error: --out: output directory")
    assert "holds a directory 'results.json'" in res.stderr
    assert sorted(p.name for p in out.iterdir()) == ["results.json"]
