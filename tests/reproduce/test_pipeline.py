"""The results envelope and the reports of every registered experiment (quick runs)."""

from __future__ import annotations

import json
import re

import pytest

from vibrissa import __version__
from vibrissa.reproduce import Experiment, Option, experiments, get_experiment, run_experiment

#: every registered experiment (the quick_runs fixture runs each once)
NAMES = list(experiments())


def test_registry_holds_both_thesis_experiments():
    exps = experiments()
    assert set(NAMES) <= set(exps)
    assert [e.chapter for e in exps.values()] == sorted(e.chapter for e in exps.values())
    for e in exps.values():
        assert isinstance(e, Experiment)
        assert e.n_trials(True) < e.n_trials(False)
    with pytest.raises(ValueError, match="unknown experiment 'nope'; choose one of"):
        get_experiment("nope")


@pytest.mark.parametrize("name", NAMES)
def test_results_envelope(quick_runs, name):
    out, res = quick_runs[name]
    saved = json.loads((out / "results.json").read_text())
    assert list(saved)[:3] == ["meta", "parameters", "classifiers"]
    meta = saved["meta"]
    assert meta["vibrissa_version"] == __version__
    assert meta["command"] == f"pytest quick {name}"
    assert meta["seed"] == 0 and meta["quick"] is True and meta["experiment"] == name
    assert set(meta["wall_seconds"]) == {"generate", "evaluate", "report", "total"}
    assert all(v >= 0 for v in meta["wall_seconds"].values())
    assert meta["cores"]["available"] >= 1 and meta["cores"]["generate_workers"] == 1
    assert meta["cores"]["evaluate_workers"] == 1
    assert re.match(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d", meta["started_at"])
    for p in saved["parameters"].values():
        assert p["unit"] and p["values"]


@pytest.mark.parametrize("name", NAMES)
def test_report_states_provenance_and_quick_run(quick_runs, name):
    out, res = quick_runs[name]
    md = (out / "report.md").read_text()
    head = md[:1500]
    assert head.startswith("# ")
    assert "**Quick run.**" in head
    assert f"vibrissa {__version__}" in head and f"`pytest quick {name}`" in head
    assert "goes here" not in md and "<!--" not in md
    assert not re.search(r"^## [^\n]*\n\s*(## |\Z)", md, flags=re.M), "empty section"
    for link in re.findall(r"\]\((figures/[^)]+)\)", md):
        assert (out / link).stat().st_size > 0, link


def test_full_run_has_no_quick_banner(tmp_path):
    """The banner is a property of the run, not of the report writer."""
    from vibrissa.evaluate.report_common import report_header

    head = report_header({"title": "T", "quick": False, "dataset": {"n_trials": 5}})
    assert "Quick run" not in head and head.startswith("# T")


def test_unknown_and_bad_options_fail_before_work(tmp_path):
    out = tmp_path / "o"
    with pytest.raises(ValueError, match="no option"):
        run_experiment("angle-texture", out, quick=True, n_seeds=2)
    with pytest.raises(ValueError, match="--n-seeds must be an integer >= 1"):
        run_experiment("radial-distance", out, quick=True, n_seeds=0)
    assert not out.exists()


def test_option_flag():
    assert Option("n_seeds", 5, "h").flag == "--n-seeds"


def test_the_dataset_is_simulated_on_the_dask_cluster_asked_for(tmp_path, monkeypatch):
    distributed = pytest.importorskip("dask.distributed")
    from vibrissa.reproduce import pipeline
    from vibrissa.robots.crunchbot import synthetic_record
    from vibrissa.thesis.crunchbot_slam.protocol import CrunchbotProtocol

    p = CrunchbotProtocol(
        n_runs=1,
        seconds=5.0,
        texture_seconds=4.0,
        seed=2,
        simulate_run=synthetic_record,
        train=None,
    )
    seen = []
    own = p.generate_dataset

    def spy(path, workers=None, progress=None, scheduler=None):
        seen.append(scheduler)
        return own(path, workers=workers, progress=progress, scheduler=scheduler)

    object.__setattr__(p, "generate_dataset", spy)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        ds, _, reused = pipeline.cached_dataset(p, tmp_path, scheduler=cluster.scheduler_address)
    assert seen == [cluster.scheduler_address] and not reused
    assert ds.sizes["trial"] == 2


@pytest.mark.parametrize("address", ["nonsense", "tcp://host", "", 8786])
def test_a_bad_scheduler_address_is_refused_before_any_work(tmp_path, address):
    with pytest.raises(ValueError, match="scheduler must be a Dask address"):
        run_experiment("radial-distance", tmp_path / "out", quick=True, scheduler=address)
    assert not (tmp_path / "out").exists()


def test_a_cached_dataset_without_vibrissas_checksum_is_simulated_again(tmp_path):
    """Issue 33: a cached dataset whose vibrissa_* attributes were stripped (saved again
    with plain xarray, or any NetCDF given that name) was reused unverified."""
    from vibrissa.experiments.generate import generate
    from vibrissa.experiments.protocols import get_protocol
    from vibrissa.reproduce import pipeline

    p = get_protocol("radial-distance", radial_distances_mm=(140.0,), speeds_mm_s=(100.0,), runs=1)
    path = pipeline.dataset_path(p, tmp_path)
    ref = generate(p, path, workers=1)
    stripped = ref.copy()
    stripped.attrs = {k: v for k, v in ref.attrs.items() if not k.startswith("vibrissa_")}
    stripped["signal"] = stripped["signal"] + 1.0  # and its data changed
    path.unlink()
    stripped.to_netcdf(path)
    ds, _, reused = pipeline.cached_dataset(p, tmp_path / "data", workers=1)
    assert not reused
    assert ds["signal"].values.tobytes() == ref["signal"].values.tobytes()
    ds2, _, reused2 = pipeline.cached_dataset(p, tmp_path / "data", workers=1)
    assert reused2  # the regenerated file, with its checksum, is reused


def test_outputs_appear_whole_or_not_at_all(tmp_path):
    """Issue 33: a full disk while the reports were written left results.json and figures
    without a report. Staged outputs move into place only when all are written."""
    import errno

    from vibrissa.reproduce.pipeline import _staging

    out = tmp_path / "out"
    (out / "figures").mkdir(parents=True)
    (out / "figures" / "old.png").write_text("previous run")
    (out / "results.json").write_text("previous run")
    with pytest.raises(OSError), _staging(out) as stage:
        (stage / "results.json").write_text("new")
        (stage / "figures").mkdir()
        raise OSError(errno.ENOSPC, "No space left on device")
    assert (out / "results.json").read_text() == "previous run"
    assert sorted(p.name for p in out.iterdir()) == ["figures", "results.json"]  # no staging
    with _staging(out) as stage:
        (stage / "figures").mkdir()
        (stage / "figures" / "new.png").write_text("this run")
        (stage / "report.md").write_text("this run")
        (stage / "results.json").write_text("this run")
    assert sorted(p.name for p in (out / "figures").iterdir()) == ["new.png"]
    assert (out / "results.json").read_text() == "this run"
    assert sorted(p.name for p in out.iterdir()) == ["figures", "report.md", "results.json"]


def test_a_directory_where_the_run_writes_a_file_is_refused_before_any_work(tmp_path):
    """And never replaced: the staged results.json would have taken its place."""
    out = tmp_path / "out"
    (out / "results.json").mkdir(parents=True)
    (out / "results.json" / "keep.txt").write_text("mine")
    with pytest.raises(ValueError, match="holds a directory 'results.json'"):
        run_experiment("scratchbot", out, quick=True)
    assert (out / "results.json" / "keep.txt").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == ["results.json"]
