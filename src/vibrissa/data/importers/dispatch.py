"""The entry points: tell a file's format, read it, build the Dataset.

:func:`import_recording` checks the mapping against the format, hands the file
to its reader (:mod:`~vibrissa.data.importers.csv_files`, or
:mod:`~vibrissa.data.importers.arrays` over the variables read by
:mod:`~vibrissa.data.importers.matlab_v5`,
:mod:`~vibrissa.data.importers.matlab_hdf5` or :func:`~.arrays.read_npz`),
then adds the mapping's constants, the time axis and the provenance attributes
and builds a validated Dataset. :func:`import_file` also saves it atomically.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.data.dataset import make_dataset
from vibrissa.data.importers._common import Source
from vibrissa.data.importers.arrays import import_array, read_npz
from vibrissa.data.importers.csv_files import import_csv
from vibrissa.data.importers.mapping import (
    FORMATS,
    ImportMapping,
    ImportMappingError,
    check_keys,
    load_mapping,
)
from vibrissa.data.importers.matlab_hdf5 import is_mat_v73, open_mat_v73
from vibrissa.data.importers.matlab_v5 import read_mat_v5

__all__ = ["detect_format", "import_file", "import_recording"]

_EXTENSIONS = {".mat": "mat", ".csv": "csv", ".txt": "csv", ".npz": "npz"}


def detect_format(path: str | os.PathLike[str], fmt: str | None = None) -> str:
    """The format of ``path``: ``fmt`` if given (not ``"auto"``), else from the extension.

    Parameters
    ----------
    path
        The source file (``.mat``, ``.csv``/``.txt``, ``.npz``).
    fmt
        ``"mat"``, ``"csv"``, ``"npz"``, ``"auto"`` or ``None``.

    Returns
    -------
    str
        One of :data:`FORMATS`.

    Raises
    ------
    ImportMappingError
        If the format is unknown or cannot be told from the extension.
    """
    if fmt not in (None, "auto"):
        if fmt not in FORMATS:
            raise ImportMappingError(f"unknown format {fmt!r}; choose one of {list(FORMATS)}")
        return fmt
    ext = Path(path).suffix.lower()
    if ext not in _EXTENSIONS:
        raise ImportMappingError(
            f"{path}: cannot tell the file type from extension {ext or '(none)'!r}; "
            f"give the format ({', '.join(FORMATS)}) explicitly"
        )
    return _EXTENSIONS[ext]


def import_recording(
    source: str | os.PathLike[str],
    mapping: ImportMapping | Mapping[str, Any] | str | os.PathLike[str] | None,
    *,
    format: str | None = None,
) -> xr.Dataset:
    """Read a recording into a Dataset of the vibrissa schema.

    Parameters
    ----------
    source
        The ``.mat`` (v4/v5/v7 or v7.3), ``.csv`` or ``.npz`` file. Only read.
    mapping
        Where signals and labels are (see ``docs/importing.md``): an
        :class:`ImportMapping`, a dict, or a path to a JSON/TOML file.
    format
        ``"mat"``, ``"csv"``, ``"npz"`` or ``None``/``"auto"``: the mapping's
        ``format``, else the file's extension.

    Returns
    -------
    xarray.Dataset
        Validated; attrs ``protocol`` (default ``"imported"``), ``source_file``,
        ``source_format``, ``source_sha256`` (of the source file's bytes) and
        ``import_mapping`` (JSON) besides those of the mapping's ``attrs``.

    Raises
    ------
    ImportMappingError
        Naming the field, cell, column or line: missing variable/column,
        non-numeric data, ragged or empty recordings (when not allowed), axis
        sizes that do not match the file, unknown file type, bad mapping.
    FileNotFoundError
        If ``source`` does not exist.
    """
    path = Path(source)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such file")
    if path.is_dir():
        raise ImportMappingError(f"{path}: is a directory, not a recording file")
    m = mapping if isinstance(mapping, ImportMapping) else load_mapping(mapping)
    fmt = detect_format(path, format if format not in (None, "auto") else m.format)
    check_keys(m, fmt)
    if fmt == "csv":
        res = import_csv(path, m)
        kind = "csv"
    else:
        with _open_source(path, fmt) as src:
            res = import_array(src, m)
            kind = src.kind
    signal = res["signal"]
    n, c, t = signal.shape
    channels = res.get("channels") if m.channels is None else list(m.channels)
    if channels is not None and len(channels) != c:
        raise ImportMappingError(
            f"mapping 'channels' names {len(channels)} channel(s) {list(channels)} but the "
            f"recordings have {c} (check 'time_axis')"
        )
    labels = dict(res["labels"])
    for name, value in m.constants.items():
        labels[name] = np.full(n, value) if not isinstance(value, str) else np.array([value] * n)
    fs = res["sample_rate_hz"]
    time = res["time"] if res["time"] is not None else m.t0_s + np.arange(t) / fs
    attrs: dict[str, Any] = {"protocol": "imported"}
    attrs.update(m.attrs)
    attrs.update(
        {
            "source_file": path.name,
            "source_format": kind,
            "source_sha256": _file_sha256(path),
            "import_mapping": json.dumps(m.raw, sort_keys=True, default=str),
        }
    )
    if res["cropped_from"] is not None:
        attrs["cropped_from_samples"] = res["cropped_from"]
    try:
        return make_dataset(
            signal,
            sample_rate_hz=fs,
            channels=channels,
            time=time,
            labels=labels,
            attrs=attrs,
            units=m.units,
        )
    except ImportMappingError:
        raise
    except ValueError as exc:  # e.g. a reserved label name, a non-increasing time column
        raise ImportMappingError(f"{path}: {exc}") from None


def import_file(
    source: str | os.PathLike[str],
    mapping: ImportMapping | Mapping[str, Any] | str | os.PathLike[str] | None,
    out: str | os.PathLike[str],
    *,
    format: str | None = None,
) -> xr.Dataset:
    """Import ``source`` with :func:`import_recording` and save it to ``out`` (NetCDF).

    The output is written atomically (:func:`vibrissa.data.save_dataset`); an
    existing ``out`` is replaced only when the import succeeded.

    Parameters
    ----------
    source, mapping, format
        As for :func:`import_recording`.
    out
        The dataset file to write (its directory is created if needed).

    Returns
    -------
    xarray.Dataset
        The dataset written.

    Raises
    ------
    ImportMappingError
        If ``out`` is the source file itself, or for any import error.
    """
    from vibrissa.data.netcdf import save_dataset

    src, dst = Path(source), Path(out)
    if dst.exists() and src.exists() and os.path.samefile(src, dst):
        raise ImportMappingError(f"output {dst} is the source file; choose another output path")
    if dst.is_dir():
        raise ImportMappingError(f"output {dst} is a directory")
    ds = import_recording(src, mapping, format=format)
    save_dataset(ds, dst)
    return ds


@contextmanager
def _open_source(path: Path, fmt: str) -> Iterator[Source]:
    """The variables of a ``.mat`` (v5 or, if HDF5, v7.3) or ``.npz`` file, while open."""
    if fmt == "npz":
        yield read_npz(path)
        return
    if is_mat_v73(path):
        with open_mat_v73(path) as src:
            yield src
        return
    yield read_mat_v5(path)


def _file_sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()
