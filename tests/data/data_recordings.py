"""Builders of recordings in the layouts users hold (MATLAB data_XY and friends)."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

#: reduced data_XY grid: 4 sets x 3 speeds x 5 radii, each cell 750 x 2 at 1 kHz
SETS = [1, 2, 3, 4]
SPEEDS = [36.0, 43.2, 50.4]
RADII = [80.0, 81.0, 82.0, 83.0, 84.0]
N_SAMPLES = 750

XY_MAPPING = {
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


def cell_recording(i: int, j: int, k: int, n: int = N_SAMPLES) -> np.ndarray:
    """A samples x channels array whose values encode its cell (i, j, k) and the sample."""
    code = 10000.0 * i + 100.0 * j + k
    t = np.arange(n) / 1000.0
    return np.column_stack([code + t, -code - t])


def xy_cells(shape: tuple[int, int, int] = (4, 3, 5)) -> np.ndarray:
    cells = np.empty(shape, dtype=object)
    for idx in np.ndindex(shape):
        cells[idx] = cell_recording(*idx)
    return cells


def write_mat73(path: Path, variables: dict[str, object]) -> Path:
    """Write ``variables`` the way MATLAB's ``save -v7.3`` lays them out.

    Numeric arrays are stored transposed with ``MATLAB_class``; object arrays
    become cell arrays of references into ``#refs#``; strings become ``char``
    (uint16, transposed); dicts become struct groups; empty arrays are dims
    vectors flagged ``MATLAB_empty``.
    """
    with h5py.File(path, "w", userblock_size=512) as f:
        refs = f.create_group("#refs#")
        counter = [0]

        def put(group: h5py.Group, name: str, value: object) -> h5py.Dataset | h5py.Group:
            if isinstance(value, dict):
                g = group.create_group(name)
                g.attrs["MATLAB_class"] = np.bytes_("struct")
                for k, v in value.items():
                    put(g, k, v)
                return g
            if isinstance(value, str):
                codes = np.array([[ord(c) for c in value]], dtype=np.uint16)  # 1 x n
                d = group.create_dataset(name, data=codes.T)
                d.attrs["MATLAB_class"] = np.bytes_("char")
                return d
            arr = np.asarray(value)
            if arr.dtype == object:
                ref_arr = np.empty(arr.shape, dtype=h5py.ref_dtype)
                for idx in np.ndindex(arr.shape):
                    counter[0] += 1
                    target = put(refs, f"r{counter[0]}", arr[idx])
                    ref_arr[idx] = target.ref
                d = group.create_dataset(name, data=ref_arr.T, dtype=h5py.ref_dtype)
                d.attrs["MATLAB_class"] = np.bytes_("cell")
                return d
            if arr.size == 0:
                d = group.create_dataset(name, data=np.array(arr.shape, dtype=np.uint64))
                d.attrs["MATLAB_class"] = np.bytes_("double")
                d.attrs["MATLAB_empty"] = np.uint8(1)
                return d
            arr2 = np.atleast_2d(arr)
            d = group.create_dataset(name, data=arr2.T)
            d.attrs["MATLAB_class"] = np.bytes_(
                "logical"
                if arr.dtype == bool
                else "double"
                if arr.dtype.kind == "f"
                else str(arr.dtype)
            )
            return d

        for name, value in variables.items():
            put(f, name, value)
    with open(path, "r+b") as fh:  # MATLAB's text header in the user block
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2011")
    return path
