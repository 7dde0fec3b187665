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
from vibrissa.data.dataset import attr_value, validate_dataset

__all__ = ["DatasetFileError", "checksum", "load_dataset", "save_dataset"]

_CHECKSUM_ATTR = "vibrissa_checksum"
_ENGINE = "h5netcdf"


class DatasetFileError(ValueError):
    """A dataset file is missing, unreadable, truncated or corrupt.

    The message starts with the file's path, also kept in :attr:`path`.
    """

    def __init__(self, path: str | os.PathLike[str], problem: str) -> None:
        self.path = Path(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")

    def __reduce__(self) -> tuple[type, tuple[Path, str]]:
        return (type(self), (self.path, self.problem))


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
    """Write ``ds`` to ``path`` (NetCDF-4/HDF5) atomically with a checksum.

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
        k: attr_value(v) for k, v in ds.attrs.items() if v is not None and k != _CHECKSUM_ATTR
    }
    out.attrs[_CHECKSUM_ATTR] = checksum(ds)
    for name in out.coords:
        if out[name].dtype.kind in "OU":
            out[name] = out[name].astype(str)
    with atomic_path(path, suffix=".nc") as tmp:
        out.to_netcdf(tmp, engine=_ENGINE)
    return Path(path)


def load_dataset(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a dataset written by :func:`save_dataset` (or any schema-conforming NetCDF).

    The whole file is read into memory (the file is closed on return). A file
    without the checksum attribute (written by other software) is accepted
    after the schema check; NetCDF-3 files are read with the ``scipy`` engine.

    Parameters
    ----------
    path
        The file.

    Returns
    -------
    xarray.Dataset
        The dataset, string labels as ``str`` arrays, without the checksum
        attribute.

    Raises
    ------
    DatasetFileError
        If the file is missing, not NetCDF/HDF5, truncated, fails its checksum or
        lacks the schema's variables.
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
    try:
        with xr.open_dataset(p, engine=engine) as f:
            ds = f.load()
    except Exception as exc:  # h5py raises OSError, xarray ValueError, ...
        raise DatasetFileError(
            p, f"cannot be read as a NetCDF dataset (truncated or corrupt?): {exc}"
        ) from None
    for name in ds.coords:
        if ds[name].dtype.kind == "O":
            ds[name] = ds[name].astype(str)
    try:
        validate_dataset(ds)
    except (ValueError, TypeError) as exc:
        raise DatasetFileError(p, str(exc)) from None
    stored = ds.attrs.pop(_CHECKSUM_ATTR, None)
    if stored is not None and stored != checksum(ds):
        raise DatasetFileError(p, "checksum mismatch - the file's contents are corrupt")
    return ds
