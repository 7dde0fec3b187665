"""Dataset generation: thesis phenomena, determinism, resumption, Dask, bad input."""

import hashlib
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.data import load_dataset
from vibrissa.experiments.generate import GenerationError, generate, parts_dir
from vibrissa.experiments.protocols import get_protocol
from vibrissa.robots import LatencyModel, XYStage
from vibrissa.signal import contact_duration

RADII = (90.0, 110.0, 130.0, 150.0, 170.0)
SPEEDS = (40.0, 100.0, 160.0, 216.0)


def small(seed=0, **kw):
    base = dict(
        radial_distances_mm=(100.0, 150.0),
        speeds_mm_s=(60.0, 180.0),
        runs=1,
        directions=(1, -1),
        seed=seed,
    )
    base.update(kw)
    return get_protocol("radial-distance", **base)


@pytest.fixture(scope="module")
def phenomena(tmp_path_factory):
    p = get_protocol(
        "radial-distance",
        radial_distances_mm=RADII,
        speeds_mm_s=SPEEDS,
        runs=1,
        directions=(1,),
        # a fixed loop latency (no duty-cycle jitter) isolates the mechanism; the
        # jitter adds +/-50 ms per trial on top
        stage=XYStage(latency=LatencyModel(0.3, 0.0)),
    )
    ds = generate(p, tmp_path_factory.mktemp("g") / "ph.nc", workers=1)
    X = ds["signal"].values[:, 0]
    r = ds["radial_distance_mm"].values
    v = ds["speed_mm_s"].values
    peak = np.abs(X - 2.5).max(axis=1)
    dur = contact_duration(X, sample_rate_hz=1000, mode="peak")
    table = {(ri, vi): (pk, du) for ri, vi, pk, du in zip(r, v, peak, dur, strict=True)}
    return table


def test_peak_falls_with_radial_distance_at_fixed_speed(phenomena):
    for v in SPEEDS:
        peaks = [phenomena[(r, v)][0] for r in RADII]
        assert all(a > b for a, b in zip(peaks, peaks[1:], strict=False)), (v, peaks)


def test_contact_duration_grows_with_speed_at_fixed_radius(phenomena):
    # the object keeps advancing for the fixed loop latency: the faster it comes, the
    # deeper it goes and the longer the 720 mm/s retraction takes to clear the whisker
    for r in (90.0, 110.0, 130.0, 150.0):
        d = np.array([phenomena[(r, v)][1] for v in SPEEDS])
        assert np.polyfit(SPEEDS, d, 1)[0] > 0, (r, d)  # not strictly monotone: the
        assert d[-1] - d[0] > 0.04, (r, d)  # release (slip, ringing) adds its own detail


def test_different_contacts_give_equal_peaks(phenomena):
    # figure 3.7: a near contact at low speed looks like a far contact at high speed
    pairs = [
        (a, b)
        for a in phenomena
        for b in phenomena
        if a[0] < b[0]
        and a[1] < b[1]
        and abs(phenomena[a][0] - phenomena[b][0]) < 0.05 * phenomena[a][0]
    ]
    assert pairs, "no (radial distance, speed) pair with equal peak deflection"


def test_same_seed_same_bytes_and_other_seed_differs(tmp_path):
    a = generate(small(), tmp_path / "a.nc", workers=1)
    b = generate(small(), tmp_path / "b.nc", workers=2, chunk_size=1)
    assert a["signal"].values.tobytes() == b["signal"].values.tobytes()
    c = generate(small(seed=1), tmp_path / "c.nc", workers=1)
    assert not np.array_equal(a["signal"].values, c["signal"].values)
    loaded = load_dataset(tmp_path / "a.nc")
    assert loaded["signal"].values.tobytes() == a["signal"].values.tobytes()
    assert set(loaded["set"].values) == {1, 2}
    assert loaded.attrs["sample_rate_hz"] == 1000.0


def test_interrupted_generation_resumes_to_identical_signals(tmp_path):
    ref = generate(small(), tmp_path / "ref.nc", workers=1)
    out = tmp_path / "out.nc"
    assert generate(small(), out, workers=1, chunk_size=1, max_chunks=3) is None
    assert not out.exists()
    shards = sorted(parts_dir(out).glob("chunk-*.npz"))
    assert len(shards) == 3
    before = {s.name: s.stat().st_mtime_ns for s in shards}
    # a shard truncated by the interruption is detected and redone
    shards[-1].write_bytes(shards[-1].read_bytes()[:100])
    seen = []
    ds = generate(small(), out, workers=1, chunk_size=1, progress=lambda d, t: seen.append(d))
    assert seen[0] == 2  # two intact shards reused, nothing lost
    assert ds["signal"].values.tobytes() == ref["signal"].values.tobytes()
    assert not parts_dir(out).exists()
    assert before  # finished shards were not recomputed: checked via the progress count


def test_tampered_or_foreign_shards_are_simulated_again_not_trusted(tmp_path):
    """Issue 33: a resumed generation matched kept shards by trial index only, so an
    edited shard, or one from another seed, was sealed into the result with a valid
    checksum."""
    ref = generate(small(), tmp_path / "ref.nc", workers=1)
    out = tmp_path / "out.nc"
    assert generate(small(), out, workers=1, chunk_size=1, max_chunks=2) is None
    shards = sorted(parts_dir(out).glob("chunk-*.npz"))
    # shard 0 edited: same arrays and trial index, one value changed
    with np.load(shards[0]) as z:
        data = {k: z[k] for k in z.files}
    data["signal"] = data["signal"] + 1e-3
    with open(shards[0], "wb") as fh:
        np.savez(fh, **data)
    # shard 2 taken from another seed's generation of the same chunk
    other = tmp_path / "other.nc"
    generate(small(seed=5), other, workers=1, chunk_size=1, max_chunks=3)
    (parts_dir(out) / "chunk-00002.npz").write_bytes(
        (parts_dir(other) / "chunk-00002.npz").read_bytes()
    )
    seen = []
    with pytest.warns(UserWarning, match="2 kept shard"):
        ds = generate(small(), out, workers=1, chunk_size=1, progress=lambda d, t: seen.append(d))
    assert seen[0] == 1  # only the untouched shard 1 was kept
    assert ds["signal"].values.tobytes() == ref["signal"].values.tobytes()


def test_leftover_shards_of_another_protocol_are_refused(tmp_path):
    out = tmp_path / "x.nc"
    generate(small(), out, workers=1, chunk_size=1, max_chunks=1)
    with pytest.raises(GenerationError, match="different protocol"):
        generate(small(seed=5), out, workers=1, chunk_size=1)
    ds = generate(small(seed=5), out, workers=1, chunk_size=1, restart=True)
    assert ds.attrs["seed"] == 5


def test_dask_cluster_gives_identical_output(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    ref = generate(small(), tmp_path / "ref.nc", workers=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        ds = generate(
            small(), tmp_path / "dask.nc", scheduler=cluster.scheduler_address, chunk_size=1
        )
    assert ds["signal"].values.tobytes() == ref["signal"].values.tobytes()


def sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["radial-distance", "--radial-distances", "80:200:20"], "radial_distance_mm"),
        (["radial-distance", "--speeds", "36:900:100"], "speed_mm_s"),
        (["angle-texture", "--angles", "10,95"], "angle_deg"),
        (["angle-texture", "--textures", "p80,velvet"], "texture"),
        (["no-such-protocol"], "protocol"),
        (["radial-distance", "--speeds", "fast"], "speeds"),
        (["radial-distance", "--sample-rate-hz", "3000"], "sample period"),
        (["radial-distance", "--noise-v", "-0.1"], "--noise-v must be non-negative"),
    ],
)
def test_cli_bad_input_is_one_clear_line_and_leaves_files_alone(tmp_path, args, word):
    out = tmp_path / "existing.nc"
    out.write_bytes(b"precious")
    before = sha(out)
    res = CliRunner().invoke(app, ["generate", *args, "--out", str(out)])
    assert res.exit_code == 2
    assert word in res.output
    assert sha(out) == before
    assert not parts_dir(out).exists()


def test_cli_quick_generation(tmp_path):
    out = tmp_path / "q.nc"
    res = CliRunner().invoke(
        app,
        [
            "generate",
            "radial-distance",
            "--radial-distances",
            "100,150",
            "--speeds",
            "60,180",
            "--runs",
            "1",
            "--out",
            str(out),
            "--json",
            "--workers",
            "1",
        ],
    )
    assert res.exit_code == 0, res.output
    assert '"n_trials": 8' in res.output
    assert load_dataset(out).sizes["trial"] == 8


def test_cli_sensor_options_set_the_protocols_sensor(tmp_path):
    out = tmp_path / "s.nc"
    args = [
        "generate",
        "radial-distance",
        "--radial-distances",
        "120",
        "--speeds",
        "100",
        "--runs",
        "1",
        "--sample-rate-hz",
        "2000",
        "--noise-v",
        "0",
        "--out",
        str(out),
        "--json",
        "--workers",
        "1",
    ]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    assert '"sample_rate_hz": 2000.0' in res.output
    ds = load_dataset(out)
    assert ds.attrs["sample_rate_hz"] == 2000.0
    assert ds.sizes["time"] == round(0.6 * 2000) + round(0.7 * 2000) + 1
    params = json.loads(ds.attrs["protocol_params"])
    assert params["sensor"]["noise_v"] == 0.0 and params["sensor"]["calibration_mm"] == [80, 60]
    whisker = json.loads(ds.attrs["whisker"])
    assert whisker["hall_sensor"]["sample_rate_hz"] == 2000.0
    assert whisker["hall_calibration_mm"] == [80.0, 60.0]


# ----------------------------------------------------------------- issue 13, finding 4
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"workers": 0}, "workers must be a positive integer"),
        ({"workers": -1}, "workers must be a positive integer"),
        ({"chunk_size": 0}, "chunk_size must be a positive integer"),
    ],
)
def test_refused_generation_leaves_nothing_on_disk(tmp_path, kwargs, message):
    out = tmp_path / "x.nc"
    with pytest.raises(ValueError, match=message):
        generate(small(), out, **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_negative_seed_is_refused_by_the_protocol(tmp_path):
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        small(seed=-1)


def test_changed_options_are_refused_with_a_restart_hint_and_nothing_is_lost(tmp_path):
    out = tmp_path / "x.nc"
    generate(small(), out, workers=1, chunk_size=1, max_chunks=2)
    shards = sorted(parts_dir(out).glob("chunk-*.npz"))
    with pytest.raises(GenerationError, match="add --restart"):
        generate(small(seed=7), out, workers=1, chunk_size=1)
    assert sorted(parts_dir(out).glob("chunk-*.npz")) == shards  # the first run's work is kept
    assert issubclass(GenerationError, ValueError)  # the CLI reports it in one line, exit 2


def test_a_second_writer_fails_at_once(tmp_path):
    import fcntl

    out = tmp_path / "x.nc"
    parts_dir(out).mkdir()
    with open(parts_dir(out) / ".lock", "a+") as fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)  # another writer holds it
        with pytest.raises(GenerationError, match="another vibrissa generate is writing"):
            generate(small(), out, workers=1)
    assert not out.exists() and parts_dir(out).exists()


def test_stale_temporaries_of_a_killed_write_are_removed(tmp_path):
    out = tmp_path / "x.nc"
    stale = tmp_path / ".x.nc.abc123.nc.tmp"
    stale.write_bytes(b"half a file")
    other = tmp_path / ".y.nc.abc123.nc.tmp"  # another output's: not ours to remove
    other.write_bytes(b"keep")
    generate(small(), out, workers=1)
    assert not stale.exists() and other.exists() and out.exists()
    assert not parts_dir(out).exists()


def test_output_under_a_file_is_refused_before_work(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("keep")
    with pytest.raises(ValueError, match="is a file, not a directory"):
        generate(small(), blocker / "sub" / "x.nc", workers=1)
    assert blocker.read_text() == "keep" and sorted(tmp_path.iterdir()) == [blocker]


# ----------------------------------------------------------------- issue 13, finding 7
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"workers": 10_000}, r"workers must be at most \d+ \(4 per core of this machine"),
        ({"scheduler": "nonsense"}, "scheduler must be a Dask address like tcp://host:8786"),
    ],
)
def test_workers_beyond_the_machine_and_malformed_schedulers_are_refused(tmp_path, kwargs, message):
    with pytest.raises(ValueError, match=message):
        generate(small(), tmp_path / "x.nc", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_a_pipe_or_device_is_not_replaced_by_the_dataset(tmp_path):
    import os

    os.mkfifo(tmp_path / "pipe")
    with pytest.raises(ValueError, match="is not a regular file"):
        generate(small(), tmp_path / "pipe", workers=1)
    assert [p.name for p in tmp_path.iterdir()] == ["pipe"]


def test_a_run_that_fails_before_keeping_a_trial_leaves_nothing(tmp_path, monkeypatch):
    def broken(protocol, indices):
        raise RuntimeError("a bug")

    monkeypatch.setattr("vibrissa.experiments.generate.simulate_trials", broken)
    with pytest.raises(RuntimeError, match="a bug"):
        generate(small(), tmp_path / "x.nc", workers=1)
    assert list(tmp_path.iterdir()) == []


def test_kept_trials_counts_the_finished_shards_on_disk(tmp_path):
    """What an interrupted generation says it kept is what is on disk, even when the
    signal lands between a shard's write and the progress report after it."""
    import json

    from vibrissa.experiments.generate import kept_trials, parts_dir

    out = tmp_path / "x.nc"
    assert kept_trials(out) == 0  # nothing yet
    parts = parts_dir(out)
    parts.mkdir()
    (parts / "manifest.json").write_text(json.dumps({"n_trials": 10, "chunk_size": 4}))
    for name in ("chunk-00000.npz", "chunk-00002.npz", ".chunk-00001.npz.tmp"):
        (parts / name).write_bytes(b"")
    assert kept_trials(out) == 4 + 2  # chunks 0 (4 trials) and 2 (the last, 2 trials)


def test_shards_are_assembled_as_concatenate_joins_them_in_any_arrival_order():
    from vibrissa.experiments.generate import _Assembly

    rng = np.random.default_rng(3)
    sizes = [4, 1, 3]
    chunks = np.split(np.arange(8), np.cumsum(sizes)[:-1])
    shards = [
        {
            "signal": rng.normal(size=(n, 2, 5)),
            "index": idx,
            "label": np.array(["ab" * (k + 1)] * n),
        }  # a dtype the shards differ in
        for k, (n, idx) in enumerate(zip(sizes, chunks, strict=True))
    ]
    expect = {key: np.concatenate([s[key] for s in shards]) for key in shards[0]}
    done = _Assembly(chunks)
    for k in (0, 2, 1):  # the label widens on the way
        done.add(k, shards[k])
    assert done.filled == {0, 1, 2}
    got = done.arrays()
    for key, want in expect.items():
        assert got[key].dtype == want.dtype
        assert got[key].tobytes() == want.tobytes()


def test_arrays_of_their_own_length_are_joined_as_concatenate_joins_them():
    """A protocol of another robot (CrunchBot's: a run's states) may keep arrays that
    are not a row per trial; they are joined whole, also when the first shard's
    happened to be as long as its chunk."""
    from vibrissa.experiments.generate import _Assembly

    rng = np.random.default_rng(4)
    chunks = [np.arange(2), np.arange(2, 4), np.arange(4, 6)]
    shards = [
        {"index": idx, "state": rng.normal(size=(n, 3)), "scalar": np.arange(1)}
        for idx, n in zip(chunks, (2, 16, 5), strict=True)
    ]
    done = _Assembly(chunks)
    for k in (0, 1, 2):
        done.add(k, shards[k])
    got = done.arrays()
    for key in shards[0]:
        want = np.concatenate([s[key] for s in shards])
        assert got[key].dtype == want.dtype and got[key].tobytes() == want.tobytes()


def test_shards_with_other_arrays_are_refused_by_name():
    from vibrissa.experiments.generate import _Assembly

    done = _Assembly([np.arange(2), np.arange(2, 4)])
    done.add(0, {"signal": np.zeros((2, 2, 5))})
    with pytest.raises(GenerationError, match=r"shard 1 has the arrays \['other'\]"):
        done.add(1, {"other": np.zeros((2, 2, 5))})
