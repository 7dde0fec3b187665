"""What the format readers share: named arrays of a file, and stacking recordings.

Private to :mod:`vibrissa.data.importers`; its names are public so that the
format modules can share them, but they are not re-exported.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.importers.mapping import ImportMappingError

__all__ = ["DictSource", "Source", "equalise"]


class Source:
    """A file's named arrays (MATLAB dimension order).

    Subclasses give :meth:`names` and :meth:`get`; ``kind`` is the format
    recorded in the dataset attribute ``source_format`` (``"mat v5"``,
    ``"mat v7.3"``, ``"npz"``).
    """

    kind = "?"

    def names(self) -> list[str]:
        """The names of the file's variables, sorted."""
        raise NotImplementedError

    def get(self, name: str) -> np.ndarray:
        """The variable ``name`` (struct fields reached with dots: ``"rec.data"``)."""
        raise NotImplementedError

    def pick_signal(self, name: str | None) -> str:
        """The variable holding the signal: ``name``, or the file's only variable.

        Raises
        ------
        ImportMappingError
            If ``name`` is ``None`` and the file holds more than one variable.
        """
        if name is not None:
            return name
        names = self.names()
        if len(names) != 1:
            raise ImportMappingError(
                f"the file holds variables {names}; say which is the signal with 'signal'"
            )
        return names[0]


class DictSource(Source):
    """Variables already read into a dict (MATLAB v5 via SciPy, NPZ via NumPy).

    Names starting with ``__`` (SciPy's ``__header__`` and friends) are hidden;
    dotted names walk into MATLAB v5 structs (1 x 1 record arrays).

    Parameters
    ----------
    path
        The source file, named in error messages.
    variables
        Name -> array, as read from the file.
    kind
        The format, e.g. ``"mat v5"`` or ``"npz"``.
    """

    def __init__(self, path: Path, variables: dict[str, Any], kind: str) -> None:
        self.path = path
        self.vars = variables
        self.kind = kind

    def names(self) -> list[str]:
        return sorted(k for k in self.vars if not k.startswith("__"))

    def get(self, name: str) -> np.ndarray:
        if name in self.vars and not name.startswith("__"):
            return np.asarray(self.vars[name])
        head, *rest = name.split(".")
        if head not in self.vars or head.startswith("__"):
            raise ImportMappingError(f"{self.path}: no variable {head!r}; it holds {self.names()}")
        obj = self.vars[head]
        walked = head
        for part in rest:
            arr = np.asarray(obj)
            if arr.dtype.names is None:
                raise ImportMappingError(
                    f"{self.path}: {walked!r} is not a struct, cannot take {part!r}"
                )
            if part not in arr.dtype.names:
                raise ImportMappingError(
                    f"{self.path}: struct {walked!r} has no field {part!r}; "
                    f"fields: {list(arr.dtype.names)}"
                )
            if arr.size != 1:
                raise ImportMappingError(
                    f"{self.path}: {walked!r} is a struct array, not one struct"
                )
            obj = arr.ravel()[0][part]
            walked += "." + part
        return np.asarray(obj)


def equalise(
    recs: list[np.ndarray], names: list[str], ragged: str
) -> tuple[np.ndarray, int | None]:
    """Stack recordings (n_channels, n_samples_i) into one array, cropping if allowed.

    Parameters
    ----------
    recs
        The recordings, each (n_channels, n_samples_i).
    names
        How each recording is named in error messages (e.g. ``cell data{1,2,3}``).
    ragged
        ``"error"`` or ``"crop"`` (cut every recording to the shortest, keeping
        its first samples).

    Returns
    -------
    signal : numpy.ndarray
        (n_recordings, n_channels, n_samples).
    cropped_from : int or None
        The longest original length (samples) if recordings were cropped.

    Raises
    ------
    ImportMappingError
        If channel counts differ, or lengths differ and ``ragged`` is not ``"crop"``.
    """
    n_ch = recs[0].shape[0]
    for r, nm in zip(recs, names, strict=True):
        if r.shape[0] != n_ch:
            raise ImportMappingError(
                f"{nm} has {r.shape[0]} channel(s), {names[0]} has {n_ch}; "
                "every recording needs the same channels (check 'time_axis')"
            )
    lengths = np.array([r.shape[1] for r in recs])
    cropped_from = None
    if np.any(lengths != lengths[0]):
        if ragged != "crop":
            k = int(np.flatnonzero(lengths != lengths[0])[0])
            raise ImportMappingError(
                f"{names[k]} has {lengths[k]} samples but {names[0]} has {lengths[0]} "
                f"(recordings range from {lengths.min()} to {lengths.max()} samples); "
                'set "ragged": "crop" (--crop) to cut all to the shortest'
            )
        cropped_from = int(lengths.max())
        n = int(lengths.min())
        if n == 0:
            raise ImportMappingError(
                f"{names[int(np.argmin(lengths))]} has no samples; cannot crop"
            )
        recs = [r[:, :n] for r in recs]
    return np.stack(recs), cropped_from
