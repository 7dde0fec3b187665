"""MATLAB v4/v5/v7 ``.mat`` files, read with :func:`scipy.io.loadmat`.

Variables keep MATLAB's dimension order; a cell array is a NumPy object array,
a struct a 1 x 1 record array whose fields are reached with dotted names
(``"rec.data"``). Function handles and objects (classdef, ``string``, ``table``:
what SciPy reads as ``MatlabFunction``, ``MatlabOpaque`` or ``MatlabObject``) are
refused when the mapping names them. MATLAB v7.3 files are HDF5 and read by
:mod:`vibrissa.data.importers.matlab_hdf5` instead.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.importers._common import DictSource
from vibrissa.data.importers.mapping import ImportMappingError

__all__ = ["MatV5Source", "read_mat_v5"]


class MatV5Source(DictSource):
    """The variables of a MATLAB v4-v7 file; function handles and objects are refused."""

    def get(self, name: str) -> np.ndarray:
        """The variable (or struct field) ``name``, refused if it is not an array.

        Raises
        ------
        ImportMappingError
            If it is missing, or a function handle or MATLAB object.
        """
        from scipy.io.matlab import MatlabFunction, MatlabObject, MatlabOpaque

        head = name.split(".")[0]
        obj: Any = self.vars.get(head)
        if isinstance(obj, MatlabFunction | MatlabOpaque | MatlabObject):
            kind = "function handle" if isinstance(obj, MatlabFunction) else "object"
            raise ImportMappingError(
                f"{self.path}: {head!r} is a MATLAB {kind}, not numbers, chars or a cell "
                "array; convert it to an array in MATLAB and save again"
            )
        return super().get(name)


def read_mat_v5(path: Path) -> MatV5Source:
    """Read every variable of a MATLAB v4/v5/v7 file (opened for reading only).

    Parameters
    ----------
    path
        The ``.mat`` file.

    Returns
    -------
    MatV5Source
        Its variables, of kind ``"mat v5"``.

    Raises
    ------
    ImportMappingError
        If the file is not a MATLAB file, is truncated or uses an unsupported feature.
    """
    import scipy.io

    try:
        variables = scipy.io.loadmat(
            path, squeeze_me=False, struct_as_record=True, chars_as_strings=True
        )
    except NotImplementedError as exc:
        raise ImportMappingError(f"{path}: unsupported MATLAB file: {exc}") from None
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError, ...
        raise ImportMappingError(f"{path}: cannot be read as a MATLAB .mat file: {exc}") from None
    return MatV5Source(path, variables, "mat v5")
