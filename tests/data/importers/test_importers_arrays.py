"""Tests of cell and numeric arrays -> trials, and NPZ files (vibrissa.data.importers.arrays)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io
from data_recordings import SETS, SPEEDS, XY_MAPPING, cell_recording, write_mat73, xy_cells
from importer_checks import check_xy

from vibrissa.data import import_recording
from vibrissa.data.importers import ImportMappingError

# ------------------------------------------------------- trial axes and labels


def test_axis_values_from_file_variable(tmp_path) -> None:
    path = tmp_path / "a.mat"
    scipy.io.savemat(path, {"data": xy_cells(), "speeds": np.array([SPEEDS])})
    mapping = json.loads(json.dumps(XY_MAPPING))
    mapping["cell_axes"][1] = {"name": "speed_mm_s", "from": "speeds"}
    check_xy(import_recording(path, mapping))


def test_axis_sizes_must_match_the_file(xy_mat) -> None:
    bad = {
        **XY_MAPPING,
        "cell_axes": [
            {"name": "set", "values": SETS},
            {"name": "speed_mm_s", "start": 36, "stop": 216, "num": 26},
            {"name": "radial_distance_mm", "start": 80, "step": 1},
        ],
    }
    with pytest.raises(
        ValueError,
        match=r"'speed_mm_s'\) has 26 values but signal 'data' \(a "
        r"4 x 3 x 5 cell array\) has 3",
    ):
        import_recording(xy_mat, bad)
    with pytest.raises(ValueError, match="4 x 3 x 5 cell array but the mapping's cell_axes has 2"):
        import_recording(xy_mat, {**XY_MAPPING, "cell_axes": XY_MAPPING["cell_axes"][:2]})
    stop_wrong = json.loads(json.dumps(XY_MAPPING))
    stop_wrong["cell_axes"][2] = {"name": "radial_distance_mm", "start": 80, "step": 1, "stop": 180}
    with pytest.raises(ValueError, match="end at 84, not at 'stop' 180"):
        import_recording(xy_mat, stop_wrong)


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
    np.testing.assert_array_equal(
        np.unique(ds["radial_distance_mm"].values), np.arange(80.0, 181.0)
    )
    # trial n is cell n in C order (set, speed, radius), transposed to channels x samples
    np.testing.assert_array_equal(ds["signal"].values[:, 0, 0], np.arange(10504.0))
    np.testing.assert_array_equal(ds["signal"].values[:, 1, 3], -np.arange(10504.0))
    t = np.ravel_multi_index((2, 5, 17), (4, 26, 101))
    assert (
        ds["set"].values[t],
        ds["speed_mm_s"].values[t],
        ds["radial_distance_mm"].values[t],
    ) == (3, 72.0, 97.0)


# --------------------------------- recordings: ragged, empty, non-numeric, NaN


def test_ragged_cells_error_or_crop(tmp_path) -> None:
    cells = xy_cells((1, 2, 3))
    cells[0, 1, 2] = cell_recording(0, 1, 2, n=740)
    path = tmp_path / "ragged.mat"
    scipy.io.savemat(path, {"data": cells})
    mapping = {
        "signal": "data",
        "sample_rate_hz": 1000,
        "cell_axes": ["set", "speed_mm_s", "radial_distance_mm"],
    }
    with pytest.raises(
        ValueError,
        match=r"cell data\{1,2,3\} has 740 samples but "
        r"cell data\{1,1,1\} has 750",
    ):
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
        import_recording(
            path, {"signal": "data", "sample_rate_hz": 1000, "cell_axes": ["a", "b", "c"]}
        )
    csv = tmp_path / "nan.csv"
    csv.write_text("trial,x,y\n0,1,2\n0,1,2\n1,1,2\n1,,2\n1,nan,inf\n")
    with pytest.raises(
        ImportMappingError,
        match=r"trial 1 of nan.csv has 3 empty, NaN or "
        r"infinite .* column 'x' on line 5",
    ):
        import_recording(csv, {"sample_rate_hz": 10})


# -------------------------------------------------------------- numeric arrays


def test_matlab_numeric_array_with_trials_last(tmp_path) -> None:
    # samples x channels x trials, as MATLAB users often store recordings
    data = np.stack([cell_recording(0, 0, k, n=40) for k in range(3)], axis=-1)
    assert data.shape == (40, 2, 3)
    mapping = {
        "signal": "data",
        "sample_rate_hz": 1000,
        "trial_axes": "last",
        "cell_axes": [{"name": "radial_distance_mm", "values": [80.0, 90.0, 100.0]}],
    }
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


# ------------------------------------------------------------------------- NPZ


def test_npz_trial_time_channel_and_grid(tmp_path) -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(size=(6, 100, 2))
    p = tmp_path / "r.npz"
    np.savez(p, x=x, speeds=np.arange(6) * 10.0, tex=np.array(list("abcabc")))
    ds = import_recording(
        p,
        {
            "signal": "x",
            "sample_rate_hz": 100,
            "labels": {"speed_mm_s": "speeds", "texture": "tex"},
        },
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
    ds3 = import_recording(
        pg,
        {
            "sample_rate_hz": 1000,
            "cell_axes": [
                {"name": "set", "values": [1, 2]},
                {"name": "speed_mm_s", "values": [6, 16, 26]},
            ],
        },
    )
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
        import_recording(p2, {"signal": "x", "sample_rate_hz": 1, "labels": {"speed_mm_s": "lab"}})
    with pytest.raises(ValueError, match="holds variables"):
        np.savez(p2, x=np.zeros((3, 10)), y=np.zeros((3, 10)))
        import_recording(p2, {"sample_rate_hz": 1})
    with pytest.raises(ValueError, match="do not apply to npz"):
        import_recording(p2, {"signal": "x", "sample_rate_hz": 1, "layout": "wide"})
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"PK not really a zip")
    with pytest.raises(ValueError, match="bad.npz"):
        import_recording(bad, {"signal": "x", "sample_rate_hz": 1})
