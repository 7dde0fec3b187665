"""Tests of the importers of real recordings (vibrissa.data.importers)."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
import scipy.io
from data_recordings import (
    N_SAMPLES,
    RADII,
    SETS,
    SPEEDS,
    XY_MAPPING,
    cell_recording,
    write_mat73,
    xy_cells,
)

from vibrissa.data import (
    ImportMapping,
    import_file,
    import_recording,
    load_dataset,
    load_mapping,
    select,
)
from vibrissa.data.importers import (
    ImportMappingError,
    detect_format,
    parse_axis_option,
    parse_range,
)
from vibrissa.examples import EXAMPLE_MAPPING, EXAMPLE_RECORDING, example_names, example_path


def _check_xy(ds, shape=(4, 3, 5)) -> None:
    """Every trial holds the cell its labels name (C order: set, speed, radius)."""
    n = int(np.prod(shape))
    assert ds.sizes == {"trial": n, "channel": 2, "time": N_SAMPLES}
    assert list(ds["channel"].values) == ["x", "y"]
    np.testing.assert_allclose(ds["time"].values, np.arange(N_SAMPLES) / 1000.0)
    assert ds.attrs["sample_rate_hz"] == 1000.0
    for trial, (i, j, k) in enumerate(np.ndindex(shape)):
        assert ds["set"].values[trial] == SETS[i]
        assert ds["speed_mm_s"].values[trial] == SPEEDS[j]
        assert ds["radial_distance_mm"].values[trial] == RADII[k]
        np.testing.assert_array_equal(ds["signal"].values[trial], cell_recording(i, j, k).T)


# ----------------------------------------------------------------------------- MATLAB v5


def test_mat_v5_data_xy_layout(xy_mat) -> None:
    ds = import_recording(xy_mat, XY_MAPPING)
    _check_xy(ds)
    assert ds["set"].dtype.kind == "i"
    assert ds["speed_mm_s"].dtype == np.float64
    assert ds.attrs["protocol"] == "imported"
    assert ds.attrs["source_file"] == "data_XY.mat"
    assert ds.attrs["source_format"] == "mat v5"
    assert json.loads(ds.attrs["import_mapping"]) == XY_MAPPING
    # speeds 36 + 7.2 k are stored as the decimal values a user types
    assert select(ds, speed_mm_s=43.2, set=2).sizes["trial"] == 5
    assert 43.2 in ds["speed_mm_s"].values


def test_import_file_round_trip_and_leaves_source_alone(xy_mat, tmp_path) -> None:
    before = xy_mat.read_bytes()
    mtime = os.stat(xy_mat).st_mtime_ns
    out = tmp_path / "out" / "xy.nc"
    ds = import_file(xy_mat, XY_MAPPING, out)
    assert xy_mat.read_bytes() == before
    assert os.stat(xy_mat).st_mtime_ns == mtime
    back = load_dataset(out)
    _check_xy(back)
    assert back.attrs["source_sha256"] == ds.attrs["source_sha256"]
    with pytest.raises(ValueError, match="is the source file"):
        import_file(xy_mat, XY_MAPPING, xy_mat)
    assert xy_mat.read_bytes() == before


def test_failed_import_keeps_existing_output(xy_mat, tmp_path) -> None:
    out = tmp_path / "xy.nc"
    import_file(xy_mat, XY_MAPPING, out)
    good = out.read_bytes()
    with pytest.raises(ValueError):
        import_file(xy_mat, {**XY_MAPPING, "channels": ["x"]}, out)
    assert out.read_bytes() == good
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data_XY.mat", "xy.nc"]


def test_mat_v5_squeezed_row_cell_and_label_variables(tmp_path) -> None:
    cells = np.empty((1, 3), dtype=object)
    for k in range(3):
        cells[0, k] = cell_recording(0, 0, k, n=20)[:, 0]  # single channel column
    tex = np.empty((1, 3), dtype=object)
    tex[0, :] = ["P80", "P180", "aluminium"]
    path = tmp_path / "rec.mat"
    scipy.io.savemat(
        path,
        {"rec": {"sig": cells, "fs": 500.0}, "tex": tex, "angles": np.array([[10, 20, 30]])},
    )
    ds = import_recording(
        path,
        {
            "signal": "rec.sig",
            "sample_rate_hz": "rec.fs",
            "labels": {"texture": "tex", "angle_deg": "angles"},
            "constants": {"speed_mm_s": 36, "whisker_id": "C2"},
            "t0_s": -0.01,
        },
    )
    assert ds.sizes == {"trial": 3, "channel": 1, "time": 20}
    assert list(ds["texture"].values) == ["P80", "P180", "aluminium"]
    assert list(ds["angle_deg"].values) == [10, 20, 30]
    assert list(ds["whisker_id"].values) == ["C2"] * 3
    assert ds.attrs["sample_rate_hz"] == 500.0
    np.testing.assert_allclose(ds["time"].values, -0.01 + np.arange(20) / 500.0)
    np.testing.assert_array_equal(ds["signal"].values[2, 0], cell_recording(0, 0, 2, n=20)[:, 0])


def test_axis_values_from_file_variable(tmp_path) -> None:
    path = tmp_path / "a.mat"
    scipy.io.savemat(path, {"data": xy_cells(), "speeds": np.array([SPEEDS])})
    mapping = json.loads(json.dumps(XY_MAPPING))
    mapping["cell_axes"][1] = {"name": "speed_mm_s", "from": "speeds"}
    _check_xy(import_recording(path, mapping))


# ----------------------------------------------------------------------------- MATLAB v7.3


def test_mat_v73_hdf5_layout_matches_v5(tmp_path, xy_mat) -> None:
    p73 = write_mat73(tmp_path / "data_XY73.mat", {"data": xy_cells()})
    ds73 = import_recording(p73, XY_MAPPING)
    assert ds73.attrs["source_format"] == "mat v7.3"
    _check_xy(ds73)
    ds5 = import_recording(xy_mat, XY_MAPPING)
    np.testing.assert_array_equal(ds73["signal"].values, ds5["signal"].values)


def test_mat_v73_structs_strings_empty_cells(tmp_path) -> None:
    cells = np.empty((2, 2), dtype=object)
    for idx in np.ndindex(2, 2):
        cells[idx] = cell_recording(0, *idx, n=30)
    cells[1, 0] = np.zeros((0, 0))  # a missing trial
    tex = np.empty((2, 2), dtype=object)
    for idx, name in zip(np.ndindex(2, 2), ["P80", "P180", "P600", "aluminium"], strict=True):
        tex[idx] = name
    path = write_mat73(
        tmp_path / "s.mat", {"exp": {"recs": cells, "fs": np.array(4000.0)}, "tex": tex}
    )
    mapping = {
        "signal": "exp.recs",
        "cell_axes": [{"name": "angle_deg", "values": [10, 20]}, {"name": "run"}],
        "labels": {"texture": "tex"},
        "sample_rate_hz": "exp.fs",
        "channels": ["x", "y"],
    }
    with pytest.raises(ValueError, match=r"cell exp\.recs\{2,1\} is empty"):
        import_recording(path, mapping)
    ds = import_recording(path, {**mapping, "empty": "skip"})
    assert ds.sizes["trial"] == 3
    assert list(ds["angle_deg"].values) == [10, 10, 20]
    assert list(ds["run"].values) == [0, 1, 1]
    assert list(ds["texture"].values) == ["P80", "P180", "aluminium"]
    assert ds.attrs["sample_rate_hz"] == 4000.0
    np.testing.assert_array_equal(ds["signal"].values[2], cell_recording(0, 1, 1, n=30).T)
    with pytest.raises(ValueError, match="no variable/field 'nope'.*'recs'"):
        import_recording(path, {**mapping, "signal": "exp.nope"})
    with pytest.raises(ValueError, match="is a struct"):
        import_recording(path, {**mapping, "signal": "exp"})


def test_mat_v73_non_numeric_cell(tmp_path) -> None:
    cells = np.empty((1, 2), dtype=object)
    cells[0, 0] = cell_recording(0, 0, 0, n=10)
    cells[0, 1] = "oops"
    path = write_mat73(tmp_path / "c.mat", {"data": cells})
    with pytest.raises(ValueError, match=r"cell data\{1,2\} holds text, not numbers"):
        import_recording(path, {"signal": "data", "sample_rate_hz": 1000})


# ----------------------------------------------------------------------------- errors


def test_axis_sizes_must_match_the_file(xy_mat) -> None:
    bad = {**XY_MAPPING, "cell_axes": [
        {"name": "set", "values": SETS},
        {"name": "speed_mm_s", "start": 36, "stop": 216, "num": 26},
        {"name": "radial_distance_mm", "start": 80, "step": 1},
    ]}
    with pytest.raises(ValueError, match=r"'speed_mm_s'\) has 26 values but signal 'data' \(a "
                                         r"4 x 3 x 5 cell array\) has 3"):
        import_recording(xy_mat, bad)
    with pytest.raises(ValueError, match="4 x 3 x 5 cell array but the mapping's cell_axes has 2"):
        import_recording(xy_mat, {**XY_MAPPING, "cell_axes": XY_MAPPING["cell_axes"][:2]})
    stop_wrong = json.loads(json.dumps(XY_MAPPING))
    stop_wrong["cell_axes"][2] = {"name": "radial_distance_mm", "start": 80, "step": 1,
                                  "stop": 180}
    with pytest.raises(ValueError, match="end at 84, not at 'stop' 180"):
        import_recording(xy_mat, stop_wrong)


def test_missing_fields(xy_mat) -> None:
    with pytest.raises(ValueError, match=r"no variable 'dta'; it holds \['data'\]"):
        import_recording(xy_mat, {**XY_MAPPING, "signal": "dta"})
    with pytest.raises(ValueError, match="label 'texture'.*'tex'|no variable 'tex'"):
        import_recording(xy_mat, {**XY_MAPPING, "labels": {"texture": "tex"}})
    no_rate = {k: v for k, v in XY_MAPPING.items() if k != "sample_rate_hz"}
    with pytest.raises(ValueError, match="sample_rate_hz"):
        import_recording(xy_mat, no_rate)
    with pytest.raises(ValueError, match=r"names 3 channel\(s\).*recordings have 2"):
        import_recording(xy_mat, {**XY_MAPPING, "channels": ["x", "y", "z"]})
    with pytest.raises(ValueError, match="recordings have 750 .*time_axis"):
        import_recording(xy_mat, {**XY_MAPPING, "time_axis": 1})


def test_ragged_cells_error_or_crop(tmp_path) -> None:
    cells = xy_cells((1, 2, 3))
    cells[0, 1, 2] = cell_recording(0, 1, 2, n=740)
    path = tmp_path / "ragged.mat"
    scipy.io.savemat(path, {"data": cells})
    mapping = {"signal": "data", "sample_rate_hz": 1000,
               "cell_axes": ["set", "speed_mm_s", "radial_distance_mm"]}
    with pytest.raises(ValueError, match=r"cell data\{1,2,3\} has 740 samples but "
                                         r"cell data\{1,1,1\} has 750"):
        import_recording(path, mapping)
    ds = import_recording(path, {**mapping, "ragged": "crop"})
    assert ds.sizes["time"] == 740 and ds.sizes["trial"] == 6
    assert ds.attrs["cropped_from_samples"] == 750
    np.testing.assert_array_equal(ds["signal"].values[0], cell_recording(0, 0, 0).T[:, :740])
    assert list(ds["radial_distance_mm"].values) == [0, 1, 2, 0, 1, 2]  # index labels


def test_non_numeric_and_nan_cells(tmp_path) -> None:
    cells = xy_cells((1, 1, 3))
    cells[0, 0, 1] = "text"
    path = tmp_path / "t.mat"
    scipy.io.savemat(path, {"data": cells})
    mapping = {"signal": "data", "sample_rate_hz": 1000, "cell_axes": ["a", "b", "c"]}
    with pytest.raises(ValueError, match=r"cell data\{1,1,2\} holds text"):
        import_recording(path, mapping)
    cells[0, 0, 1] = np.full((750, 2), np.nan)
    scipy.io.savemat(path, {"data": cells})
    with pytest.raises(ValueError, match=r"cell data\{1,1,2\} contains 1500 NaN"):
        import_recording(path, mapping)
    cells[0, 0, 1] = cell_recording(0, 0, 1)[:, :1]
    scipy.io.savemat(path, {"data": cells})
    with pytest.raises(ValueError, match=r"cell data\{1,1,2\} has 1 channel"):
        import_recording(path, mapping)


def test_unknown_or_unreadable_files(tmp_path, xy_mat) -> None:
    p = tmp_path / "rec.xyz"
    p.write_bytes(b"\x00\x01")
    with pytest.raises(ValueError, match="cannot tell the file type"):
        import_recording(p, XY_MAPPING)
    with pytest.raises(ValueError, match="unknown format"):
        import_recording(xy_mat, XY_MAPPING, format="xls")
    bad = tmp_path / "bad.mat"
    bad.write_bytes(b"this is not a MATLAB file at all" * 10)
    with pytest.raises(ValueError, match="bad.mat: cannot be read as a MATLAB"):
        import_recording(bad, XY_MAPPING)
    trunc = tmp_path / "trunc.mat"
    trunc.write_bytes(xy_mat.read_bytes()[:5000])
    with pytest.raises(ValueError, match="trunc.mat"):
        import_recording(trunc, XY_MAPPING)
    with pytest.raises(FileNotFoundError):
        import_recording(tmp_path / "none.mat", XY_MAPPING)
    assert detect_format(p, "npz") == "npz"


# ----------------------------------------------------------------------------- NPZ


def test_npz_trial_time_channel_and_grid(tmp_path) -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(size=(6, 100, 2))
    p = tmp_path / "r.npz"
    np.savez(p, x=x, speeds=np.arange(6) * 10.0, tex=np.array(list("abcabc")))
    ds = import_recording(
        p, {"signal": "x", "sample_rate_hz": 100, "labels": {"speed_mm_s": "speeds",
                                                               "texture": "tex"}}
    )
    np.testing.assert_array_equal(ds["signal"].values, x.transpose(0, 2, 1))
    assert list(ds["texture"].values) == list("abcabc")
    # vibrissa's own layout (trial, channel, time)
    ds2 = import_recording(p, {"signal": "x", "sample_rate_hz": 100, "time_axis": 1})
    assert ds2.sizes == {"trial": 6, "channel": 100, "time": 2}
    # a numeric grid (set, speed, time, channel) with a single variable
    g = rng.normal(size=(2, 3, 50, 2))
    pg = tmp_path / "g.npz"
    np.savez(pg, g=g)
    ds3 = import_recording(pg, {"sample_rate_hz": 1000, "cell_axes": [
        {"name": "set", "values": [1, 2]}, {"name": "speed_mm_s", "values": [6, 16, 26]}]})
    assert ds3.sizes["trial"] == 6
    np.testing.assert_array_equal(ds3["signal"].values[4], g[1, 1].T)
    assert (ds3["set"].values[4], ds3["speed_mm_s"].values[4]) == (2, 16)
    with pytest.raises(ValueError, match="each recording would have 3 dimensions"):
        import_recording(pg, {"sample_rate_hz": 1000})


def test_npz_refuses_pickles_and_bad_labels(tmp_path) -> None:
    p = tmp_path / "o.npz"
    obj = np.empty(2, dtype=object)
    obj[0], obj[1] = np.zeros(3), np.zeros(4)
    np.savez(p, x=obj)
    with pytest.raises(ValueError, match="pickle"):
        import_recording(p, {"signal": "x", "sample_rate_hz": 1})
    p2 = tmp_path / "l.npz"
    np.savez(p2, x=np.zeros((3, 10)), lab=np.arange(4))
    with pytest.raises(ValueError, match="label 'speed_mm_s' .* 4 values for 3 recordings"):
        import_recording(p2, {"signal": "x", "sample_rate_hz": 1,
                              "labels": {"speed_mm_s": "lab"}})
    with pytest.raises(ValueError, match="holds variables"):
        np.savez(p2, x=np.zeros((3, 10)), y=np.zeros((3, 10)))
        import_recording(p2, {"sample_rate_hz": 1})
    with pytest.raises(ValueError, match="do not apply to npz"):
        import_recording(p2, {"signal": "x", "sample_rate_hz": 1, "layout": "wide"})
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"PK not really a zip")
    with pytest.raises(ValueError, match="bad.npz"):
        import_recording(bad, {"signal": "x", "sample_rate_hz": 1})


# ----------------------------------------------------------------------------- CSV


def _long_csv(path, n_trials=3, n=8, shuffle=False, bad_label=False) -> None:
    lines = ["trial,time,x,y,speed_mm_s,texture"]
    rows = []
    for tr in range(n_trials):
        for s in range(n):
            tex = "P80" if tr != 1 else "P180"
            if bad_label and tr == 2 and s == 5:
                tex = "P600"
            rows.append(f"{tr},{s / 250:.4f},{tr * 100 + s},{-tr * 100 - s},{36 + 7.2 * tr},{tex}")
    if shuffle:
        rows = rows[::-1]
    path.write_text("\n".join(lines + rows) + "\n")


def test_csv_long_format(tmp_path) -> None:
    p = tmp_path / "long.csv"
    _long_csv(p, shuffle=True)
    ds = import_recording(p, {"labels": ["speed_mm_s", "texture"]})
    assert ds.sizes == {"trial": 3, "channel": 2, "time": 8}
    assert ds.attrs["sample_rate_hz"] == pytest.approx(250.0)
    np.testing.assert_allclose(ds["time"].values, np.arange(8) / 250)
    assert list(ds["texture"].values) == ["P80", "P180", "P80"][::-1]  # order of appearance
    # trial 2 appeared first in the shuffled file; samples sorted by time
    np.testing.assert_array_equal(ds["signal"].values[0, 0], 200 + np.arange(8))
    np.testing.assert_array_equal(ds["signal"].values[0, 1], -200 - np.arange(8))
    assert ds["speed_mm_s"].values[0] == pytest.approx(50.4)
    ds2 = import_recording(p, {"channels": ["y"], "sample_rate_hz": 250, "time_column": None})
    assert list(ds2["channel"].values) == ["y"]
    np.testing.assert_array_equal(ds2["signal"].values[0, 0], -200 - np.arange(8)[::-1])


def test_csv_long_errors(tmp_path) -> None:
    p = tmp_path / "long.csv"
    _long_csv(p, bad_label=True)
    with pytest.raises(ValueError, match="trial 2 .*'texture' is not constant"):
        import_recording(p, {"labels": ["texture"]})
    _long_csv(p)
    text = p.read_text().splitlines()
    text[4] = text[4].replace(",3,", ",abc,", 1)
    p.write_text("\n".join(text))
    with pytest.raises(ValueError, match="column 'x' must hold numbers; line 5 has 'abc'"):
        import_recording(p, {"channels": ["x", "y"]})
    with pytest.raises(ValueError, match="no trial column 'run'"):
        import_recording(p, {"trial_column": "run"})
    with pytest.raises(ValueError, match=r"no channel column\(s\) \['z'\]"):
        import_recording(p, {"channels": ["z"]})
    with pytest.raises(ValueError, match="do not apply to csv"):
        import_recording(p, {"signal": "data"})
    _long_csv(p)
    lines = p.read_text().splitlines()
    p.write_text("\n".join(lines[:-2]) + "\n")  # trial 2 loses two samples
    with pytest.raises(ValueError, match="trial 2 of long.csv has 6 samples"):
        import_recording(p, {})


def test_csv_wide_format_with_ragged_rows(tmp_path) -> None:
    p = tmp_path / "wide.csv"
    header = "angle_deg,texture," + ",".join(f"x_{k}" for k in range(5)) + "," + ",".join(
        f"y_{k}" for k in range(5))
    rows = ["10,P80,1,2,3,4,5,-1,-2,-3,-4,-5", "20,P180,6,7,8,,,-6,-7,-8,,"]
    p.write_text("\n".join([header, *rows]) + "\n")
    mapping = {"layout": "wide", "labels": ["angle_deg", "texture"], "sample_rate_hz": 4000}
    with pytest.raises(ValueError, match="row 3 of wide.csv has 3 samples"):
        import_recording(p, mapping)
    ds = import_recording(p, {**mapping, "ragged": "crop"})
    assert ds.sizes == {"trial": 2, "channel": 2, "time": 3}
    np.testing.assert_array_equal(ds["signal"].values[1], [[6, 7, 8], [-6, -7, -8]])
    assert list(ds["texture"].values) == ["P80", "P180"]
    assert list(ds["channel"].values) == ["x", "y"]


# ----------------------------------------------------------------------------- mapping


def test_load_mapping_files_and_errors(tmp_path) -> None:
    pj = tmp_path / "m.json"
    pj.write_text(json.dumps(XY_MAPPING))
    m = load_mapping(pj)
    assert isinstance(m, ImportMapping) and m.signal == "data" and m.channels == ("x", "y")
    pt = tmp_path / "m.toml"
    pt.write_text(
        'signal = "data"\nsample_rate_hz = 1000\nchannels = ["x", "y"]\n'
        '[[cell_axes]]\nname = "set"\nvalues = [1, 2, 3, 4]\n'
        '[[cell_axes]]\nname = "speed_mm_s"\nstart = 36\nstop = 50.4\nnum = 3\n'
        '[[cell_axes]]\nname = "radial_distance_mm"\nstart = 80\nstep = 1\n'
    )
    assert len(load_mapping(pt).cell_axes) == 3
    bad = tmp_path / "bad.json"
    bad.write_text("{signal: data")
    with pytest.raises(ValueError, match="bad.json is not valid JSON"):
        load_mapping(bad)
    with pytest.raises(ValueError, match="does not exist"):
        load_mapping(tmp_path / "none.json")
    for raw, match in [
        ({"sigal": "data"}, r"unknown mapping key\(s\) \['sigal'\]"),
        ({"sample_rate_hz": -1}, "sample_rate_hz"),
        ({"cell_axes": [{"name": "a", "start": 1}]}, "'num'.*'step'"),
        ({"cell_axes": [{"name": "a", "values": [1], "start": 1, "num": 1}]}, "more than one"),
        ({"cell_axes": [{"values": [1]}]}, "needs a 'name'"),
        ({"cell_axes": [{"name": "a", "stepp": 1}]}, "unknown key"),
        ({"cell_axes": ["a", "a"]}, "repeats"),
        ({"time_axis": 2}, "time_axis"),
        ({"ragged": "pad"}, "ragged"),
        ({"channels": ["x", "x"]}, "repeated"),
        ({"constants": {"set": 1}, "labels": {"set": "s"}}, "more than once"),
        ({"format": "xls"}, "format"),
    ]:
        with pytest.raises(ValueError, match=match):
            load_mapping(raw)


def test_parse_range_and_axis_option() -> None:
    assert parse_range("36:7.2:216")[:3] == [36.0, 43.2, 50.4]
    assert len(parse_range("36:7.2:216")) == 26 and parse_range("36:7.2:216")[-1] == 216.0
    assert parse_range("80:180") == [float(v) for v in range(80, 181)]
    assert parse_range("1,2,4") == [1, 2, 4]
    assert parse_range("0.5, 1") == [0.5, 1]
    assert parse_range("P80,P180") == ["P80", "P180"]
    with pytest.raises(ValueError):
        parse_range("1:0:3")
    with pytest.raises(ValueError):
        parse_range("5:1")
    assert parse_axis_option("set=1:4") == {"name": "set", "values": [1, 2, 3, 4]}
    assert parse_axis_option("speed_mm_s=@speeds") == {"name": "speed_mm_s", "from": "speeds"}
    assert parse_axis_option("trial") == {"name": "trial"}
    with pytest.raises(ValueError, match="--axis"):
        parse_axis_option("=1,2")


def test_matlab_numeric_array_with_trials_last(tmp_path) -> None:
    # samples x channels x trials, as MATLAB users often store recordings
    data = np.stack([cell_recording(0, 0, k, n=40) for k in range(3)], axis=-1)
    assert data.shape == (40, 2, 3)
    mapping = {"signal": "data", "sample_rate_hz": 1000, "trial_axes": "last",
               "cell_axes": [{"name": "radial_distance_mm", "values": [80.0, 90.0, 100.0]}]}
    p5 = tmp_path / "v5.mat"
    scipy.io.savemat(p5, {"data": data})
    p73 = write_mat73(tmp_path / "v73.mat", {"data": data})
    for path in (p5, p73):
        ds = import_recording(path, mapping)
        assert ds.sizes == {"trial": 3, "channel": 2, "time": 40}
        np.testing.assert_array_equal(ds["signal"].values[2], cell_recording(0, 0, 2, n=40).T)
        assert ds["radial_distance_mm"].values[2] == 100.0
    data[5, 1, 2] = np.inf
    scipy.io.savemat(p5, {"data": data})
    with pytest.raises(ValueError, match=r"data\(:,:,3\) contains 1 NaN or infinite"):
        import_recording(p5, mapping)
    csv = tmp_path / "x.csv"
    csv.write_text("trial,x\n0,1\n")
    with pytest.raises(ValueError, match="do not apply to csv"):
        import_recording(csv, {"trial_axes": "last", "sample_rate_hz": 1})


# ----------------------------------------------------------------------------- the brief's cases

#: The mapping of the thesis author's full data_XY.mat (4 x 26 x 101 cells of 750 x 2).
FULL_XY_MAPPING = {
    "format": "mat",
    "signal": "data",
    "cell_axes": [
        {"name": "set", "values": [1, 2, 3, 4]},
        {"name": "speed_mm_s", "start": 36, "stop": 216, "num": 26},
        {"name": "radial_distance_mm", "start": 80, "stop": 180, "num": 101},
    ],
    "channels": ["x", "y"],
    "time_axis": 0,
    "sample_rate_hz": 1000,
    "units": "V",
}


def _sha256(path) -> str:
    import hashlib

    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_full_size_data_xy_grid_with_the_documented_mapping(tmp_path) -> None:
    # the full 4 x 26 x 101 cell grid, with short cells (4 x 2) to stay fast
    cells = np.empty((4, 26, 101), dtype=object)
    for idx in np.ndindex(cells.shape):
        cells[idx] = np.full((4, 2), float(np.ravel_multi_index(idx, cells.shape)))
        cells[idx][:, 1] *= -1
    path = tmp_path / "data_XY.mat"
    scipy.io.savemat(path, {"data": cells})
    ds = import_recording(path, FULL_XY_MAPPING)
    assert ds.sizes == {"trial": 10504, "channel": 2, "time": 4}
    assert ds["signal"].attrs["units"] == "V"
    np.testing.assert_allclose(np.unique(ds["speed_mm_s"].values), 36 + 7.2 * np.arange(26))
    np.testing.assert_array_equal(np.unique(ds["radial_distance_mm"].values),
                                  np.arange(80.0, 181.0))
    # trial n is cell n in C order (set, speed, radius), transposed to channels x samples
    np.testing.assert_array_equal(ds["signal"].values[:, 0, 0], np.arange(10504.0))
    np.testing.assert_array_equal(ds["signal"].values[:, 1, 3], -np.arange(10504.0))
    t = np.ravel_multi_index((2, 5, 17), (4, 26, 101))
    assert (ds["set"].values[t], ds["speed_mm_s"].values[t],
            ds["radial_distance_mm"].values[t]) == (3, 72.0, 97.0)


def test_errors_are_import_mapping_errors(xy_mat, tmp_path) -> None:
    assert issubclass(ImportMappingError, ValueError)
    cases = [
        ({**XY_MAPPING, "signals": "data"}, "unknown mapping key"),
        ({**XY_MAPPING, "channels": "x,x"}, "repeated"),
        ({**XY_MAPPING, "sample_rate_hz": True}, "sample_rate_hz"),
        ({**XY_MAPPING, "cell_axes": "set"}, "cell_axes"),
        ({**XY_MAPPING, "signal": "nope"}, "no variable 'nope'"),
        ({**XY_MAPPING, "constants": {"time": 1}}, "reserved"),
        ({**XY_MAPPING, "cell_axes": [{"name": "set", "values": [1, 2]}, "b", "c"]},
         r"'set'\) has 2 values but signal 'data' \(a 4 x 3 x 5 cell array\) has 4"),
    ]
    for mapping, match in cases:
        with pytest.raises(ImportMappingError, match=match):
            import_recording(xy_mat, mapping)
    xls = tmp_path / "data_XY.xls"
    xls.write_bytes(b"not a recording")
    with pytest.raises(ImportMappingError, match="cannot tell the file type"):
        import_recording(xls, XY_MAPPING)


def test_nan_and_inf_say_how_many_and_where(tmp_path) -> None:
    cells = xy_cells((1, 2, 2))
    bad = cell_recording(0, 1, 0)
    bad[10:13, 1] = np.nan  # samples 11-13 (MATLAB rows), channel y
    bad[400, 0] = -np.inf
    cells[0, 1, 0] = bad
    path = tmp_path / "nan.mat"
    scipy.io.savemat(path, {"data": cells})
    with pytest.raises(
        ImportMappingError,
        match=r"cell data\{1,2,1\} contains 4 NaN or infinite value\(s\) \(3 NaN, 1 infinite\) "
        r"in 4 of 750 samples; the first \(NaN\) is sample 11 of channel 2",
    ):
        import_recording(path, {"signal": "data", "sample_rate_hz": 1000,
                                "cell_axes": ["a", "b", "c"]})
    csv = tmp_path / "nan.csv"
    csv.write_text("trial,x,y\n0,1,2\n0,1,2\n1,1,2\n1,,2\n1,nan,inf\n")
    with pytest.raises(ImportMappingError, match=r"trial 1 of nan.csv has 3 empty, NaN or "
                                                 r"infinite .* column 'x' on line 5"):
        import_recording(csv, {"sample_rate_hz": 10})


def test_mat_v73_truncated_or_damaged(tmp_path) -> None:
    p = write_mat73(tmp_path / "ok.mat", {"data": xy_cells((2, 2, 2))})
    mapping = {**XY_MAPPING, "cell_axes": ["a", "b", "c"]}
    assert import_recording(p, mapping).sizes["trial"] == 8
    blob = p.read_bytes()
    trunc = tmp_path / "trunc.mat"
    trunc.write_bytes(blob[: len(blob) // 2])
    with pytest.raises(ImportMappingError, match=r"trunc.mat: cannot be read as a MATLAB v7.3"):
        import_recording(trunc, mapping)
    # damage object headers: every failure is one ImportMappingError naming the file
    rng = np.random.default_rng(0)
    failures = 0
    for _ in range(60):
        bad = bytearray(blob)
        o = int(rng.integers(512, len(blob) - 64))
        bad[o:o + 64] = rng.integers(0, 256, 64, dtype=np.uint8).tobytes()
        q = tmp_path / "damaged.mat"
        q.write_bytes(bytes(bad))
        try:
            import_recording(q, mapping)
        except ImportMappingError as exc:
            failures += 1
            assert "damaged.mat" in str(exc) or "cell data" in str(exc)
    assert failures > 0


@pytest.mark.parametrize("kind", ["mat5", "mat73", "npz", "csv"])
def test_source_file_unchanged_by_import_and_failed_import(tmp_path, kind) -> None:
    if kind == "mat5":
        path = tmp_path / "r.mat"
        scipy.io.savemat(path, {"data": xy_cells((1, 2, 2))})
        mapping = {"signal": "data", "sample_rate_hz": 1000, "cell_axes": ["a", "b", "c"]}
    elif kind == "mat73":
        path = write_mat73(tmp_path / "r.mat", {"data": xy_cells((1, 2, 2))})
        mapping = {"signal": "data", "sample_rate_hz": 1000, "cell_axes": ["a", "b", "c"]}
    elif kind == "npz":
        path = tmp_path / "r.npz"
        np.savez(path, x=np.arange(60.0).reshape(3, 20), s=np.array([1, 2, 3]))
        mapping = {"signal": "x", "sample_rate_hz": 1000, "labels": {"speed_mm_s": "s"}}
    else:
        path = tmp_path / "r.csv"
        _long_csv(path)
        mapping = {"labels": ["texture"]}
    digest, mtime = _sha256(path), os.stat(path).st_mtime_ns
    out = tmp_path / "out.nc"
    import_file(path, mapping, out)
    with pytest.raises(ImportMappingError):
        import_file(path, {**mapping, "channels": ["a", "b", "c", "d", "e"]}, out)
    assert _sha256(path) == digest and os.stat(path).st_mtime_ns == mtime
    assert load_dataset(out).attrs["source_sha256"] == digest


def test_failed_import_leaves_existing_output_byte_identical(xy_mat, tmp_path) -> None:
    out = tmp_path / "xy.nc"
    out.write_bytes(b"an older dataset")
    for bad in ({**XY_MAPPING, "signal": "nope"}, {**XY_MAPPING, "ragged": "pad"}):
        with pytest.raises(ImportMappingError):
            import_file(xy_mat, bad, out)
        assert out.read_bytes() == b"an older dataset"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data_XY.mat", "xy.nc"]


# ----------------------------------------------------------------------------- shipped example


def test_shipped_example_is_a_data_xy_layout_mat_v5() -> None:
    assert example_names() == [EXAMPLE_MAPPING, EXAMPLE_RECORDING]
    path = example_path(EXAMPLE_RECORDING)
    assert path.stat().st_size < 200_000
    raw = scipy.io.loadmat(path)
    assert raw["__header__"].startswith(b"MATLAB 5.0 MAT-file")
    assert sorted(k for k in raw if not k.startswith("__")) == ["data"]
    cells = raw["data"]
    assert cells.dtype == object and cells.shape == (4, 3, 5)
    for c in cells.flat:
        assert c.shape == (750, 2) and c.dtype == np.float64
    with pytest.raises(FileNotFoundError, match="data_XY_small.mat"):
        example_path("data_XY.mat")
    with pytest.raises(FileNotFoundError):
        example_path("../__init__.py")


def test_shipped_example_imports_with_its_mapping() -> None:
    path = example_path(EXAMPLE_RECORDING)
    digest = _sha256(path)
    ds = import_recording(path, example_path(EXAMPLE_MAPPING))
    assert _sha256(path) == digest
    assert ds.sizes == {"trial": 60, "channel": 2, "time": 750}
    assert list(ds["channel"].values) == ["x", "y"]
    assert ds.attrs["sample_rate_hz"] == 1000.0
    assert "SIMULATED" in ds.attrs["description"]
    np.testing.assert_allclose(ds["time"].values, -0.375 + np.arange(750) / 1000.0, atol=1e-12)
    cells = scipy.io.loadmat(path)["data"]
    sets, speeds, radii = [1, 2, 3, 4], [36.0, 126.0, 216.0], [80.0, 105.0, 130.0, 155.0, 180.0]
    for trial, (i, j, k) in enumerate(np.ndindex(4, 3, 5)):
        assert ds["set"].values[trial] == sets[i]
        assert ds["speed_mm_s"].values[trial] == speeds[j]
        assert ds["radial_distance_mm"].values[trial] == radii[k]
        np.testing.assert_array_equal(ds["signal"].values[trial], cells[i, j, k].T)
    # the labels sit on the right trials physically too: deflection falls with radius
    # and grows with speed in every set, and peaks at the alignment point t = 0
    x = ds["signal"].values
    amp = np.abs(x - x[:, :, :50].mean(axis=2, keepdims=True)).max(axis=(1, 2))
    amp = amp.reshape(4, 3, 5)
    assert np.all(np.diff(amp, axis=2) < 0)
    assert np.all(np.diff(amp, axis=1) > 0)
    peak = np.abs(x - x[:, :, :50].mean(axis=2, keepdims=True)).max(axis=1).argmax(axis=1)
    assert np.mean(ds["time"].values[peak] == 0.0) > 0.9
