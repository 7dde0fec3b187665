"""Tests of `vibrissa plot`."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()


def _dataset() -> xr.Dataset:
    t = np.arange(-20, 40) / 1000.0
    rows = [(r, s, k) for k in (0, 1) for r in (80.0, 120.0, 160.0) for s in (36.0, 72.0, 108.0)]
    pulses = [2.5 + (100 / r) * np.exp(-0.5 * (t / (0.004 * 72 / s)) ** 2) for r, s, _ in rows]
    sig = np.stack([np.stack([x, np.full_like(t, 2.5)]) for x in pulses])
    return xr.Dataset(
        {"signal": (("trial", "channel", "time"), sig, {"units": "V"})},
        coords={
            "channel": ["x", "y"],
            "time": t,
            "radial_distance_mm": ("trial", [r[0] for r in rows]),
            "speed_mm_s": ("trial", [r[1] for r in rows]),
            "set": ("trial", [r[2] for r in rows]),
        },
        attrs={"sample_rate_hz": 1000.0, "whisker": "{}"},
    )


def _save(ds: xr.Dataset, path) -> None:
    try:
        from vibrissa.data import save_dataset
    except ImportError:
        ds.to_netcdf(path)
    else:
        save_dataset(ds, path)


@pytest.fixture(scope="module")
def nc(tmp_path_factory):
    path = tmp_path_factory.mktemp("plot") / "grid.nc"
    _save(_dataset(), path)
    return path


def test_plot_all_writes_pngs(nc, tmp_path) -> None:
    res = runner.invoke(app, ["plot", str(nc), "--out", str(tmp_path / "figs")])
    assert res.exit_code == 0, res.output
    written = json.loads(res.stdout)["written"]
    assert sorted(p.rsplit("/", 1)[-1] for p in written) == ["contours.png", "traces.png"]
    for p in written:
        data = open(p, "rb").read()
        assert data[:4] == b"\x89PNG" and len(data) > 1000


def test_plot_kind_and_channel(nc, tmp_path) -> None:
    res = runner.invoke(
        app, ["plot", str(nc), "--out", str(tmp_path), "--kind", "traces", "--channel", "x"]
    )
    assert res.exit_code == 0, res.output
    assert [p.rsplit("/", 1)[-1] for p in json.loads(res.stdout)["written"]] == ["traces.png"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--kind", "bars"], "--kind must be one of"),
        (["--channel", "z"], "--channel must be an index in [0, 1] or a name (x, y)"),
    ],
)
def test_plot_bad_options_exit_2(nc, tmp_path, args, message) -> None:
    res = runner.invoke(app, ["plot", str(nc), "--out", str(tmp_path), *args])
    assert res.exit_code == 2
    assert message in res.stderr and len(res.stderr.strip().splitlines()) == 1


def test_plot_missing_file_exit_2(tmp_path) -> None:
    res = runner.invoke(app, ["plot", str(tmp_path / "nope.nc"), "--out", str(tmp_path)])
    assert res.exit_code == 2
    assert res.stderr.startswith("error:") and "nope.nc" in res.stderr


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda r, s: (np.where(r == 120.0, np.nan, r), s), "radial_distance_mm holds NaN"),
        (lambda r, s: (r, np.full_like(s, 72.0)), "at least two different speed_mm_s values"),
    ],
)
def test_contours_over_labels_they_cannot_be_drawn_over_are_refused(tmp_path, edit, message):
    # both gave a blank contour map before
    ds = _dataset()
    r, s = edit(ds["radial_distance_mm"].values, ds["speed_mm_s"].values)
    ds = ds.assign_coords(radial_distance_mm=("trial", r), speed_mm_s=("trial", s))
    path = tmp_path / "odd.nc"
    _save(ds, path)
    out = tmp_path / "figs"
    res = runner.invoke(app, ["plot", str(path), "--out", str(out), "--kind", "contours"])
    assert res.exit_code == 2, res.output
    assert message in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert not out.exists()
