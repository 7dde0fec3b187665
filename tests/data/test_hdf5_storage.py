"""Tests of vibrissa.data.hdf5_storage (HDF5 files that take data from elsewhere)."""

from __future__ import annotations

import h5py
import numpy as np

from vibrissa.data.hdf5_storage import foreign_storage


def _found(path) -> str | None:
    with h5py.File(path, "r") as f:
        return foreign_storage(f)


def test_a_self_contained_file_has_none(tmp_path) -> None:
    with h5py.File(tmp_path / "ok.h5", "w") as f:
        f["a"] = np.arange(3)
        f["g/h/deep"] = 1.0
        f["soft"] = h5py.SoftLink("/a")  # inside the file
        f["dangling"] = h5py.SoftLink("/nowhere")
        f.create_dataset("chunked", data=np.ones((4, 4)), chunks=(2, 2), compression="gzip")
    assert _found(tmp_path / "ok.h5") is None


def test_each_indirection_is_named_with_where_it_points(tmp_path) -> None:
    (tmp_path / "raw.bin").write_bytes(np.arange(4.0).tobytes())
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = np.arange(4.0)
    with h5py.File(tmp_path / "ext.h5", "w") as f:
        f.create_dataset("g/d", shape=(4,), dtype="<f8", external=[("raw.bin", 0, 32)])
    with h5py.File(tmp_path / "link.h5", "w") as f:
        f["g/sub/b"] = h5py.ExternalLink("other.h5", "/x")
    with h5py.File(tmp_path / "vds.h5", "w") as f:
        layout = h5py.VirtualLayout(shape=(4,), dtype="<f8")
        layout[:] = h5py.VirtualSource("other.h5", "x", shape=(4,))
        f.create_virtual_dataset("v", layout)
    assert _found(tmp_path / "ext.h5") == "dataset '/g/d' with external storage in raw.bin"
    assert _found(tmp_path / "link.h5") == "an external link '/g/sub/b' to other.h5:/x"
    assert _found(tmp_path / "vds.h5") == "virtual dataset '/v' mapped onto other.h5"
