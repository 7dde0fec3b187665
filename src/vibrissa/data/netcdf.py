"""NetCDF storage of Datasets, with atomic writes, a schema version and a checksum.

:func:`save_dataset` writes through a temporary file that is renamed into place
only when complete. The file carries

- ``vibrissa_schema``: the version of the file layout (:data:`SCHEMA_VERSION`);
- ``vibrissa_checksum``: a SHA-256 over everything that defines the data: the
  signal and every other data variable (values, dtype, shape), every coordinate
  (values, dtype, dims) and every attribute of the dataset and of its variables
  (canonical JSON), except the two checksum attributes themselves;
- ``vibrissa_checksum_parts``: JSON with the dimension sizes and a short hash of
  each part (each variable's values, each variable's attributes, each dataset
  attribute), so that a mismatch names what changed.

:func:`load_dataset` reads the whole file into memory and verifies it: a file
changed after vibrissa wrote it raises :class:`DatasetModifiedError` naming what
differs (a subset saved with plain xarray, which keeps the old checksum
attribute, is recognised by its dimension sizes); a file of an older or newer
schema raises :class:`DatasetSchemaError`. ``verify=False`` loads such a file
anyway with a :class:`DatasetIntegrityWarning`. A file without any vibrissa
attributes (written by other software) is accepted after the schema check.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Final

import numpy as np
import xarray as xr

from vibrissa._atomic import atomic_path
from vibrissa.data.dataset import attr_value, validate_dataset
from vibrissa.data.hdf5_storage import foreign_storage

__all__ = [
    "SCHEMA_VERSION",
    "DatasetFileError",
    "DatasetIntegrityWarning",
    "DatasetModifiedError",
    "DatasetSchemaError",
    "checksum",
    "checksum_parts",
    "load_dataset",
    "save_dataset",
]

#: Version of the file layout written by :func:`save_dataset` (attribute
#: ``vibrissa_schema``). 1: files of vibrissa before the attribute existed (checksum of
#: signal and coordinates only); 2: checksum of every variable and attribute, per-part
#: hashes, coordinates with ``units`` and ``long_name``.
SCHEMA_VERSION = 2

_CHECKSUM_ATTR = "vibrissa_checksum"
_PARTS_ATTR = "vibrissa_checksum_parts"
_SCHEMA_ATTR = "vibrissa_schema"
_UNCOVERED = frozenset({_CHECKSUM_ATTR, _PARTS_ATTR})
_PART_HEX = 16  # hex digits kept per part in the parts attribute
_ENGINE: Final = "h5netcdf"


class DatasetFileError(ValueError):
    """A dataset file is missing, unreadable, truncated or corrupt.

    The message starts with the file's path, also kept in :attr:`path`.
    """

    def __init__(self, path: str | os.PathLike[str], problem: str) -> None:
        self.path = Path(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return (type(self), (self.path, self.problem))


class DatasetModifiedError(DatasetFileError):
    """A file written by vibrissa was changed afterwards (its checksum does not match).

    :attr:`differs` names the parts that changed (e.g. ``"attribute 'robot'"``),
    empty when they cannot be told.
    """

    def __init__(
        self, path: str | os.PathLike[str], problem: str, differs: Iterable[str] = ()
    ) -> None:
        self.differs = tuple(differs)
        super().__init__(path, problem)

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return (type(self), (self.path, self.problem, self.differs))


class DatasetSchemaError(DatasetFileError):
    """A file written by an older or newer vibrissa, of another :data:`SCHEMA_VERSION`.

    :attr:`schema` is the file's version (1 for files without ``vibrissa_schema``;
    ``None`` if unreadable).
    """

    def __init__(
        self, path: str | os.PathLike[str], problem: str, schema: int | None = None
    ) -> None:
        self.schema = schema
        super().__init__(path, problem)

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return (type(self), (self.path, self.problem, self.schema))


class DatasetIntegrityWarning(UserWarning):
    """A file failed verification and was loaded anyway (``verify=False``)."""


_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"


def _file_kind(p: Path) -> str:
    """``"hdf5"`` (NetCDF-4), ``"netcdf3"`` or ``"other"`` from the file's signature."""
    with open(p, "rb") as fh:
        head = fh.read(8)
        if head.startswith(b"CDF\x01") or head.startswith(b"CDF\x02"):
            return "netcdf3"
        # HDF5 allows a user block of 512, 1024, 2048, ... bytes before the signature
        offset = 0
        while True:
            if head == _HDF5_MAGIC:
                return "hdf5"
            offset = 512 if offset == 0 else offset * 2
            fh.seek(offset)
            head = fh.read(8)
            if len(head) < 8:
                return "other"


def _canonical(value: Any) -> Any:
    """``value`` as plain JSON types, the same before writing and after reading."""
    value = attr_value(value)
    if isinstance(value, np.ndarray):
        if value.size == 1:  # NetCDF gives one-element attribute arrays back as scalars
            return _canonical(value.reshape(()).item())
        return [_canonical(v) for v in value.tolist()]
    if isinstance(value, bytes | np.bytes_):
        return bytes(value).decode("utf-8", errors="replace")
    if isinstance(value, np.generic):
        return _canonical(value.item())
    if isinstance(value, list | tuple):
        return [_canonical(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): _canonical(v) for k, v in value.items()}
    if isinstance(value, str | int | float) or value is None:
        return value
    return str(value)


def _json(value: Any) -> str:
    return json.dumps(value, sort_keys=True, ensure_ascii=False, separators=(",", ":"))


def _utf8(text: str) -> bytes:
    """``text`` as UTF-8, lone surrogates included.

    The lone surrogates by which a corrupt file's undecodable bytes are read are encoded as
    they are (the digest then differs instead of failing).
    """
    return text.encode("utf-8", "surrogatepass")


def _values_digest(var: xr.DataArray) -> str:
    """SHA-256 of a variable's dims, shape, dtype and values."""
    h = hashlib.sha256()
    vals = np.asarray(var.values)
    h.update(_utf8(_json([[str(d) for d in var.dims], list(vals.shape)])))
    if vals.dtype.kind in "OUS":
        # strings: the dtype's width changes on a round trip, the text does not
        h.update(b"str")
        h.update(
            _utf8(
                _json(
                    [_canonical(v) if not isinstance(v, str) else v for v in vals.ravel().tolist()]
                )
            )
        )
    else:
        little = vals.dtype.newbyteorder("<") if vals.dtype.byteorder != "|" else vals.dtype
        h.update(little.str.encode())
        # the array's own buffer as a memoryview (no copy of it as bytes: the signal
        # of a full grid is hundreds of MB)
        h.update(np.ascontiguousarray(vals, dtype=little).reshape(-1).view(np.uint8).data)
    return h.hexdigest()


def _attrs_digest(attrs: Mapping[Any, Any]) -> str:
    text = _json({str(k): _canonical(v) for k, v in attrs.items()})
    return hashlib.sha256(_utf8(text)).hexdigest()


def _full_parts(ds: xr.Dataset) -> dict[str, Any]:
    return {
        "sizes": {str(k): int(v) for k, v in ds.sizes.items()},
        "variables": {str(k): _values_digest(ds[k]) for k in ds.variables},
        "variable_attrs": {str(k): _attrs_digest(ds[k].attrs) for k in ds.variables},
        "attrs": {
            str(k): hashlib.sha256(_utf8(_json(_canonical(v)))).hexdigest()
            for k, v in ds.attrs.items()
            if str(k) not in _UNCOVERED
        },
    }


def checksum(ds: xr.Dataset) -> str:
    """SHA-256 over everything that defines the data of ``ds``.

    Covers every data variable and coordinate (dims, shape, dtype, values; strings by
    their text), the attributes of each (canonical JSON, keys sorted) and every
    attribute of the dataset except ``vibrissa_checksum`` and
    ``vibrissa_checksum_parts``; attributes count in the form NetCDF stores them
    (:func:`vibrissa.data.attr_value`: ``True`` as 1, dicts as JSON).

    Parameters
    ----------
    ds
        Any dataset.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    return _checksum_of(_full_parts(ds))


def _checksum_of(full: dict[str, Any]) -> str:
    return hashlib.sha256(_utf8(_json(full))).hexdigest()


def checksum_parts(ds: xr.Dataset) -> dict[str, Any]:
    """The dimension sizes and a short hash of each part of ``ds``.

    Stored beside :func:`checksum` (attribute ``vibrissa_checksum_parts``) so that a
    mismatch can name what changed.

    Returns
    -------
    dict
        ``sizes`` (dim -> length), ``variables`` and ``variable_attrs`` (name ->
        hash of the values, of the attributes), ``attrs`` (dataset attribute ->
        hash); hashes are the first 16 hex digits of SHA-256.
    """
    return _parts_of(_full_parts(ds))


def _parts_of(full: dict[str, Any]) -> dict[str, Any]:
    return {
        "sizes": full["sizes"],
        **{
            key: {k: v[:_PART_HEX] for k, v in full[key].items()}
            for key in ("variables", "variable_attrs", "attrs")
        },
    }


def _kind(ds: xr.Dataset, name: str) -> str:
    return "data variable" if name in ds.data_vars else "coordinate"


def _differences(ds: xr.Dataset, stored: Mapping[str, Any]) -> list[str]:
    """What differs between ``ds`` and the stored parts, as ``"attribute 'robot'"``..."""
    now = checksum_parts(ds)
    out: list[str] = []
    for key, what in (
        ("variables", "{kind} {name!r}"),
        ("variable_attrs", "attributes of {kind} {name!r}"),
        ("attrs", "attribute {name!r}"),
    ):
        old = stored.get(key)
        if not isinstance(old, Mapping):
            continue
        new = now[key]
        for name in sorted(set(old) | set(new)):
            kind = _kind(ds, name) if name in ds.variables else "variable"
            label = what.format(kind=kind, name=name)
            if name not in new:
                out.append(f"{label} (removed)")
            elif name not in old:
                out.append(f"{label} (added)")
            elif old[name] != new[name]:
                out.append(label)
    return out


def _sizes_text(sizes: Mapping[str, Any], order: Iterable[str]) -> str:
    names = [k for k in order if k in sizes] + sorted(k for k in sizes if k not in order)
    return ", ".join(f"{k}={sizes[k]}" for k in names)


def _schema_version(value: Any) -> int | None:
    try:
        v = _canonical(value)
        if isinstance(v, str | int | float) and float(v) == int(float(v)):
            return int(float(v))
    except (TypeError, ValueError, OverflowError):
        pass
    return None


def _integrity_problem(
    p: Path, ds: xr.Dataset, stored: Any, parts_raw: Any
) -> DatasetFileError | None:
    """The verification error of the file ``p`` loaded as ``ds``, or ``None``."""
    has_schema = _SCHEMA_ATTR in ds.attrs
    if not has_schema and stored is None and parts_raw is None:
        return None  # written by other software: nothing to verify
    if not has_schema:
        return DatasetSchemaError(
            p,
            "was written by an older vibrissa (file schema 1, this vibrissa reads schema "
            f"{SCHEMA_VERSION}), whose checksum does not cover the attributes; re-create the "
            "file (rerun the command that made it), or load it with "
            "load_dataset(path, verify=False) and write it again with save_dataset",
            schema=1,
        )
    version = _schema_version(ds.attrs[_SCHEMA_ATTR])
    if version is None:
        return DatasetSchemaError(
            p,
            f"has an unreadable schema version {ds.attrs[_SCHEMA_ATTR]!r} "
            f"(attribute {_SCHEMA_ATTR!r}; this vibrissa reads schema {SCHEMA_VERSION})",
        )
    if version > SCHEMA_VERSION:
        return DatasetSchemaError(
            p,
            f"was written by a newer vibrissa (file schema {version}, this vibrissa reads "
            f"schema {SCHEMA_VERSION} and older); upgrade vibrissa to read it",
            schema=version,
        )
    if version < SCHEMA_VERSION:
        return DatasetSchemaError(
            p,
            f"was written by an older vibrissa (file schema {version}, this vibrissa reads "
            f"schema {SCHEMA_VERSION}); re-create the file, or load it with verify=False",
            schema=version,
        )
    if stored is None:
        return DatasetModifiedError(
            p,
            f"was modified or re-saved outside vibrissa: it has attribute {_SCHEMA_ATTR!r} "
            f"but no {_CHECKSUM_ATTR!r}",
            differs=(f"attribute {_CHECKSUM_ATTR!r} (removed)",),
        )
    try:
        parts = json.loads(str(_canonical(parts_raw))) if parts_raw is not None else {}
    except ValueError:
        parts = {}
    parts = parts if isinstance(parts, dict) else {}
    sizes = parts.get("sizes")
    now_sizes = {str(k): int(v) for k, v in ds.sizes.items()}
    if isinstance(sizes, dict) and sizes != now_sizes:
        return DatasetModifiedError(
            p,
            f"was modified or re-saved outside vibrissa: it holds "
            f"{_sizes_text(now_sizes, now_sizes)} but vibrissa wrote "
            f"{_sizes_text(sizes, list(now_sizes))} (a subset saved with xarray's to_netcdf "
            "keeps the old checksum attribute); save subsets with vibrissa.data.save_dataset, "
            "or load with verify=False",
            differs=("sizes",),
        )
    if str(_canonical(stored)) == checksum(ds):
        return None
    differs = _differences(ds, parts)
    what = ("; differs: " + ", ".join(differs)) if differs else ""
    return DatasetModifiedError(
        p,
        f"was modified after it was written by vibrissa (checksum mismatch){what}",
        differs=differs,
    )


def save_dataset(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """Write ``ds`` to ``path`` (NetCDF-4/HDF5) atomically with a schema version and checksum.

    Parameters
    ----------
    ds
        A dataset of the schema (validated first).
    path
        Destination. The file is written beside it under a temporary name and
        renamed into place only when complete, so an existing file is never
        half-overwritten.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        If ``ds`` does not conform to the schema.
    """
    validate_dataset(ds)
    out = ds.copy()
    out.attrs = {
        k: attr_value(v) for k, v in ds.attrs.items() if v is not None and k not in _UNCOVERED
    }
    out.attrs[_SCHEMA_ATTR] = SCHEMA_VERSION
    for name in out.coords:
        if out[name].dtype.kind in "OU":
            out[name] = out[name].astype(str)
    for var in out.variables.values():
        var.attrs = {k: attr_value(v) for k, v in var.attrs.items() if v is not None}
    full = _full_parts(out)  # hashed once for both attributes
    out.attrs[_CHECKSUM_ATTR] = _checksum_of(full)
    out.attrs[_PARTS_ATTR] = _json(_parts_of(full))
    # The file is made in memory and written with plain file I/O: when HDF5 itself wrote
    # to a full disk, its failed close left a file object whose later clean-up (garbage
    # collection, interpreter exit) crashed the process with SIGSEGV; now a full disk is
    # an OSError from write() like any other, and the temporary file is removed.
    image = out.to_netcdf(engine=_ENGINE)
    with atomic_path(path, suffix=".nc") as tmp, open(tmp, "wb") as fh:
        fh.write(image)
    return Path(path)


def _open_hdf5_root(p: Path) -> str | None:
    """Open ``p`` with h5py, read its root attributes and look for data kept elsewhere.

    h5netcdf reads the root attributes while constructing its file object; when that
    fails (a corrupt header) the half-built object is left to the garbage collector,
    whose finaliser then fails too and prints a traceback on standard error after the
    error was reported. Failing here first keeps a corrupt file to one error.

    Returns
    -------
    str or None
        What in the file takes its data from outside it
        (:func:`~vibrissa.data.hdf5_storage.foreign_storage`), else ``None``.
    """
    import h5py

    with h5py.File(p, "r") as f:
        f.attrs.get("_nc3_strict")
        dict(f.attrs)
        return foreign_storage(f)


def load_dataset(
    path: str | os.PathLike[str], *, verify: bool = True, written_by_vibrissa: bool = False
) -> xr.Dataset:
    """Read a dataset written by :func:`save_dataset` (or any schema-conforming NetCDF).

    The whole file is read into memory (the file is closed on return) and checked
    against the schema; a file written by vibrissa is verified against its
    checksum. A file without vibrissa's attributes (written by other software) is
    accepted after the schema check; NetCDF-3 files are read with the ``scipy``
    engine.

    Parameters
    ----------
    path
        The file.
    verify
        ``False`` loads a file that fails verification (modified, other schema)
        anyway, with a :class:`DatasetIntegrityWarning` saying why.
    written_by_vibrissa
        ``True`` refuses a file without vibrissa's checksum (written by other software,
        or its ``vibrissa_*`` attributes stripped), as a cache must.

    Returns
    -------
    xarray.Dataset
        The dataset, string labels as ``str`` arrays, without the attributes
        ``vibrissa_schema``, ``vibrissa_checksum`` and ``vibrissa_checksum_parts``.

    Raises
    ------
    DatasetModifiedError
        If the file was changed after vibrissa wrote it (the message says
        "modified after it was written by vibrissa" and names what differs) or
        re-saved outside vibrissa (e.g. a subset written with xarray).
    DatasetSchemaError
        If the file was written by an older or newer vibrissa.
    DatasetFileError
        If the file is missing, not NetCDF/HDF5, truncated or lacks the schema's
        variables.
    """
    p = Path(path)
    if not p.exists():
        raise DatasetFileError(p, "no such file")
    if p.is_dir():
        raise DatasetFileError(p, "is a directory, not a dataset file")
    try:
        kind = _file_kind(p)
    except OSError as exc:
        raise DatasetFileError(p, f"cannot be opened: {exc.strerror or exc}") from None
    if kind == "other":
        raise DatasetFileError(p, "is not a NetCDF/HDF5 file")
    engine = "scipy" if kind == "netcdf3" else _ENGINE
    foreign = None
    try:
        if kind == "hdf5":
            foreign = _open_hdf5_root(p)
    except Exception as exc:  # h5py raises OSError, KeyError, RuntimeError, ...
        raise DatasetFileError(
            p, f"cannot be read as a NetCDF dataset (truncated or corrupt?): {exc}"
        ) from None
    if foreign is not None:
        raise DatasetFileError(
            p, f"takes data from outside the file ({foreign}); such files are refused"
        )
    try:
        with xr.open_dataset(p, engine=engine) as f:
            ds = f.load()
    except Exception as exc:  # h5py raises OSError, xarray ValueError, ...
        detail = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        raise DatasetFileError(
            p, f"cannot be read as a NetCDF dataset (truncated or corrupt?): {detail}"
        ) from None
    for name in ds.coords:
        if ds[name].dtype.kind == "O":
            ds[name] = ds[name].astype(str)
    try:
        validate_dataset(ds)
    except (ValueError, TypeError) as exc:
        raise DatasetFileError(p, str(exc)) from None
    stored = ds.attrs.pop(_CHECKSUM_ATTR, None)
    parts_raw = ds.attrs.pop(_PARTS_ATTR, None)
    if written_by_vibrissa and stored is None:
        raise DatasetFileError(
            p, "carries no vibrissa checksum (not written by vibrissa, or its attributes stripped)"
        )
    problem = _integrity_problem(p, ds, stored, parts_raw)
    ds.attrs.pop(_SCHEMA_ATTR, None)
    if problem is not None:
        if verify:
            raise problem
        warnings.warn(
            f"{p}: {problem.problem}; loaded anyway (verify=False)",
            DatasetIntegrityWarning,
            stacklevel=2,
        )
    return ds
