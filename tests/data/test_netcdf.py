"""Tests of checksummed atomic NetCDF storage (vibrissa.data.netcdf)."""

from __future__ import annotations

import os

import h5py
import numpy as np
import pytest
import xarray as xr

from vibrissa.data import DatasetFileError, checksum, load_dataset, make_dataset, save_dataset


def _ds() -> xr.Dataset:
    rng = np.random.default_rng(0)
    n = 6
    return make_dataset(
        rng.normal(2.5, 0.1, (n, 2, 300)),
        sample_rate_hz=1000.0,
        time=(np.arange(300) - 150) / 1000.0,
        labels={
            "radial_distance_mm": np.linspace(80, 180, n),
            "speed_mm_s": np.full(n, 43.2),
            "texture": ["aluminium", "P600", "P180", "P80", "P80", "é-ß"],
            "direction": [1, -1, 1, -1, 1, -1],
            "set": np.arange(1, n + 1),
        },
        attrs={"whisker": {"length_mm": 185.0}, "protocol": "t", "seed": 7, "flag": True},
    )


def test_round_trip_is_identical(tmp_path) -> None:
    ds = _ds()
    path = save_dataset(ds, tmp_path / "a.nc")
    back = load_dataset(path)
    xr.testing.assert_identical(back.drop_attrs(), ds.drop_attrs())
    assert back["texture"].dtype.kind == "U"
    assert list(back["texture"].values) == list(ds["texture"].values)
    assert back["direction"].dtype == np.int64
    assert back.attrs["flag"] == 1
    assert back.attrs["whisker"] == ds.attrs["whisker"]
    assert "vibrissa_checksum" not in back.attrs
    with h5py.File(path) as f:
        assert f.attrs["vibrissa_checksum"] == checksum(ds)


def test_checksum_covers_signal_and_labels() -> None:
    ds = _ds()
    c = checksum(ds)
    assert c == checksum(ds.copy(deep=True))
    sig = ds.copy(deep=True)
    sig["signal"].values[3, 1, 7] += 1e-12
    assert checksum(sig) != c
    assert checksum(ds.assign_coords(texture=("trial", ["x"] * 6))) != c
    assert checksum(ds.assign_coords(speed_mm_s=("trial", np.full(6, 43.3)))) != c


def test_save_is_atomic_and_keeps_old_file_on_failure(tmp_path) -> None:
    path = tmp_path / "a.nc"
    save_dataset(_ds(), path)
    before = path.read_bytes()
    bad = _ds()
    bad.attrs["unstorable"] = object()
    with pytest.raises(TypeError):
        save_dataset(bad, path)
    assert path.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["a.nc"]  # no temporary left behind
    with pytest.raises(ValueError, match="NaN"):
        save_dataset(_ds().where(lambda d: d.time < 0.1), path)
    assert path.read_bytes() == before


def test_missing_file(tmp_path) -> None:
    with pytest.raises(DatasetFileError, match="no such file") as err:
        load_dataset(tmp_path / "nope.nc")
    assert err.value.path == tmp_path / "nope.nc"
    assert str(tmp_path / "nope.nc") in str(err.value)
    with pytest.raises(DatasetFileError, match="directory"):
        load_dataset(tmp_path)


def test_not_a_netcdf_file(tmp_path) -> None:
    p = tmp_path / "x.nc"
    p.write_text("trial,time,x\n0,0,1\n")
    with pytest.raises(DatasetFileError, match="not a NetCDF") as err:
        load_dataset(p)
    assert str(p) in str(err.value)
    p.write_bytes(b"")
    with pytest.raises(DatasetFileError, match="not a NetCDF"):
        load_dataset(p)


def test_truncated_file(tmp_path) -> None:
    p = save_dataset(_ds(), tmp_path / "a.nc")
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(DatasetFileError, match="a.nc") as err:
        load_dataset(p)
    assert isinstance(err.value, ValueError)


def test_checksum_mismatch(tmp_path) -> None:
    ds = _ds()
    p = save_dataset(ds, tmp_path / "a.nc")
    # rewrite one value of the signal in place, keeping the old checksum attribute
    with h5py.File(p, "r+") as f:
        f["signal"][2, 0, 10] = f["signal"][2, 0, 10] + 0.5
    with pytest.raises(DatasetFileError, match="checksum mismatch"):
        load_dataset(p)
    # a changed label is caught too
    p2 = save_dataset(ds, tmp_path / "b.nc")
    with h5py.File(p2, "r+") as f:
        f["radial_distance_mm"][0] = 81.0
    with pytest.raises(DatasetFileError, match="checksum"):
        load_dataset(p2)


def test_missing_variables(tmp_path) -> None:
    p = tmp_path / "other.nc"
    xr.Dataset({"foo": ("a", np.arange(3.0))}).to_netcdf(p, engine="h5netcdf")
    with pytest.raises(DatasetFileError, match="no 'signal'"):
        load_dataset(p)


def test_foreign_file_without_checksum_is_accepted(tmp_path) -> None:
    ds = _ds()
    p = tmp_path / "plain.nc"
    ds.to_netcdf(p, engine="h5netcdf")
    back = load_dataset(p)
    np.testing.assert_array_equal(back["signal"].values, ds["signal"].values)
    p3 = tmp_path / "classic.nc"
    ds.drop_vars("texture").to_netcdf(p3, engine="scipy")
    back = load_dataset(p3)
    np.testing.assert_array_equal(back["signal"].values, ds["signal"].values)


def test_error_pickles() -> None:
    import pickle

    err = pickle.loads(pickle.dumps(DatasetFileError("/a/b.nc", "bad")))
    assert str(err) == "/a/b.nc: bad" and err.problem == "bad"
