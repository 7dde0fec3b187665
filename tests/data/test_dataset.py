"""Tests of the Dataset schema helpers (vibrissa.data.dataset)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from vibrissa.data import (
    as_arrays,
    concat_datasets,
    encode_texture,
    label_names,
    make_dataset,
    select,
    validate_dataset,
    whisker_params,
)


def _grid(n_r: int = 3, n_s: int = 2, n_t: int = 20, offset: float = 0.0) -> xr.Dataset:
    r = np.repeat(80.0 + np.arange(n_r), n_s)
    s = np.tile(36.0 + 7.2 * np.arange(n_s), n_r)
    n = n_r * n_s
    sig = np.arange(n * 2 * n_t, dtype=float).reshape(n, 2, n_t) + offset
    return make_dataset(
        sig,
        sample_rate_hz=1000.0,
        channels=["x", "y"],
        labels={"radial_distance_mm": r, "speed_mm_s": s, "texture": ["P80"] * n},
        attrs={"whisker": {"length_mm": 185.0}, "protocol": "test", "seed": 3, "robot": None},
    )


def test_make_dataset_schema() -> None:
    ds = _grid()
    assert ds["signal"].dims == ("trial", "channel", "time")
    assert ds["signal"].dtype == np.float64
    assert ds["signal"].attrs["units"] == "V"
    assert list(ds["channel"].values) == ["x", "y"]
    np.testing.assert_allclose(ds["time"].values, np.arange(20) / 1000.0)
    assert ds.attrs["sample_rate_hz"] == 1000.0
    assert json.loads(ds.attrs["whisker"]) == {"length_mm": 185.0}
    assert whisker_params(ds) == {"length_mm": 185.0}
    assert "robot" not in ds.attrs  # None dropped
    assert ds.attrs["vibrissa_version"]
    assert label_names(ds) == ["radial_distance_mm", "speed_mm_s", "texture"]
    assert ds["texture"].dtype.kind == "U"
    # trial k keeps its own signal and labels
    assert ds["signal"].values[1, 0, 0] == 40.0
    assert ds["speed_mm_s"].values[1] == pytest.approx(43.2)


def test_make_dataset_defaults_and_explicit_time() -> None:
    ds = make_dataset(np.zeros((2, 5)), sample_rate_hz=4000)
    assert ds.sizes == {"trial": 2, "channel": 1, "time": 5}
    assert list(ds["channel"].values) == ["x"]
    np.testing.assert_allclose(ds["time"].values, np.arange(5) / 4000)
    t = np.linspace(-0.002, 0.002, 5)
    ds = make_dataset(np.zeros((2, 1, 5)), sample_rate_hz=1000, time=t)
    np.testing.assert_allclose(ds["time"].values, t)
    ds = make_dataset(np.zeros((1, 4, 3)), sample_rate_hz=1)
    assert list(ds["channel"].values) == ["ch0", "ch1", "ch2", "ch3"]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"signal": np.zeros(5)}, "shape"),
        ({"signal": np.zeros((2, 1, 5)) + 1j}, "real"),
        ({"signal": np.full((2, 1, 5), np.nan)}, "NaN"),
        ({"sample_rate_hz": 0.0}, "sample_rate_hz"),
        ({"sample_rate_hz": float("nan")}, "sample_rate_hz"),
        ({"channels": ["x", "y"]}, "channel"),
        ({"time": np.arange(4.0)}, "time"),
        ({"time": np.zeros(5)}, "increasing"),
        ({"labels": {"speed_mm_s": [1.0, 2.0, 3.0]}}, "speed_mm_s"),
        ({"labels": {"speed_mm_s": [[1.0], [2.0]]}}, "speed_mm_s"),
        ({"labels": {"time": [1, 2]}}, "reserved"),
    ],
)
def test_make_dataset_rejects(kwargs, match) -> None:
    args = {"signal": np.zeros((2, 1, 5)), "sample_rate_hz": 1000.0}
    args.update(kwargs)
    sig = args.pop("signal")
    with pytest.raises(ValueError, match=match):
        make_dataset(sig, **args)


def test_validate_dataset_names_the_problem() -> None:
    ds = _grid()
    assert validate_dataset(ds) is ds
    with pytest.raises(TypeError):
        validate_dataset(ds["signal"])
    with pytest.raises(ValueError, match="no 'signal'"):
        validate_dataset(ds.rename({"signal": "sig"}))
    with pytest.raises(ValueError, match="dims"):
        validate_dataset(ds.transpose("trial", "time", "channel"))
    bad = ds.copy(deep=True)
    bad["signal"].values[0, 0, 3] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        validate_dataset(bad)
    bad = ds.copy()
    bad.attrs["sample_rate_hz"] = -5
    with pytest.raises(ValueError, match="sample_rate_hz"):
        validate_dataset(bad)
    bad.attrs.pop("sample_rate_hz")
    with pytest.raises(ValueError, match="sample_rate_hz"):
        validate_dataset(bad)
    with pytest.raises(ValueError, match="'time'"):
        validate_dataset(ds.drop_vars("time"))
    with pytest.raises(ValueError, match="'channel'"):
        validate_dataset(ds.drop_vars("channel"))
    with pytest.raises(ValueError, match="floating"):
        validate_dataset(ds.assign(signal=ds["signal"].astype(int)))
    with pytest.raises(ValueError, match="label 'oops'"):
        validate_dataset(ds.assign_coords(oops=(("trial", "time"), np.zeros((6, 20)))))


def test_as_arrays() -> None:
    ds = _grid()
    X, y = as_arrays(ds, ["radial_distance_mm", "speed_mm_s"])
    assert X.shape == (6, 2, 20) and y.shape == (6, 2)
    assert y.dtype == float
    np.testing.assert_array_equal(X, ds["signal"].values)
    np.testing.assert_allclose(y[:, 0], ds["radial_distance_mm"].values)
    np.testing.assert_allclose(y[:, 1], ds["speed_mm_s"].values)
    _, y1 = as_arrays(ds, "speed_mm_s")
    assert y1.shape == (6, 1)
    # numeric labels stay numeric beside strings (issue 13: every label became a string)
    _, ys = as_arrays(ds, ["texture", "speed_mm_s"])
    assert ys.dtype == object and ys[0, 0] == "P80"
    assert isinstance(ys[0, 1], float) and ys[0, 1] == ds["speed_mm_s"].values[0]
    _, yt = as_arrays(ds, ["texture"])
    assert yt.dtype.kind == "U"
    lower = ds.assign_coords(texture=("trial", np.char.lower(ds["texture"].values.astype(str))))
    _, ye = as_arrays(lower, ["speed_mm_s", "texture"], encode_textures=True)
    assert ye.dtype == float and ye[0, 1] == encode_texture(["p80"])[0]
    with pytest.raises(ValueError, match="unknown texture"):
        as_arrays(ds, ["texture"], encode_textures=True)
    _, y0 = as_arrays(ds, [])
    assert y0.shape == (6, 0)
    with pytest.raises(KeyError, match="angle_deg"):
        as_arrays(ds, ["angle_deg"])


def test_select() -> None:
    ds = _grid()
    sub = select(ds, speed_mm_s=43.2)  # 36 + 7.2 is not bit-equal to 43.2
    assert sub.sizes["trial"] == 3
    assert np.allclose(sub["speed_mm_s"].values, 43.2)
    sub = select(ds, radial_distance_mm=[80, 82], speed_mm_s=36)
    assert list(sub["radial_distance_mm"].values) == [80.0, 82.0]
    np.testing.assert_array_equal(sub["signal"].values, ds["signal"].values[[0, 4]])
    assert select(ds, texture="P80").sizes["trial"] == 6
    assert select(ds, texture="P600").sizes["trial"] == 0
    assert select(ds, radial_distance_mm=lambda r: r > 80.5).sizes["trial"] == 4
    with pytest.raises(KeyError, match="angle_deg"):
        select(ds, angle_deg=10)


def test_concat_datasets() -> None:
    a, b = _grid(), _grid(n_r=2, offset=1000.0)
    ab = concat_datasets([a, b])
    assert ab.sizes["trial"] == 10
    np.testing.assert_array_equal(ab["trial"].values, np.arange(10))
    np.testing.assert_array_equal(ab["signal"].values[6:], b["signal"].values)
    np.testing.assert_array_equal(
        ab["radial_distance_mm"].values,
        np.concatenate([a["radial_distance_mm"].values, b["radial_distance_mm"].values]),
    )
    assert ab.attrs["protocol"] == "test"
    validate_dataset(ab)


def test_concat_datasets_rejects_mismatches() -> None:
    a = _grid()
    with pytest.raises(ValueError, match="no datasets"):
        concat_datasets([])
    with pytest.raises(ValueError, match="time"):
        concat_datasets([a, _grid(n_t=21)])
    other_rate = a.copy()
    other_rate.attrs = dict(a.attrs, sample_rate_hz=2000.0)
    with pytest.raises(ValueError, match="sample rate"):
        concat_datasets([a, other_rate])
    with pytest.raises(ValueError, match="channels"):
        concat_datasets([a, a.assign_coords(channel=["u", "v"])])
    with pytest.raises(ValueError, match="labels"):
        concat_datasets([a, a.drop_vars("texture")])


def test_make_dataset_coordinates_carry_units_and_long_name() -> None:
    from vibrissa.data.dataset import coordinate_attrs

    ds = make_dataset(
        np.zeros((2, 2, 4)),
        sample_rate_hz=1000.0,
        labels={
            "radial_distance_mm": [80.0, 90.0],
            "speed_mm_s": [36.0, 36.0],
            "angle_deg": [0, 45],
            "texture": ["p80", "p600"],
            "set": [1, 2],
            "depth_um": [1, 2],
            "pole_offset_mm": [1.0, 2.0],
            "note_s": ["a", "b"],
        },
    )
    want = {
        "trial": "1",
        "time": "s",
        "radial_distance_mm": "mm",
        "speed_mm_s": "mm/s",
        "angle_deg": "degree",
        "set": "1",
        "pole_offset_mm": "mm",
    }
    for name, units in want.items():
        assert ds[name].attrs["units"] == units, name
    for name in ds.coords:
        assert ds[name].attrs["long_name"], name
    for name in ("channel", "texture", "depth_um", "note_s"):  # text, or a unit not known
        assert "units" not in ds[name].attrs, name
    assert ds["time"].attrs["long_name"] == "time from the alignment point"
    assert coordinate_attrs("latency_s") == {
        "long_name": "latency of the robot's response",
        "units": "s",
    }
