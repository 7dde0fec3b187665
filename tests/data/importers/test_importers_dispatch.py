"""Tests of the entry points: format, errors, output (vibrissa.data.importers.dispatch)."""

from __future__ import annotations

import os

import numpy as np
import pytest
import scipy.io
from data_recordings import XY_MAPPING, write_mat73, xy_cells
from importer_checks import check_xy, sha256_hex, write_long_csv

from vibrissa.data import import_file, import_recording, load_dataset
from vibrissa.data.importers import ImportMappingError, detect_format


def test_import_file_round_trip_and_leaves_source_alone(xy_mat, tmp_path) -> None:
    before = xy_mat.read_bytes()
    mtime = os.stat(xy_mat).st_mtime_ns
    out = tmp_path / "out" / "xy.nc"
    ds = import_file(xy_mat, XY_MAPPING, out)
    assert xy_mat.read_bytes() == before
    assert os.stat(xy_mat).st_mtime_ns == mtime
    back = load_dataset(out)
    check_xy(back)
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


def test_failed_import_leaves_existing_output_byte_identical(xy_mat, tmp_path) -> None:
    out = tmp_path / "xy.nc"
    out.write_bytes(b"an older dataset")
    for bad in ({**XY_MAPPING, "signal": "nope"}, {**XY_MAPPING, "ragged": "pad"}):
        with pytest.raises(ImportMappingError):
            import_file(xy_mat, bad, out)
        assert out.read_bytes() == b"an older dataset"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data_XY.mat", "xy.nc"]


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
        write_long_csv(path)
        mapping = {"labels": ["texture"]}
    digest, mtime = sha256_hex(path), os.stat(path).st_mtime_ns
    out = tmp_path / "out.nc"
    import_file(path, mapping, out)
    with pytest.raises(ImportMappingError):
        import_file(path, {**mapping, "channels": ["a", "b", "c", "d", "e"]}, out)
    assert sha256_hex(path) == digest and os.stat(path).st_mtime_ns == mtime
    assert load_dataset(out).attrs["source_sha256"] == digest


# ---------------------------------------------------------------------- errors


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


def test_errors_are_import_mapping_errors(xy_mat, tmp_path) -> None:
    assert issubclass(ImportMappingError, ValueError)
    cases = [
        ({**XY_MAPPING, "signals": "data"}, "unknown mapping key"),
        ({**XY_MAPPING, "channels": "x,x"}, "repeated"),
        ({**XY_MAPPING, "sample_rate_hz": True}, "sample_rate_hz"),
        ({**XY_MAPPING, "cell_axes": "set"}, "cell_axes"),
        ({**XY_MAPPING, "signal": "nope"}, "no variable 'nope'"),
        ({**XY_MAPPING, "constants": {"time": 1}}, "reserved"),
        (
            {**XY_MAPPING, "cell_axes": [{"name": "set", "values": [1, 2]}, "b", "c"]},
            r"'set'\) has 2 values but signal 'data' \(a 4 x 3 x 5 cell array\) has 4",
        ),
    ]
    for mapping, match in cases:
        with pytest.raises(ImportMappingError, match=match):
            import_recording(xy_mat, mapping)
    xls = tmp_path / "data_XY.xls"
    xls.write_bytes(b"not a recording")
    with pytest.raises(ImportMappingError, match="cannot tell the file type"):
        import_recording(xls, XY_MAPPING)
