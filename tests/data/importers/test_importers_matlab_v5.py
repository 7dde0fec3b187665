"""Tests of MATLAB v5 files (vibrissa.data.importers.matlab_v5)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io
from data_recordings import XY_MAPPING, cell_recording
from importer_checks import check_xy, sha256_hex

from vibrissa.data import import_recording, select
from vibrissa.data.importers import ImportMappingError
from vibrissa.examples import EXAMPLE_MAPPING, EXAMPLE_RECORDING, example_names, example_path


def test_mat_v5_data_xy_layout(xy_mat) -> None:
    ds = import_recording(xy_mat, XY_MAPPING)
    check_xy(ds)
    assert ds["set"].dtype.kind == "i"
    assert ds["speed_mm_s"].dtype == np.float64
    assert ds.attrs["protocol"] == "imported"
    assert ds.attrs["source_file"] == "data_XY.mat"
    assert ds.attrs["source_format"] == "mat v5"
    assert json.loads(ds.attrs["import_mapping"]) == XY_MAPPING
    # speeds 36 + 7.2 k are stored as the decimal values a user types
    assert select(ds, speed_mm_s=43.2, set=2).sizes["trial"] == 5
    assert 43.2 in ds["speed_mm_s"].values


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


# ------------------------------------------ shipped example (a MATLAB v5 file)


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
    digest = sha256_hex(path)
    ds = import_recording(path, example_path(EXAMPLE_MAPPING))
    assert sha256_hex(path) == digest
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


@pytest.mark.parametrize("kind", ["MatlabFunction", "MatlabOpaque", "MatlabObject"])
def test_mat_v5_function_handles_and_objects_are_refused(tmp_path, monkeypatch, kind) -> None:
    """What SciPy reads as a function handle or an object is refused by name, not imported.

    SciPy cannot write these classes, so ``loadmat`` is made to return one.
    """
    import scipy.io
    import scipy.io.matlab as mio

    path = tmp_path / "h.mat"
    scipy.io.savemat(path, {"fs": 1000.0})
    arr = np.arange(20.0).reshape(10, 2)
    value = mio.MatlabObject(arr, "MyClass") if kind == "MatlabObject" else getattr(mio, kind)(arr)
    monkeypatch.setattr(scipy.io, "loadmat", lambda *a, **k: {"data": value, "fs": 1000.0})
    mapping = {"signal": "data", "sample_rate_hz": 1000.0, "time_axis": 1}
    with pytest.raises(ImportMappingError, match=r"'data' is a MATLAB (function handle|object)"):
        import_recording(path, mapping)
