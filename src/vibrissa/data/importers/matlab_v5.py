"""MATLAB v4/v5/v7 ``.mat`` files, read with :func:`scipy.io.loadmat`.

Variables keep MATLAB's dimension order; a cell array is a NumPy object array,
a struct a 1 x 1 record array whose fields are reached with dotted names
(``"rec.data"``). MATLAB v7.3 files are HDF5 and read by
:mod:`vibrissa.data.importers.matlab_hdf5` instead.
"""

from __future__ import annotations

from pathlib import Path

from vibrissa.data.importers._common import DictSource
from vibrissa.data.importers.mapping import ImportMappingError

__all__ = ["read_mat_v5"]


def read_mat_v5(path: Path) -> DictSource:
    """Read every variable of a MATLAB v4/v5/v7 file (opened for reading only).

    Parameters
    ----------
    path
        The ``.mat`` file.

    Returns
    -------
    DictSource
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
    return DictSource(path, variables, "mat v5")
