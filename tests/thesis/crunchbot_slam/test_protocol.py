"""CrunchBot's tactile-SLAM protocol: the robot as a parameter, runs as chunks, the
dataset round trip back to sensor logs, and the checks of ``vibrissa run crunchbot``."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.data import load_dataset
from vibrissa.experiments.generate import generate, parts_dir
from vibrissa.robots.crunchbot import PRESETS, synthetic_record
from vibrissa.thesis.crunchbot_slam.protocol import (
    CrunchbotProtocol,
    crunchbot_protocol,
    default_robot,
    hall_run,
    sensor_logs,
)
from vibrissa.thesis.crunchbot_slam.viewer import check_watch, watch_run

CALLS: list[tuple] = []


def fake_train(seed, quick=False):
    """A stand-in for helper A's train_classifiers (tests only)."""
    CALLS.append(("train", seed, quick))
    return {"trained": seed}


def fake_robot(arena, seconds, seed, classifiers=None):
    """A stand-in for helper A's run_crunchbot: the synthetic record with latencies."""
    CALLS.append(("run", arena.name, seconds, seed, classifiers))
    rec = synthetic_record(arena, seconds, seed)
    from dataclasses import replace

    return replace(
        rec,
        latency_s={
            "floor_texture": np.full(rec.log.n_steps, 1e-4),
            "radial_distance": np.array([2e-5, 3e-5]),
        },
    )


def test_default_robot_is_the_simulated_physical_robot():
    from vibrissa.robots.crunchbot.robot import run_crunchbot
    from vibrissa.robots.crunchbot.training import train_classifiers

    run, train = default_robot()
    p = crunchbot_protocol(quick=True)
    assert run is run_crunchbot and train is train_classifiers
    assert p.robot_kind == "simulated-physics" == p.to_dict()["robot"]
    assert CrunchbotProtocol(simulate_run=synthetic_record).robot_kind == "synthetic-oracle"
    assert p.n_trials == p.n_runs + 1 and p.chunk_size == 1


def test_the_fingerprint_names_the_robot_and_is_stable():
    a = CrunchbotProtocol(n_runs=2, seconds=5.0)
    b = CrunchbotProtocol(n_runs=2, seconds=5.0)
    c = CrunchbotProtocol(n_runs=2, seconds=5.0, simulate_run=fake_robot)
    assert a.fingerprint() == b.fingerprint() != c.fingerprint()
    assert c.robot_kind == "custom" and "fake_robot" in c.to_dict()["simulate_run"]
    assert CrunchbotProtocol(n_runs=2, seconds=6.0).fingerprint() != a.fingerprint()
    assert a.run_seed(0) != a.run_seed(1) and a.run_seed(1) == b.run_seed(1)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_runs": 0}, "n_runs"),
        ({"seconds": -1.0}, "seconds"),
        ({"texture_seconds": 0.0}, "texture_seconds"),
        ({"arena": "nowhere"}, "unknown arena"),
        ({"seed": -1}, "seed"),
    ],
)
def test_bad_protocols_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        CrunchbotProtocol(**kwargs)


def test_runs_are_chunks_and_round_trip_to_sensor_logs(tmp_path):
    CALLS.clear()
    p = CrunchbotProtocol(
        n_runs=2,
        seconds=8.0,
        texture_seconds=6.0,
        seed=4,
        simulate_run=fake_robot,
        train=fake_train,
        quick_training=True,
    )
    out = tmp_path / "x.nc"
    # interrupted after one run: the shard is kept and the rest resumes
    assert generate(p, out, workers=1, chunk_size=1, max_chunks=1) is None
    assert len(list(parts_dir(out).glob("chunk-*.npz"))) == 1
    ds = p.generate_dataset(out, workers=1)
    runs = [c for c in CALLS if c[0] == "run"]
    assert [c[1] for c in runs] == ["slam", "slam", "tiles"]
    assert all(c[4] == {"trained": 4} for c in runs)
    assert [c for c in CALLS if c[0] == "train"] == [("train", 4, True)]  # once per seed
    ds = load_dataset(out)
    assert list(ds["kind"].values) == ["slam", "slam", "texture"]
    assert ds.attrs["robot"] == "custom"
    logs = sensor_logs(ds)
    for i, log in enumerate(logs):
        want = synthetic_record(PRESETS["slam"], 8.0, p.run_seed(i)).log
        assert np.array_equal(log.state, want.state)
        assert np.allclose(log.odometry, want.odometry)
        assert np.array_equal(log.contact, want.contact)
        assert np.allclose(log.true_pose, want.true_pose)
        assert log.floor_loglik is None  # the SLAM arena has no tiles
    tex = sensor_logs(ds, "texture")[0]
    assert tex.floor_loglik is not None and set(tex.textures) == {
        "vinyl",
        "smooth-carpet",
        "rough-carpet",
    }
    from vibrissa.robots.crunchbot.synthetic import FLOOR_WHISKERS_M

    assert np.array_equal(tex.floor_whisker_m, FLOOR_WHISKERS_M)
    lat = ds["latency_floor_texture_s"].values
    assert np.isfinite(lat).sum() == int(ds["n_steps"].values.sum())
    assert np.isnan(ds["latency_surface_angle_s"].values).all()
    h = hall_run(ds)
    assert h["hall_v"].shape == (h["time_s"].size, 6, 2) and h["step_start"][-1] == h["time_s"].size
    assert ds["ground_truth"].shape == (50, 50)


@pytest.mark.parametrize(
    "args, match",
    [
        (("slam", 0.0, 0, 10, "blob"), "--seconds"),
        (("slam", -1.0, 0, 10, "blob"), "--seconds"),
        (("slam", float("nan"), 0, 10, "blob"), "--seconds"),
        (("slam", 5.0, 0, 0, "blob"), "--particles"),
        (("slam", 5.0, -1, 10, "blob"), "--seed"),
        (("slam", 5.0, 0, 10, "nope"), "--mode"),
        (("nowhere", 5.0, 0, 10, "blob"), "--arena"),
    ],
)
def test_watch_options_are_checked(args, match):
    with pytest.raises(ValueError, match=match):
        check_watch(*args)


def test_watch_run_writes_an_animation_and_a_page(tmp_path):
    stages = []
    res = watch_run(
        tmp_path / "w",
        PRESETS["slam"],
        6.0,
        seed=1,
        particles=20,
        progress=lambda s, f: stages.append(s),
    )
    assert {"robot", "slam", "draw"} <= set(stages)
    assert (tmp_path / "w" / "crunchbot.gif").stat().st_size > 0
    html = (tmp_path / "w" / "crunchbot.html").read_text()
    assert "http://" not in html and "https://" not in html and "<script src" not in html
    assert 0 <= res["map_error"] <= 1 and res["trajectory_error_mm"] >= 0
    assert res["robot"] in ("synthetic-oracle", "simulated-physics")


def test_a_dask_cluster_gives_the_same_runs(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    p = CrunchbotProtocol(
        n_runs=2,
        seconds=8.0,
        texture_seconds=6.0,
        seed=4,
        simulate_run=synthetic_record,
        train=None,
    )
    here = p.generate_dataset(tmp_path / "here.nc", workers=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        there = p.generate_dataset(tmp_path / "there.nc", scheduler=cluster.scheduler_address)
    timing = [v for v in here.variables if "seconds" in v or "latency" in v]
    assert "wall_seconds" in timing  # measured, so it differs from run to run
    assert there.drop_vars(timing).identical(here.drop_vars(timing))
    assert there["signal"].values.tobytes() == here["signal"].values.tobytes()
