"""Recordings held as arrays: MATLAB cell arrays and numeric arrays, NPZ files.

:func:`import_array` turns one variable of a file (MATLAB v5 or v7.3, NPZ) into
trials: a cell array gives one trial per cell (each a 1-D or 2-D recording,
possibly of unequal lengths, cropped if the mapping allows), a numeric array
one trial per index of its leading (or, with ``"trial_axes": "last"``,
trailing) dimensions. Trial labels come from the mapping's ``cell_axes`` and
``labels``; trial order is C order over the trial axes. :func:`read_npz` reads
an ``.npz`` file without pickle support. See ``docs/importing.md``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.importers._common import DictSource, Source, equalise
from vibrissa.data.importers.mapping import (
    INTEGER_LABELS,
    ImportMapping,
    ImportMappingError,
    round_values,
)

__all__ = ["import_array", "read_npz"]


def read_npz(path: Path) -> DictSource:
    """Read every array of an ``.npz`` file, refusing pickled objects.

    Parameters
    ----------
    path
        The ``.npz`` file (opened for reading only).

    Returns
    -------
    DictSource
        Its arrays, of kind ``"npz"``.

    Raises
    ------
    ImportMappingError
        If the file is not a readable NPZ file or an array holds Python objects.
    """
    try:
        with np.load(path, allow_pickle=False) as z:
            variables = {k: _npz_get(path, z, k) for k in z.files}
    except ValueError as exc:
        raise ImportMappingError(f"{path}: {exc}") from None
    except Exception as exc:  # zipfile.BadZipFile, OSError, EOFError
        raise ImportMappingError(f"{path}: cannot be read as an NPZ file: {exc}") from None
    return DictSource(path, variables, "npz")


def _npz_get(path: Path, z: Any, key: str) -> np.ndarray:
    try:
        return z[key]
    except ValueError as exc:
        if "allow_pickle" in str(exc):
            raise ImportMappingError(
                f"array {key!r} holds Python objects (a pickle), which are not loaded for "
                "safety; store numeric arrays (one per trial grid) instead"
            ) from None
        raise


def import_array(source: Source, mapping: ImportMapping) -> dict[str, Any]:
    """The recordings and labels of a cell array or numeric array of ``source``.

    Parameters
    ----------
    source
        The file's variables (MATLAB v5, v7.3 or NPZ).
    mapping
        Which variable is the signal (``signal``), its trial axes
        (``cell_axes``, ``trial_axes``), ``time_axis``, ``labels``, ``ragged``,
        ``empty`` and ``sample_rate_hz``.

    Returns
    -------
    dict
        ``signal`` (n_trials, n_channels, n_samples) float array, ``labels``
        (label -> one value per trial), ``cropped_from`` (samples, or ``None``),
        ``sample_rate_hz`` (Hz), ``time`` (``None``: from the sampling rate)
        and ``signal_name``.

    Raises
    ------
    ImportMappingError
        Naming the cell or slice at fault (MATLAB style for ``.mat`` files,
        e.g. ``cell data{2,3,17}`` or ``data(:,:,3)``).
    """
    name = source.pick_signal(mapping.signal)
    arr = source.get(name)
    is_cell = arr.dtype == object
    axes = mapping.cell_axes if mapping.cell_axes is not None else ({"name": "trial"},)
    k = len(axes)
    if is_cell:
        shape = arr.shape
        if len(shape) != k:
            squeezed = tuple(s for s in shape if s != 1)
            if len(squeezed) != k:
                raise ImportMappingError(
                    f"signal {name!r} is a {' x '.join(map(str, shape))} cell array but the "
                    f"mapping's cell_axes has {k} entr{'y' if k == 1 else 'ies'} "
                    f"({[a['name'] for a in axes]})"
                )
            keep = [i for i, s in enumerate(shape) if s != 1]
        else:
            keep = list(range(k))
        grid = tuple(shape[i] for i in keep)
        cells = []
        names = []
        for idx in np.ndindex(shape):
            cells.append(arr[idx])
            names.append(f"cell {name}{_matlab_index(idx)}")
        # reorder to C order over the kept axes (dropped axes have size 1: order unchanged)
        grid_idx = [tuple(idx[i] for i in keep) for idx in np.ndindex(shape)]
    else:
        if arr.dtype.kind not in "iufc" and arr.dtype != bool:
            raise ImportMappingError(f"signal {name!r} holds {arr.dtype} data, not numbers")
        rec_ndim = arr.ndim - k
        if rec_ndim not in (1, 2):
            raise ImportMappingError(
                f"signal {name!r} has shape {arr.shape}: with {k} trial ax"
                f"{'is' if k == 1 else 'es'} in cell_axes ({[a['name'] for a in axes]}) each "
                f"recording would have {rec_ndim} dimensions, not 1 (time) or 2 (time, channel)"
            )
        last = mapping.trial_axes == "last"
        grid = arr.shape[rec_ndim:] if last else arr.shape[:k]
        matlab = source.kind.startswith("mat")
        colons = [":"] * rec_ndim
        cells, names, grid_idx = [], [], []
        for idx in np.ndindex(grid):
            full = (*[slice(None)] * rec_ndim, *idx) if last else idx
            cells.append(arr[full])
            pos = [str(i + 1) if matlab else str(i) for i in idx]
            parts = [*colons, *pos] if last else [*pos, *colons]
            names.append(f"{name}({','.join(parts)})" if matlab else f"{name}[{', '.join(parts)}]")
            grid_idx.append(idx)
    # values of every trial axis, checked against the grid
    kind = "cell array" if is_cell else "array"
    what = f"signal {name!r} (a {' x '.join(map(str, arr.shape))} {kind})"
    axis_vals = [
        _axis_values(a, grid[i], f"mapping 'cell_axes'[{i}]", source, what)
        for i, a in enumerate(axes)
    ]
    recs, rec_names, kept_idx, keep_mask = [], [], [], []
    for cell, nm, gi in zip(cells, names, grid_idx, strict=True):
        c = np.asarray(cell)
        if c.size == 0 and c.dtype.kind in "iufO":
            if mapping.empty == "skip":
                keep_mask.append(False)
                continue
            raise ImportMappingError(
                f'{nm} is empty; set "empty": "skip" (--skip-empty) to leave it out'
            )
        recs.append(_numeric_recording(c, nm, mapping.time_axis, matlab_vectors=is_cell))
        rec_names.append(nm)
        kept_idx.append(gi)
        keep_mask.append(True)
    if not recs:
        raise ImportMappingError(f"signal {name!r} holds no recordings")
    signal, cropped_from = equalise(recs, rec_names, mapping.ragged)
    labels: dict[str, np.ndarray] = {}
    for ax, (a, vals) in enumerate(zip(axes, axis_vals, strict=True)):
        if vals is not None:
            labels[a["name"]] = np.asarray([vals[gi[ax]] for gi in kept_idx])
    mask = np.asarray(keep_mask)
    n_all = len(cells)
    for label, var in mapping.labels.items():
        vals = _label_array(source.get(var), var)
        if vals.size != n_all:
            raise ImportMappingError(
                f"label {label!r} (variable {var!r}) has {vals.size} values for "
                f"{n_all} recordings in {name!r}"
            )
        labels[label] = vals[mask]
    return {
        "signal": signal,
        "labels": labels,
        "cropped_from": cropped_from,
        "sample_rate_hz": _sample_rate(mapping, source),
        "time": None,
        "signal_name": name,
    }


def _axis_values(
    entry: dict[str, Any], size: int, where: str, source: Source | None, what: str = ""
) -> Any:
    """Values of one trial axis (``None`` for an unlabelled ``trial`` axis)."""
    name = entry["name"]
    if "values" in entry:
        vals = np.asarray(entry["values"])
    elif "from" in entry:
        if source is None:
            raise ImportMappingError(f"{where} ({name!r}): 'from' is not available for this format")
        vals = _label_array(source.get(entry["from"]), entry["from"])
    elif "start" in entry:
        start = float(entry["start"])
        if "num" in entry:
            num = entry["num"]
            if not isinstance(num, int) or num < 1:
                raise ImportMappingError(f"{where} ({name!r}): 'num' must be a positive integer")
            vals = round_values(np.linspace(start, float(entry["stop"]), num))
        else:
            step = float(entry["step"])
            vals = round_values(start + step * np.arange(size))
            if "stop" in entry and not math.isclose(
                float(vals[-1]), float(entry["stop"]), rel_tol=1e-9, abs_tol=1e-9
            ):
                raise ImportMappingError(
                    f"{where} ({name!r}): {size} values from {start:g} in steps of {step:g} end "
                    f"at {float(vals[-1]):g}, not at 'stop' {float(entry['stop']):g}; "
                    f"{what or 'the signal'} has {size} along this axis"
                )
        if name in INTEGER_LABELS and np.all(vals == np.round(vals)):
            vals = vals.astype(np.int64)
    elif name == "trial":
        return None
    else:
        vals = np.arange(size)
    if vals.ndim != 1 or vals.size != size:
        raise ImportMappingError(
            f"{where} ({name!r}) has {vals.size} values but {what or 'the signal'} has "
            f"{size} along this axis"
        )
    return vals


def _matlab_index(idx: tuple[int, ...]) -> str:
    return "{" + ",".join(str(i + 1) for i in idx) + "}"


def _numeric_recording(
    x: Any, what: str, time_axis: int, matlab_vectors: bool = False
) -> np.ndarray:
    """One recording as a float array (n_channels, n_samples).

    With ``matlab_vectors``, a 1 x N cell content (MATLAB row vector) is one
    channel of N samples even when time is axis 0.
    """
    arr = np.asarray(x)
    if arr.dtype == object or arr.dtype.kind in "USVb" or arr.dtype.names is not None:
        kind = {"U": "text", "S": "text", "O": "cells/structs", "b": "logical values"}.get(
            arr.dtype.kind, "structured data"
        )
        raise ImportMappingError(f"{what} holds {kind}, not numbers")
    if arr.dtype.kind == "c":
        raise ImportMappingError(f"{what} holds complex numbers, not real numbers")
    if arr.dtype.kind not in "iuf":
        raise ImportMappingError(f"{what} holds {arr.dtype}, not numbers")
    if matlab_vectors and arr.ndim == 2 and arr.shape[0] == 1 and time_axis in (0, -2):
        # MATLAB vectors are 2-D: a 1 x N row is one channel of N samples
        arr = arr.reshape(-1, 1)
    if arr.ndim == 1:
        arr = arr[:, None] if time_axis in (0, -2) else arr[None, :]
    if arr.ndim != 2:
        raise ImportMappingError(f"{what} has shape {arr.shape}; a recording must be 1-D or 2-D")
    rec = arr.T if time_axis in (0, -2) else arr
    rec = rec.astype(np.float64)
    finite = np.isfinite(rec)
    if not finite.all():
        raise ImportMappingError(f"{what} contains {_bad_values(rec, finite)}")
    return rec


def _bad_values(rec: np.ndarray, finite: np.ndarray) -> str:
    """How many NaN/infinite values a (n_channels, n_samples) recording has, and where."""
    n_nan = int(np.count_nonzero(np.isnan(rec)))
    n_inf = int(rec.size - np.count_nonzero(finite) - n_nan)
    bad = ~finite
    t = int(np.flatnonzero(bad.any(axis=0))[0])
    ch = int(np.flatnonzero(bad[:, t])[0])
    first = "NaN" if np.isnan(rec[ch, t]) else "infinite"
    return (
        f"{n_nan + n_inf} NaN or infinite value(s) ({n_nan} NaN, {n_inf} infinite) in "
        f"{int(np.count_nonzero(bad.any(axis=0)))} of {rec.shape[1]} samples; the first "
        f"({first}) is sample {t + 1} of channel {ch + 1} (counting from 1)"
    )


def _label_array(x: np.ndarray, name: str) -> np.ndarray:
    """A variable of the file as a flat array of numbers or strings."""
    arr = np.asarray(x)
    if arr.dtype == object:
        out = []
        for el in arr.ravel(order="C"):
            e = np.asarray(el)
            if e.dtype.kind in "US" and e.size == 1:
                out.append(str(e.ravel()[0]))
            elif e.dtype.kind in "iuf" and e.size == 1:
                out.append(e.ravel()[0].item())
            else:
                raise ImportMappingError(
                    f"variable {name!r} must hold one number or string per cell"
                )
        if all(isinstance(v, str) for v in out):
            return np.array(out, dtype=str)
        if any(isinstance(v, str) for v in out):
            raise ImportMappingError(f"variable {name!r} mixes numbers and strings")
        return np.array(out)
    if arr.dtype.kind in "US":
        return arr.ravel().astype(str)
    if arr.dtype.kind == "b":
        return arr.ravel().astype(np.int64)
    if arr.dtype.kind not in "iuf":
        raise ImportMappingError(f"variable {name!r} holds {arr.dtype}, not numbers or strings")
    return arr.ravel(order="C")


def _sample_rate(mapping: ImportMapping, source: Source | None) -> float:
    fs = mapping.sample_rate_hz
    if fs is None:
        raise ImportMappingError(
            "the sampling rate is not given: set 'sample_rate_hz' in the mapping "
            "(or --sample-rate-hz)"
        )
    if isinstance(fs, str):
        if source is None:
            raise ImportMappingError("'sample_rate_hz' must be a number for this format")
        v = np.asarray(source.get(fs))
        if v.size != 1 or v.dtype.kind not in "iuf":
            raise ImportMappingError(f"variable {fs!r} (sample_rate_hz) must be one number")
        value = float(v.ravel()[0])
        if not math.isfinite(value) or value <= 0:
            raise ImportMappingError(
                f"variable {fs!r} (sample_rate_hz) must be positive, got {value}"
            )
        return value
    return float(fs)
