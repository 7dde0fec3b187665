"""Checks and builders shared by the importer tests."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import xarray as xr
from data_recordings import N_SAMPLES, RADII, SETS, SPEEDS, cell_recording


def check_xy(ds: xr.Dataset, shape: tuple[int, int, int] = (4, 3, 5)) -> None:
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


def write_long_csv(
    path: Path, n_trials: int = 3, n: int = 8, shuffle: bool = False, bad_label: bool = False
) -> None:
    """A long-layout CSV: ``n`` samples at 250 Hz per trial, speed and texture label columns.

    Trial 1 has texture P180, the others P80; ``shuffle`` reverses the rows and
    ``bad_label`` changes the texture of one sample of trial 2.
    """
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


def sha256_hex(path: Path) -> str:
    """SHA-256 of a file's bytes (hex)."""
    return hashlib.sha256(path.read_bytes()).hexdigest()
