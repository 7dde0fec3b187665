"""MATLAB v7.3 ``.mat`` files (HDF5), read with :mod:`h5py`.

MATLAB's own layout is assumed: each variable is an HDF5 dataset whose
``MATLAB_class`` attribute names its class, stored with its dimensions reversed
(MATLAB is column-major), so it is transposed back here; a cell array is a
dataset of object references (class ``cell``) to datasets in the ``#refs#``
group; an empty array is a dims vector with attribute ``MATLAB_empty``;
``char`` arrays are UTF-16 code units; structs are groups. Complex, sparse and
object-class data (any ``MATLAB_class`` but the numeric ones, ``logical``, ``char``,
``cell`` and ``struct``: ``function_handle``, ``string``, ``table``, classdef
objects, whose bytes are MATLAB's private serialisation) are not supported and raise
:class:`~vibrissa.data.importers.ImportMappingError`. So is a file that takes data
from outside itself (external links, external storage, virtual datasets:
:mod:`vibrissa.data.hdf5_storage`), refused when it is opened.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.hdf5_storage import foreign_storage
from vibrissa.data.importers._common import Source
from vibrissa.data.importers.mapping import ImportMappingError

__all__ = ["H5MatSource", "is_mat_v73", "open_mat_v73"]

#: What h5py raises on damaged files (besides ValueError).
_H5_ERRORS = (OSError, KeyError, RuntimeError, TypeError)

#: The ``MATLAB_class`` values of datasets read as arrays ("" when the attribute is
#: absent: HDF5 written by other software).
_ARRAY_CLASSES = frozenset(
    {"", "double", "single", "logical", "char", "cell"}
    | {f"{s}int{b}" for s in ("", "u") for b in (8, 16, 32, 64)}
)


def _matlab_class(obj: Any) -> str:
    """The ``MATLAB_class`` attribute of an HDF5 object, ``""`` when it has none."""
    cls = obj.attrs.get("MATLAB_class", b"")
    return cls.decode(errors="replace") if isinstance(cls, bytes) else str(cls)


class H5MatSource(Source):
    """A MATLAB v7.3 file open in h5py (the layout is in the module docstring).

    Parameters
    ----------
    path
        The source file, named in error messages.
    f
        The open ``h5py.File`` (read-only); closed by the caller.
    """

    kind = "mat v7.3"

    def __init__(self, path: Path, f: Any) -> None:
        self.path = path
        self.f = f

    def names(self) -> list[str]:
        """The file's variables (the ``#refs#`` group and its kin are hidden)."""
        try:
            return sorted(k for k in self.f.keys() if not k.startswith("#"))
        except _H5_ERRORS as exc:
            raise ImportMappingError(
                f"{self.path}: cannot list its variables (corrupt or truncated file?): {exc}"
            ) from None

    def get(self, name: str) -> np.ndarray:
        """The variable ``name``, transposed back to MATLAB's dimension order.

        Raises
        ------
        ImportMappingError
            If it is missing, a struct, sparse, complex, or cannot be read.
        """
        try:
            return self._get(name)
        except _H5_ERRORS as exc:  # damaged HDF5 objects
            raise ImportMappingError(
                f"{self.path}: variable {name!r} cannot be read (corrupt or truncated file?): {exc}"
            ) from None

    def _get(self, name: str) -> np.ndarray:
        import h5py

        obj: Any = self.f
        walked = ""
        for part in name.split("."):
            if not isinstance(obj, h5py.Group) or part not in obj:
                where = f"struct {walked!r}" if walked else "the file"
                have = (
                    sorted(k for k in obj.keys() if not k.startswith("#"))
                    if isinstance(obj, h5py.Group)
                    else []
                )
                raise ImportMappingError(
                    f"{self.path}: {where} has no variable/field {part!r}; it has {have}"
                )
            obj = obj[part]
            walked = f"{walked}.{part}" if walked else part
            if isinstance(obj, h5py.Group) and _matlab_class(obj) not in ("", "struct"):
                raise self._unsupported(walked, _matlab_class(obj))
        if isinstance(obj, h5py.Group):
            raise ImportMappingError(f"{self.path}: {name!r} is a struct; name one of its fields")
        return self._read(obj, name)

    def _read(self, ds: Any, where: str) -> np.ndarray:
        import h5py

        cls = _matlab_class(ds)
        if cls not in _ARRAY_CLASSES or "MATLAB_object_decode" in ds.attrs:
            raise self._unsupported(where, cls)
        if ds.attrs.get("MATLAB_empty", 0):
            return np.zeros((0, 0))
        if ds.attrs.get("MATLAB_sparse", None) is not None:
            raise ImportMappingError(f"{self.path}: {where!r} is a sparse matrix (not supported)")
        data = ds[()]
        if cls == "cell" or (data.dtype == object and data.dtype.kind == "O"):
            refs = np.asarray(data).T
            out = np.empty(refs.shape, dtype=object)
            for idx in np.ndindex(refs.shape):
                ref = refs[idx]
                if not isinstance(ref, h5py.Reference) or not ref:
                    raise ImportMappingError(
                        f"{self.path}: {where!r} holds an invalid cell reference"
                    )
                target = self.f[ref]
                if isinstance(target, h5py.Group):
                    out[idx] = np.array([None], dtype=object)  # a struct in a cell
                else:
                    out[idx] = self._read(target, where)
            return out
        if cls == "char":
            arr = np.atleast_2d(np.asarray(data).T)
            return np.array(["".join(map(chr, row)) for row in arr.astype(np.uint32)])
        arr = np.asarray(data)
        if arr.dtype.names is not None:
            raise ImportMappingError(
                f"{self.path}: {where!r} holds complex or compound data, not reals"
            )
        arr = arr.T
        return arr.astype(bool) if cls == "logical" else arr

    def _unsupported(self, where: str, cls: str) -> ImportMappingError:
        """The error for a variable of a MATLAB class that is not an array of numbers."""
        return ImportMappingError(
            f"{self.path}: {where!r} is a MATLAB {cls or 'object'} (an object class, not "
            "numbers, chars or a cell array); convert it to an array in MATLAB and save again"
        )


def is_mat_v73(path: Path) -> bool:
    """Whether ``path`` is an HDF5 file (a MATLAB v7.3 ``.mat`` file) rather than v4-v7."""
    import h5py

    return bool(h5py.is_hdf5(path))


@contextmanager
def open_mat_v73(path: Path) -> Iterator[H5MatSource]:
    """Open a MATLAB v7.3 file for reading; closed when the ``with`` block ends.

    Parameters
    ----------
    path
        The ``.mat`` file (HDF5).

    Yields
    ------
    H5MatSource
        Its variables, of kind ``"mat v7.3"``.

    Raises
    ------
    ImportMappingError
        If HDF5 cannot open it (e.g. a truncated file) or it takes data from outside
        itself (external links, external storage, virtual datasets).
    """
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise ImportMappingError(
            f"{path}: cannot be read as a MATLAB v7.3 (HDF5) file: {exc}"
        ) from None
    with f:
        try:
            foreign = foreign_storage(f)
        except _H5_ERRORS as exc:
            raise ImportMappingError(
                f"{path}: cannot list its contents (corrupt or truncated file?): {exc}"
            ) from None
        if foreign is not None:
            raise ImportMappingError(
                f"{path}: takes data from outside the file ({foreign}); such files are "
                "refused (save it again in MATLAB without links to other files)"
            )
        yield H5MatSource(path, f)
