"""Tests of `vibrissa import` (real recordings -> dataset NetCDF)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.data import import_recording, load_dataset
from vibrissa.examples import EXAMPLE_MAPPING, EXAMPLE_RECORDING, example_path

runner = CliRunner()

SETS, SPEEDS, RADII = [1, 2, 3, 4], [36.0, 43.2, 50.4], [80.0, 81.0, 82.0, 83.0, 84.0]


def _cell(i: int, j: int, k: int) -> np.ndarray:
    """750 x 2 samples (x, y) whose values encode the cell and the sample index."""
    code = 10000.0 * i + 100.0 * j + k
    s = np.arange(750) / 1000.0
    return np.column_stack([code + s, -code - s])


@pytest.fixture
def data_xy(tmp_path):
    """A reduced data_XY.mat: cell array 'data' of 4 sets x 3 speeds x 5 radii, 750 x 2 each."""
    cells = np.empty((4, 3, 5), dtype=object)
    for idx in np.ndindex(cells.shape):
        cells[idx] = _cell(*idx)
    path = tmp_path / "data_XY.mat"
    scipy.io.savemat(path, {"data": cells})
    return path


MAPPING = {
    "signal": "data",
    "cell_axes": [
        {"name": "set", "values": SETS},
        {"name": "speed_mm_s", "start": 36, "step": 7.2, "stop": 50.4},
        {"name": "radial_distance_mm", "start": 80, "stop": 84, "num": 5},
    ],
    "channels": ["x", "y"],
    "sample_rate_hz": 1000,
    "time_axis": 0,
}


def _check(ds) -> None:
    assert ds.sizes == {"trial": 60, "channel": 2, "time": 750}
    assert list(ds["channel"].values) == ["x", "y"]
    assert ds.attrs["sample_rate_hz"] == 1000.0
    for trial, (i, j, k) in enumerate(np.ndindex(4, 3, 5)):
        assert ds["set"].values[trial] == SETS[i]
        assert ds["speed_mm_s"].values[trial] == SPEEDS[j]
        assert ds["radial_distance_mm"].values[trial] == RADII[k]
        np.testing.assert_array_equal(ds["signal"].values[trial], _cell(i, j, k).T)


def test_import_data_xy_with_mapping_file(data_xy, tmp_path) -> None:
    mapping = tmp_path / "xy.json"
    mapping.write_text(json.dumps(MAPPING))
    out = tmp_path / "xy.nc"
    before = data_xy.read_bytes()
    res = runner.invoke(app, ["import", str(data_xy), "--mapping", str(mapping), "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "60 trials x 2 channels (x, y) x 750 samples at 1000 Hz" in res.stdout
    assert "speed_mm_s: 36.0, 43.2, 50.4" in res.stdout
    assert "set: 1, 2, 3, 4" in res.stdout
    assert data_xy.read_bytes() == before
    _check(load_dataset(out))


def test_import_data_xy_with_flags_only_and_json(data_xy, tmp_path) -> None:
    out = tmp_path / "xy.nc"
    res = runner.invoke(
        app,
        [
            "import",
            str(data_xy),
            "--out",
            str(out),
            "--signal",
            "data",
            "--axis",
            "set=1:4",
            "--axis",
            "speed_mm_s=36:7.2:50.4",
            "--axis",
            "radial_distance_mm=80:84",
            "--channels",
            "x,y",
            "--sample-rate-hz",
            "1000",
            "--const",
            "texture=P80",
            "--const",
            "angle_deg=90",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    summary = json.loads(res.stdout)
    assert summary["n_trials"] == 60 and summary["n_timepoints"] == 750
    assert summary["channels"] == ["x", "y"]
    assert summary["labels"]["speed_mm_s"] == {"n_values": 3, "values": SPEEDS}
    assert summary["labels"]["texture"] == {"n_values": 1, "values": ["P80"]}
    ds = load_dataset(out)
    _check(ds)
    assert ds["set"].dtype.kind == "i"
    assert ds["angle_deg"].values[0] == 90


def test_flags_override_mapping_file(data_xy, tmp_path) -> None:
    mapping = tmp_path / "xy.json"
    mapping.write_text(json.dumps({**MAPPING, "sample_rate_hz": 4000}))
    out = tmp_path / "xy.nc"
    res = runner.invoke(
        app,
        [
            "import",
            str(data_xy),
            "-m",
            str(mapping),
            "-o",
            str(out),
            "--sample-rate-hz",
            "1000",
            "--t0-s",
            "-0.325",
        ],
    )
    assert res.exit_code == 0, res.output
    ds = load_dataset(out)
    assert ds.attrs["sample_rate_hz"] == 1000.0
    assert ds["time"].values[0] == pytest.approx(-0.325)
    assert ds["time"].values[325] == pytest.approx(0.0)


def test_ragged_crop_flag(tmp_path) -> None:
    cells = np.empty((1, 3), dtype=object)
    for k in range(3):
        cells[0, k] = np.ones((100 - 10 * k, 2)) * k
    src = tmp_path / "r.mat"
    scipy.io.savemat(src, {"data": cells})
    out = tmp_path / "r.nc"
    args = ["import", str(src), "-o", str(out), "--sample-rate-hz", "1000"]
    res = runner.invoke(app, args)
    assert res.exit_code == 2
    assert "cell data{1,2} has 90 samples" in res.stderr and "--crop" in res.stderr
    assert not out.exists()
    res = runner.invoke(app, [*args, "--crop"])
    assert res.exit_code == 0, res.output
    assert "cropped from up to 100 samples" in res.stdout
    assert load_dataset(out).sizes["time"] == 80


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (
            [
                "--axis",
                "set=1:4",
                "--axis",
                "speed_mm_s=36:7.2:216",
                "--axis",
                "radial_distance_mm=80:84",
            ],
            "'speed_mm_s') has 26 values",
        ),
        (["--axis", "set=1:4"], "4 x 3 x 5 cell array but --axis has 1"),
        (["--signal", "dat"], "no variable 'dat'"),
        (["--axis", "=3"], "--axis '=3'"),
        (["--label", "speed"], "--label 'speed': expected NAME=VALUE"),
        (["--format", "xls"], "--format must be one of auto, mat, csv, npz, got 'xls'"),
        (["--time-axis", "3"], "--time-axis must lie in [0, 1]"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(data_xy, tmp_path, extra, message) -> None:
    out = tmp_path / "x.nc"
    base = ["import", str(data_xy), "-o", str(out), "--signal", "data", "--sample-rate-hz", "1000"]
    res = runner.invoke(app, [*base, *extra])
    assert res.exit_code == 2, res.output
    assert res.stderr.startswith("error:")
    assert message in res.stderr
    assert len(res.stderr.strip().splitlines()) == 1
    assert not out.exists()


def test_missing_source_and_unknown_type(tmp_path) -> None:
    res = runner.invoke(app, ["import", str(tmp_path / "none.mat"), "-o", str(tmp_path / "o.nc")])
    assert res.exit_code == 2 and "none.mat" in res.stderr
    p = tmp_path / "rec.dat"
    p.write_text("1 2 3")
    res = runner.invoke(app, ["import", str(p), "-o", str(tmp_path / "o.nc")])
    assert res.exit_code == 2 and "cannot tell the file type" in res.stderr
    bad_map = tmp_path / "m.json"
    bad_map.write_text('{"signal": "data", "sampel_rate_hz": 1000}')
    res = runner.invoke(app, ["import", str(p), "-m", str(bad_map), "-o", str(tmp_path / "o.nc")])
    assert res.exit_code == 2 and "sampel_rate_hz" in res.stderr


def test_output_not_replaced_on_failure_and_not_the_source(data_xy, tmp_path) -> None:
    out = tmp_path / "keep.nc"
    out.write_bytes(b"old contents")
    res = runner.invoke(
        app,
        ["import", str(data_xy), "-o", str(out), "--sample-rate-hz", "1000", "--signal", "nope"],
    )
    assert res.exit_code == 2
    assert out.read_bytes() == b"old contents"
    before = data_xy.read_bytes()
    res = runner.invoke(
        app,
        [
            "import",
            str(data_xy),
            "-o",
            str(data_xy),
            "--signal",
            "data",
            "--axis",
            "a",
            "--axis",
            "b",
            "--axis",
            "c",
            "--sample-rate-hz",
            "1000",
        ],
    )
    assert res.exit_code == 2 and "is the source file" in res.stderr
    assert data_xy.read_bytes() == before


def test_csv_import_via_cli(tmp_path) -> None:
    src = tmp_path / "rec.csv"
    rows = ["trial,time,x,texture"] + [
        f"{tr},{s / 1000:.3f},{tr + s / 10},{'P80' if tr else 'P600'}"
        for tr in range(2)
        for s in range(5)
    ]
    src.write_text("\n".join(rows) + "\n")
    out = tmp_path / "rec.nc"
    res = runner.invoke(app, ["import", str(src), "-o", str(out), "--label", "texture=texture"])
    assert res.exit_code == 0, res.output
    ds = load_dataset(out)
    assert list(ds["texture"].values) == ["P600", "P80"]
    assert ds.attrs["sample_rate_hz"] == pytest.approx(1000.0)
    np.testing.assert_allclose(ds["signal"].values[1, 0], 1 + np.arange(5) / 10)


def test_help_documents_the_mapping() -> None:
    res = runner.invoke(app, ["import", "--help"])
    assert res.exit_code == 0
    for word in (
        "cell_axes",
        "time_axis",
        "data_XY.mat",
        "--crop",
        "sample_rate_hz",
        "wide",
        "format",
        "data_XY_small.mat",
        "exit status 2",
    ):
        assert word in res.stdout


def test_import_shipped_example_end_to_end(tmp_path) -> None:
    import hashlib

    src = example_path(EXAMPLE_RECORDING)
    digest = hashlib.sha256(src.read_bytes()).hexdigest()
    out = tmp_path / "xy_small.nc"
    args = [
        "import",
        str(src),
        "--mapping",
        str(example_path(EXAMPLE_MAPPING)),
        "--out",
        str(out),
        "--format",
        "mat",
    ]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "60 trials x 2 channels (x, y) x 750 samples at 1000 Hz (0.75 s)" in res.stdout
    assert "set: 1, 2, 3, 4" in res.stdout
    assert "speed_mm_s: 36.0, 126.0, 216.0" in res.stdout
    assert "radial_distance_mm: 80.0, 105.0, 130.0, 155.0, 180.0" in res.stdout
    ds = load_dataset(out)
    ref = import_recording(src, example_path(EXAMPLE_MAPPING))
    np.testing.assert_array_equal(ds["signal"].values, ref["signal"].values)
    for name in ("set", "speed_mm_s", "radial_distance_mm"):
        np.testing.assert_array_equal(ds[name].values, ref[name].values)
    cells = scipy.io.loadmat(src)["data"]
    np.testing.assert_array_equal(ds["signal"].values[17], cells[1, 0, 2].T)
    assert (
        int(ds["set"][17]),
        float(ds["speed_mm_s"][17]),
        float(ds["radial_distance_mm"][17]),
    ) == (2, 36.0, 130.0)
    assert hashlib.sha256(src.read_bytes()).hexdigest() == digest
    res = runner.invoke(app, [*args, "--json"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.stdout)
    assert summary["n_trials"] == 60 and summary["n_timepoints"] == 750
    assert {k: v["n_values"] for k, v in summary["labels"].items()} == {
        "set": 4,
        "speed_mm_s": 3,
        "radial_distance_mm": 5,
    }


def test_existing_dataset_kept_when_import_fails(tmp_path) -> None:
    out = tmp_path / "xy_small.nc"
    src, mapping = example_path(EXAMPLE_RECORDING), example_path(EXAMPLE_MAPPING)
    res = runner.invoke(app, ["import", str(src), "-m", str(mapping), "-o", str(out)])
    assert res.exit_code == 0, res.output
    before = out.read_bytes()
    for extra in (["--channels", "x"], ["--format", "csv"], ["--axis", "set=1:3"]):
        res = runner.invoke(app, ["import", str(src), "-m", str(mapping), "-o", str(out), *extra])
        assert res.exit_code == 2, res.output
        assert res.stderr.startswith("error:") and len(res.stderr.strip().splitlines()) == 1
        assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["xy_small.nc"]
