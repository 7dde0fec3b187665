"""NetCDF storage of Datasets, with atomic writes and a content checksum.

:func:`save_dataset` writes through a temporary file that is renamed into place
only when complete, and stores a SHA-256 checksum of the signal and of every
coordinate in the attribute ``vibrissa_checksum``. :func:`load_dataset` reads
the whole file into memory and verifies that checksum, so a truncated or
corrupted file gives a :class:`DatasetFileError` naming the file instead of
wrong numbers.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numpy as np
import xarray as xr

from vibrissa._atomic import atomic_path
from vibrissa.data.dataset import validate_dataset

__all__ = ["DatasetFileError", "checksum", "load_dataset", "save_dataset"]

_CHECKSUM_ATTR = "vibrissa_checksum"
_ENGINE = "h5netcdf"


class DatasetFileError(ValueError):
    """A dataset file is missing, unreadable, truncated or corrupt."""


def checksum(ds: xr.Dataset) -> str:
    """SHA-256 over the signal's bytes and every coordinate's values."""
    h = hashlib.sha256()
    sig = np.ascontiguousarray(ds["signal"].values, dtype="<f8")
    h.update(repr(sig.shape).encode())
    h.update(sig.tobytes())
    for name in sorted(str(k) for k in ds.coords):
        vals = np.asarray(ds[name].values)
        h.update(name.encode())
        if vals.dtype.kind in "OUS":
            h.update("\x1f".join(str(v) for v in vals.ravel()).encode())
        else:
            h.update(np.ascontiguousarray(vals, dtype=vals.dtype.newbyteorder("<")).tobytes())
    return h.hexdigest()


def save_dataset(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """Write ``ds`` to ``path`` (NetCDF-4) atomically with a checksum; return the path."""
    validate_dataset(ds)
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if v is not None and k != _CHECKSUM_ATTR}
    out.attrs[_CHECKSUM_ATTR] = checksum(ds)
    for name in out.coords:
        if out[name].dtype.kind in "OU":
            out[name] = out[name].astype(str)
    with atomic_path(path, suffix=".nc") as tmp:
        out.to_netcdf(tmp, engine=_ENGINE)
    return Path(path)


def load_dataset(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a dataset written by :func:`save_dataset` (or any schema-conforming NetCDF).

    Raises
    ------
    DatasetFileError
        If the file is missing, not NetCDF/HDF5, truncated, fails its checksum or
        lacks the schema's variables.
    """
    p = Path(path)
    if not p.exists():
        raise DatasetFileError(f"{p}: no such file")
    if p.is_dir():
        raise DatasetFileError(f"{p}: is a directory, not a dataset file")
    try:
        with xr.open_dataset(p, engine=_ENGINE) as f:
            ds = f.load()
    except Exception as exc:  # h5py raises OSError, xarray ValueError, ...
        raise DatasetFileError(
            f"{p}: cannot be read as a NetCDF dataset (truncated or corrupt?): {exc}"
        ) from None
    for name in ds.coords:
        if ds[name].dtype.kind == "O":
            ds[name] = ds[name].astype(str)
    try:
        validate_dataset(ds)
    except (ValueError, TypeError) as exc:
        raise DatasetFileError(f"{p}: {exc}") from None
    stored = ds.attrs.pop(_CHECKSUM_ATTR, None)
    if stored is not None and stored != checksum(ds):
        raise DatasetFileError(f"{p}: checksum mismatch - the file's contents are corrupt")
    return ds
