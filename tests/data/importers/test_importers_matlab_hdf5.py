"""Tests of MATLAB v7.3 (HDF5) files (vibrissa.data.importers.matlab_hdf5)."""

from __future__ import annotations

import numpy as np
import pytest
from data_recordings import XY_MAPPING, cell_recording, write_mat73, xy_cells
from importer_checks import check_xy

from vibrissa.data import import_recording
from vibrissa.data.importers import ImportMappingError


def test_mat_v73_hdf5_layout_matches_v5(tmp_path, xy_mat) -> None:
    p73 = write_mat73(tmp_path / "data_XY73.mat", {"data": xy_cells()})
    ds73 = import_recording(p73, XY_MAPPING)
    assert ds73.attrs["source_format"] == "mat v7.3"
    check_xy(ds73)
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
        bad[o : o + 64] = rng.integers(0, 256, 64, dtype=np.uint8).tobytes()
        q = tmp_path / "damaged.mat"
        q.write_bytes(bytes(bad))
        try:
            import_recording(q, mapping)
        except ImportMappingError as exc:
            failures += 1
            assert "damaged.mat" in str(exc) or "cell data" in str(exc)
    assert failures > 0


def _add_to_mat73(path, edit) -> None:
    """Open a written v7.3 file and let ``edit`` add to it."""
    import h5py

    with h5py.File(path, "r+") as f:
        edit(f)


@pytest.mark.parametrize("how", ["external storage", "external link", "virtual dataset"])
def test_mat_v73_taking_data_from_outside_the_file_is_refused(tmp_path, how) -> None:
    """Issue 33: the importer read other files' bytes through HDF5 indirections.

    The secret file stands for any file the user can read; it must neither be imported
    nor reach the dataset (on main before this test, the external-storage case imported
    its bytes with ``source_sha256`` covering only the ``.mat``).
    """
    import h5py

    secret = np.arange(20.0).reshape(2, 10)
    (tmp_path / "secret.bin").write_bytes(secret.T.astype("<f8").tobytes())
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = secret.T
    path = write_mat73(tmp_path / "d.mat", {"fs": np.array(1000.0)})

    def edit(f) -> None:
        if how == "external storage":
            outside = [(str(tmp_path / "secret.bin"), 0, 160)]
            d = f.create_dataset("data", shape=(10, 2), dtype="<f8", external=outside)
            d.attrs["MATLAB_class"] = np.bytes_("double")
        elif how == "external link":
            f["data"] = h5py.ExternalLink(str(tmp_path / "other.h5"), "/x")
        else:
            layout = h5py.VirtualLayout(shape=(10, 2), dtype="<f8")
            layout[:] = h5py.VirtualSource(str(tmp_path / "other.h5"), "x", shape=(10, 2))
            f.create_virtual_dataset("data", layout).attrs["MATLAB_class"] = np.bytes_("double")

    _add_to_mat73(path, edit)
    with pytest.raises(ImportMappingError, match=f"takes data from outside the file.*{how}"):
        import_recording(path, {"signal": "data", "sample_rate_hz": "fs", "time_axis": 1})


@pytest.mark.parametrize(
    ("cls", "group", "decode"),
    [
        ("function_handle", True, False),  # MATLAB saves a handle as a group of fields
        ("function_handle", False, False),
        ("string", False, True),  # MCOS objects: uint32 bytes flagged MATLAB_object_decode
        ("double", False, True),
        ("MyClassdef", False, False),
    ],
)
def test_mat_v73_object_classes_are_refused_by_name(tmp_path, cls, group, decode) -> None:
    """Issue 33: a ``function_handle`` was imported though the docs said it is refused."""
    path = write_mat73(tmp_path / "h.mat", {"fs": np.array(1000.0)})

    def edit(f) -> None:
        if group:
            g = f.create_group("data")
            g["function"] = np.arange(10.0).reshape(5, 2)
            g.attrs["MATLAB_class"] = np.bytes_(cls)
            return
        d = f.create_dataset("data", data=np.arange(20.0).reshape(10, 2))
        d.attrs["MATLAB_class"] = np.bytes_(cls)
        if decode:
            d.attrs["MATLAB_object_decode"] = np.int32(3)

    _add_to_mat73(path, edit)
    mapping = {"signal": "data", "sample_rate_hz": "fs", "time_axis": 1}
    with pytest.raises(ImportMappingError, match=r"'data' is a MATLAB .*object class"):
        import_recording(path, mapping)
    if group:  # walking into the handle's fields is refused too
        with pytest.raises(ImportMappingError, match=r"'data' is a MATLAB function_handle"):
            import_recording(path, {**mapping, "signal": "data.function"})
