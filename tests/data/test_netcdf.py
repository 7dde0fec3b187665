"""Tests of checksummed atomic NetCDF storage (vibrissa.data.netcdf)."""

from __future__ import annotations

import hashlib
import json
import os
import pickle
import subprocess
import sys
import warnings

import h5py
import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from vibrissa.data import DatasetFileError, checksum, load_dataset, make_dataset, save_dataset
from vibrissa.data.netcdf import (
    SCHEMA_VERSION,
    DatasetIntegrityWarning,
    DatasetModifiedError,
    DatasetSchemaError,
    _values_digest,
)


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
        attrs={
            "whisker": {"length_mm": 185.0, "base_radius_mm": 1.0},
            "robot": {"delay_s": 0.3, "speed_mm_s": 43.2},
            "protocol": "t",
            "protocol_params": {"radial_distances_mm": [80.0, 100.0, 180.0], "runs": 1},
            "seed": 7,
            "flag": True,
        },
    )


def test_round_trip_is_identical(tmp_path) -> None:
    ds = _ds()
    path = save_dataset(ds, tmp_path / "a.nc")
    back = load_dataset(path)
    xr.testing.assert_identical(back, ds)
    assert back["texture"].dtype.kind == "U"
    assert list(back["texture"].values) == list(ds["texture"].values)
    assert back["direction"].dtype == np.int64
    assert back.attrs["flag"] == 1
    assert back.attrs["whisker"] == ds.attrs["whisker"]
    assert not {"vibrissa_checksum", "vibrissa_checksum_parts", "vibrissa_schema"} & set(back.attrs)
    with h5py.File(path) as f:
        assert int(np.asarray(f.attrs["vibrissa_schema"]).item()) == SCHEMA_VERSION == 2
        stored = f.attrs["vibrissa_checksum"]
    # the checksum is that of the file's contents as any NetCDF reader sees them
    assert stored == checksum(xr.load_dataset(path, engine="h5netcdf"))
    assert stored == checksum(ds.assign_attrs(vibrissa_schema=SCHEMA_VERSION))
    # saving what was loaded writes the same checksum again
    with h5py.File(save_dataset(back, tmp_path / "b.nc")) as f:
        assert f.attrs["vibrissa_checksum"] == stored


def test_checksum_covers_signal_and_labels() -> None:
    ds = _ds()
    c = checksum(ds)
    assert c == checksum(ds.copy(deep=True))
    sig = ds.copy(deep=True)
    sig["signal"].values[3, 1, 7] += 1e-12
    assert checksum(sig) != c
    assert checksum(ds.assign_coords(texture=("trial", ["x"] * 6))) != c
    assert checksum(ds.assign_coords(speed_mm_s=("trial", np.full(6, 43.3)))) != c
    # ... and every attribute of the dataset and its variables, and the dtypes
    assert checksum(ds.assign_attrs(sample_rate_hz=1001.0)) != c
    assert checksum(ds.assign_attrs(extra="x")) != c
    assert checksum(ds.drop_attrs(deep=False)) != c
    units = ds.copy()
    units["time"].attrs["units"] = "ms"
    assert checksum(units) != c
    assert checksum(ds.assign_coords(set=ds["set"].astype(np.int32))) != c
    # the checksum attributes themselves are not covered
    assert checksum(ds.assign_attrs(vibrissa_checksum="x", vibrissa_checksum_parts="y")) == c


_DTYPES = st.sampled_from(
    ["<f8", ">f8", "<f4", "<i8", ">i4", "|u1", "|b1", "<c16", "<M8[ns]", "<m8[s]"]
)


@settings(max_examples=60, deadline=None)
@given(
    arr=_DTYPES.flatmap(
        lambda dt: hnp.arrays(np.dtype(dt), hnp.array_shapes(min_dims=0, max_side=5))
    ),
    transpose=st.booleans(),
)
def test_values_are_hashed_as_their_little_endian_bytes(arr, transpose) -> None:
    """The digest reads the array's buffer, not a copy of it as bytes (a full grid's
    signal is hundreds of MB); it stays the digest of those bytes, so files written
    before verify the same (any dtype, byte order, shape, contiguity)."""
    vals = arr.T if transpose else arr
    var = xr.DataArray(vals, dims=[f"d{i}" for i in range(vals.ndim)])
    little = vals.dtype.newbyteorder("<") if vals.dtype.byteorder != "|" else vals.dtype
    h = hashlib.sha256()
    h.update(
        json.dumps(
            [[f"d{i}" for i in range(vals.ndim)], list(vals.shape)],
            sort_keys=True,
            separators=(",", ":"),
        ).encode()
    )
    h.update(little.str.encode())
    h.update(np.ascontiguousarray(vals, dtype=little).tobytes())
    assert _values_digest(var) == h.hexdigest()


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
    with pytest.raises(
        DatasetModifiedError,
        match="modified after it was written by vibrissa "
        r"\(checksum mismatch\); differs: data variable 'signal'$",
    ) as err:
        load_dataset(p)
    assert err.value.differs == ("data variable 'signal'",)
    assert "corrupt" not in str(err.value)
    # a changed label is caught too
    p2 = save_dataset(ds, tmp_path / "b.nc")
    with h5py.File(p2, "r+") as f:
        f["radial_distance_mm"][0] = 81.0
    with pytest.raises(DatasetFileError, match="differs: coordinate 'radial_distance_mm'"):
        load_dataset(p2)


def _flip_bit(text: str, old: str, new: str) -> str:
    """``text`` with the first ``old`` replaced by ``new``, checking that one bit differs."""
    i = text.index(old)
    diff = [a ^ b for a, b in zip(old.encode(), new.encode(), strict=True) if a != b]
    assert len(diff) == 1 and bin(diff[0]).count("1") == 1
    return text[:i] + new + text[i + len(old) :]


def _edit_attr(path, name: str, edit) -> None:
    with h5py.File(path, "r+") as f:
        value = f.attrs[name]
        f.attrs[name] = edit(value.decode() if isinstance(value, bytes) else value)


@pytest.mark.parametrize(
    ("attr", "old", "new"),
    [
        ("protocol_params", "100.0", "104.0"),  # radial distance 100 -> 104 mm: '0' -> '4'
        ("robot", "0.3", "0.2"),  # the loop delay
        ("whisker", "length_mm", "lengtl_mm"),  # a key of the whisker
    ],
)
def test_single_bit_flip_in_an_attribute_is_refused(tmp_path, attr, old, new) -> None:
    p = save_dataset(_ds(), tmp_path / "a.nc")
    _edit_attr(p, attr, lambda text: _flip_bit(text, old, new))
    with pytest.raises(DatasetModifiedError) as err:
        load_dataset(p)
    msg = str(err.value)
    assert msg.startswith(f"{p}: was modified after it was written by vibrissa")
    assert err.value.differs == (f"attribute {attr!r}",)
    assert f"differs: attribute {attr!r}" in msg


def test_edited_sample_rate_is_refused(tmp_path) -> None:
    p = save_dataset(_ds(), tmp_path / "a.nc")
    _edit_attr(p, "sample_rate_hz", lambda v: np.asarray(v) * 0 + 1001.0)
    with pytest.raises(DatasetModifiedError, match="differs: attribute 'sample_rate_hz'"):
        load_dataset(p)


def test_added_removed_and_variable_attributes_are_named(tmp_path) -> None:
    p = save_dataset(_ds(), tmp_path / "a.nc")
    with h5py.File(p, "r+") as f:
        del f.attrs["seed"]
        f.attrs["note"] = "added"
        f["time"].attrs["units"] = "ms"
    with pytest.raises(DatasetModifiedError) as err:
        load_dataset(p)
    assert set(err.value.differs) == {
        "attribute 'seed' (removed)",
        "attribute 'note' (added)",
        "attributes of coordinate 'time'",
    }


def test_subset_saved_with_plain_xarray_is_not_called_corrupt(tmp_path) -> None:
    ds = make_dataset(
        np.random.default_rng(1).normal(size=(100, 2, 30)),
        sample_rate_hz=1000,
        labels={"set": np.arange(100) % 4},
    )
    p = save_dataset(ds, tmp_path / "all.nc")
    sub = tmp_path / "sub.nc"
    with xr.open_dataset(p) as f:
        f.isel(trial=slice(0, 40)).to_netcdf(sub)  # keeps the old checksum attribute
    with pytest.raises(DatasetModifiedError) as err:
        load_dataset(sub)
    msg = str(err.value)
    assert "was modified or re-saved outside vibrissa" in msg
    assert "trial=40, channel=2, time=30 but vibrissa wrote trial=100, channel=2, time=30" in msg
    assert "corrupt" not in msg
    # verify=False loads it anyway, saying why
    with pytest.warns(DatasetIntegrityWarning, match="re-saved outside vibrissa.*verify=False"):
        back = load_dataset(sub, verify=False)
    np.testing.assert_array_equal(back["signal"].values, ds["signal"].values[:40])
    assert "vibrissa_checksum" not in back.attrs
    # saved with vibrissa, the subset is a good file of its own
    xr.testing.assert_identical(load_dataset(save_dataset(back, sub)), back)


def test_verify_false_loads_a_modified_file_with_a_warning(tmp_path) -> None:
    ds = _ds()
    p = save_dataset(ds, tmp_path / "a.nc")
    _edit_attr(p, "robot", lambda text: _flip_bit(text, "0.3", "0.2"))
    with pytest.warns(DatasetIntegrityWarning, match="modified after it was written by vibrissa"):
        back = load_dataset(p, verify=False)
    assert json.loads(back.attrs["robot"])["delay_s"] == 0.2
    np.testing.assert_array_equal(back["signal"].values, ds["signal"].values)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_dataset(save_dataset(ds, tmp_path / "b.nc"), verify=False)  # a good file: silent


def test_schema_versions(tmp_path) -> None:
    ds = _ds()
    p = save_dataset(ds, tmp_path / "new.nc")
    with h5py.File(p, "r+") as f:
        f.attrs["vibrissa_schema"] = SCHEMA_VERSION + 1
    with pytest.raises(
        DatasetSchemaError,
        match="newer vibrissa \\(file schema 3, this vibrissa "
        "reads schema 2 and older\\); upgrade vibrissa",
    ) as err:
        load_dataset(p)
    assert err.value.schema == SCHEMA_VERSION + 1
    # a file of vibrissa before schema versions: a checksum, no vibrissa_schema
    old = tmp_path / "old.nc"
    ds.assign_attrs(vibrissa_checksum="0" * 64).to_netcdf(old, engine="h5netcdf")
    with pytest.raises(
        DatasetSchemaError,
        match="older vibrissa \\(file schema 1, this vibrissa "
        "reads schema 2\\).*re-create the file",
    ) as err:
        load_dataset(old)
    assert err.value.schema == 1 and isinstance(err.value, DatasetFileError)
    with pytest.warns(DatasetIntegrityWarning, match="older vibrissa"):
        back = load_dataset(old, verify=False)
    np.testing.assert_array_equal(back["signal"].values, ds["signal"].values)
    with h5py.File(p, "r+") as f:
        f.attrs["vibrissa_schema"] = "two"
    with pytest.raises(DatasetSchemaError, match="unreadable schema version 'two'"):
        load_dataset(p)
    p3 = save_dataset(ds, tmp_path / "c.nc")
    with h5py.File(p3, "r+") as f:
        del f.attrs["vibrissa_checksum"]
    with pytest.raises(DatasetModifiedError, match="re-saved outside vibrissa.*no 'vibrissa_chec"):
        load_dataset(p3)


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
    err = pickle.loads(pickle.dumps(DatasetFileError("/a/b.nc", "bad")))
    assert str(err) == "/a/b.nc: bad" and err.problem == "bad"
    err = pickle.loads(pickle.dumps(DatasetModifiedError("/a/b.nc", "bad", ["attribute 'x'"])))
    assert type(err) is DatasetModifiedError and err.differs == ("attribute 'x'",)
    err = pickle.loads(pickle.dumps(DatasetSchemaError("/a/b.nc", "old", schema=1)))
    assert type(err) is DatasetSchemaError and err.schema == 1 and str(err) == "/a/b.nc: old"


# --- property: save -> load gives back exactly what was saved -------------------------

_NAME = st.from_regex(r"[a-z][a-z0-9_]{0,10}", fullmatch=True).filter(
    lambda s: (
        s
        not in {
            "trial",
            "channel",
            "time",
            "signal",
            "sample_rate_hz",
            "vibrissa_version",
            "vibrissa_schema",
            "vibrissa_checksum",
            "vibrissa_checksum_parts",
        }
    )
)
_TEXT = st.text(st.characters(exclude_categories=("Cs",), exclude_characters="\x00"), max_size=12)
_FLOAT = st.floats(allow_nan=False, allow_infinity=False)
_JSONABLE = st.recursive(
    st.none() | st.booleans() | st.integers(-(2**53), 2**53) | _FLOAT | _TEXT,
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(_TEXT, inner, max_size=3),
    max_leaves=8,
)


@st.composite
def _datasets(draw: st.DrawFn) -> xr.Dataset:
    n = draw(st.integers(1, 5))
    c = draw(st.integers(1, 3))
    t = draw(st.integers(1, 12))
    signal = draw(st.lists(_FLOAT, min_size=n * c * t, max_size=n * c * t))
    channels = draw(st.lists(_TEXT, min_size=c, max_size=c, unique=True))
    kinds = {"int": st.integers(-(2**62), 2**62), "float": _FLOAT, "text": _TEXT}
    labels = {}
    for name in draw(st.lists(_NAME, max_size=4, unique=True)):
        kind = draw(st.sampled_from(sorted(kinds)))
        labels[name] = draw(st.lists(kinds[kind], min_size=n, max_size=n))
    attrs = draw(st.dictionaries(_NAME, _JSONABLE, max_size=4))
    return make_dataset(
        np.array(signal, dtype=float).reshape(n, c, t),
        sample_rate_hz=draw(st.floats(1e-3, 1e9)),
        channels=channels,
        labels=labels,
        attrs=attrs,
    )


@settings(
    max_examples=50,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(ds=_datasets())
def test_round_trip_property(tmp_path, ds: xr.Dataset) -> None:
    path = save_dataset(ds, tmp_path / "p.nc")
    back = load_dataset(path)
    xr.testing.assert_identical(back, ds)
    assert checksum(back.assign_attrs(vibrissa_schema=SCHEMA_VERSION)) == checksum(
        ds.assign_attrs(vibrissa_schema=SCHEMA_VERSION)
    )


# ----------------------------------------------------------------- issue 13, finding 7
def _unreadable_root_attributes(path) -> None:
    """Damage ``path`` (a saved dataset) so that HDF5 opens it but not its attributes.

    The damage is found by search (zeroing 64 bytes at a time), so that the test does
    not depend on the file's layout; the file is the kind that made h5netcdf print a
    finaliser's traceback after the error.
    """
    data = path.read_bytes()
    for start in range(0, len(data) - 64, 16):
        path.write_bytes(data[:start] + bytes(64) + data[start + 64 :])
        try:
            f = h5py.File(path, "r")
        except Exception:  # this damage does not keep the file openable
            continue
        with f:
            try:
                dict(f.attrs)
            except Exception:  # found
                return
    raise AssertionError("no damage leaves the file openable with unreadable attributes")


def test_a_corrupt_header_gives_one_error_and_nothing_else_on_stderr(tmp_path) -> None:
    """The old main printed the right error, then 8 lines of a finaliser's traceback."""
    p = save_dataset(_ds(), tmp_path / "a.nc")
    _unreadable_root_attributes(p)
    code = (
        "import sys\nfrom vibrissa.data import DatasetFileError, load_dataset\n"
        "try:\n    load_dataset(sys.argv[1])\nexcept DatasetFileError as e:\n    print(e)\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code, str(p)], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0
    assert proc.stderr == ""
    assert proc.stdout.startswith(f"{p}: cannot be read as a NetCDF dataset")
    assert len(proc.stdout.splitlines()) == 1


def test_undecodable_attribute_bytes_are_a_modification_not_a_crash(tmp_path) -> None:
    """The old main raised UnicodeEncodeError ("surrogates not allowed") from the checksum."""
    p = save_dataset(_ds(), tmp_path / "a.nc")
    data = bytearray(p.read_bytes())
    data[data.index(b'"delay_s"') + 1] = 0xFF  # not UTF-8: read back as a lone surrogate
    p.write_bytes(bytes(data))
    with pytest.raises(DatasetModifiedError, match="differs: attribute 'robot'"):
        load_dataset(p)


def test_a_cache_can_demand_vibrissas_checksum(tmp_path):
    path = tmp_path / "x.nc"
    save_dataset(_ds(), path)
    load_dataset(path, written_by_vibrissa=True)
    plain = load_dataset(path)
    plain.to_netcdf(tmp_path / "plain.nc")  # the checksum attributes are gone
    load_dataset(tmp_path / "plain.nc")  # another program's file is accepted ...
    with pytest.raises(DatasetFileError, match="carries no vibrissa checksum"):
        load_dataset(tmp_path / "plain.nc", written_by_vibrissa=True)  # ... but not as a cache


_FULL_DISK = r"""
import resource, signal, sys
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG
resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))
sys.argv = ["vibrissa", *sys.argv[1:]]
from vibrissa.__main__ import main
main()
"""


@pytest.mark.parametrize("limit_bytes", [20_000])
def test_a_write_that_fails_midway_is_one_line_not_a_crash(tmp_path, limit_bytes):
    """Issue 33: HDF5 writing to a full disk failed on close, and the clean-up of its
    file object then crashed the process (SIGSEGV, after the error line). A file-size
    limit makes the same failure (EFBIG) on any filesystem."""
    from vibrissa.examples import example_path

    out = tmp_path / "x.nc"
    cmd = [sys.executable, "-c", _FULL_DISK, "import", str(example_path("data_XY_small.mat"))]
    cmd += ["--mapping", str(example_path("data_XY_small.mapping.json")), "-o", str(out)]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert res.returncode == 2, (res.returncode, res.stderr[-500:])
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {out}: "), res.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []


@pytest.mark.parametrize("how", ["external link", "external storage", "virtual dataset"])
def test_a_dataset_taking_data_from_outside_the_file_is_refused(tmp_path, how) -> None:
    """Issue 33: HDF5 indirections would read other files' bytes; refused before reading."""
    ds = make_dataset(np.ones((3, 2, 10)), sample_rate_hz=1000, labels={"k": [0, 1, 2]})
    p = tmp_path / "plain.nc"
    ds.to_netcdf(p, engine="h5netcdf")  # another program's file: no vibrissa checksum
    load_dataset(p)  # accepted as it is
    (tmp_path / "secret.bin").write_bytes(np.arange(10.0).tobytes())
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = np.arange(10.0)
    with h5py.File(p, "r+") as f:
        if how == "external link":
            f["extra"] = h5py.ExternalLink(str(tmp_path / "other.h5"), "/x")
        elif how == "external storage":
            f.create_dataset(
                "extra", shape=(10,), dtype="<f8", external=[(str(tmp_path / "secret.bin"), 0, 80)]
            )
        else:
            layout = h5py.VirtualLayout(shape=(10,), dtype="<f8")
            layout[:] = h5py.VirtualSource(str(tmp_path / "other.h5"), "x", shape=(10,))
            f.create_virtual_dataset("extra", layout)
    with pytest.raises(DatasetFileError, match=f"takes data from outside the file.*{how}"):
        load_dataset(p)
