"""Import real recordings (MATLAB ``.mat``, CSV, NPZ) into the vibrissa Dataset.

A *mapping* (a dict, or a JSON/TOML file) says where the signals and labels are
in the source file. The same mapping keys serve every format; the ones that do
not apply to a format are rejected, and unknown keys are rejected too, so a typo
never passes silently.

The thesis' XY-robot recording
------------------------------
``data_XY.mat`` holds a MATLAB cell array ``data`` of 4 sets x 26 speeds x 101
radial distances, each cell a 750 x 2 double array (samples x channels x, y)
sampled at 1 kHz. This mapping imports it (``vibrissa import data_XY.mat
--mapping xy.json --out xy.nc``)::

    {
      "format": "mat",
      "signal": "data",
      "cell_axes": [
        {"name": "set", "values": [1, 2, 3, 4]},
        {"name": "speed_mm_s", "start": 36, "stop": 216, "num": 26},
        {"name": "radial_distance_mm", "start": 80, "stop": 180, "num": 101}
      ],
      "channels": ["x", "y"],
      "time_axis": 0,
      "sample_rate_hz": 1000,
      "units": "V"
    }

Trial ``n`` of the Dataset is cell ``data{set, speed, radius}`` in C order
(radius fastest), its signal the cell's 750 x 2 array transposed to
channels x samples. ``vibrissa.examples`` ships a small *simulated* file in
exactly this layout, ``data_XY_small.mat`` (4 x 3 x 5 cells), with its mapping
``data_XY_small.mapping.json``.

The same from the command line, with MATLAB colon ranges ``start:step:stop``::

    vibrissa import data_XY.mat --out xy.nc --signal data --axis set=1:4 \\
        --axis speed_mm_s=36:7.2:216 --axis radial_distance_mm=80:180 \\
        --channels x,y --sample-rate-hz 1000

Mapping keys
------------
``format``
    ``"mat"``, ``"csv"`` or ``"npz"``; default from the file's extension.
``sample_rate_hz``
    Sampling rate (Hz): a number, or (mat/npz) the name of a scalar variable in
    the file. Required, except for CSV files with a time column, where it is
    inferred from the median sample spacing.
``channels``
    Channel names, e.g. ``["x", "y"]`` (default ``x``, ``y``, ``z`` or ``ch0``...).
    For CSV, the names of the columns holding the channels.
``signal`` (mat, npz)
    Name of the variable holding the recordings. MATLAB struct fields (v5) and
    HDF5 groups (v7.3) are reached with dots: ``"rec.data"``. May be omitted if
    the file holds exactly one variable.
``cell_axes`` (mat, npz)
    One entry per *trial axis* of the signal, in MATLAB's order: for a cell
    array, its dimensions; for a numeric array, its leading dimensions (the
    remaining one or two dimensions are one recording). Each entry is
    ``{"name": LABEL, ...}`` plus one way to give its values:

    - ``"values": [v1, v2, ...]`` (numbers or strings);
    - ``"start"``, ``"stop"``, ``"num"``: ``num`` evenly spaced values, both ends
      included (like ``numpy.linspace``);
    - ``"start"``, ``"step"`` (optional ``"stop"``, checked): ``start + k*step``,
      one per cell along the axis (like MATLAB ``start:step:stop``);
    - ``"from": VARIABLE``: values read from a variable of the file;
    - nothing: the axis enumerates trials and gives no label if its name is
      ``"trial"``, else the label is the 0-based index along the axis.

    Values are rounded to 9 decimals so that ``36 + 7.2 k`` equals the literal
    ``43.2``. Ranges give floats, except integer-valued ranges of the counting
    labels ``set``, ``run``, ``order`` and ``direction``, which give integers;
    ``values`` keep the types given. The number of values must equal the size of the axis. Singleton
    dimensions (MATLAB's 1 x N cell arrays) may be left out of ``cell_axes``.
    Default: ``[{"name": "trial"}]`` (a 1-D cell array, or the first axis of a
    numeric array). **Trial order** is C order over the trial axes: the last
    axis varies fastest (for ``data_XY``: set, then speed, then radius).
``trial_axes`` (numeric mat/npz arrays)
    ``"first"`` (default): the trial axes lead, e.g. trials x samples x
    channels; ``"last"``: they trail, as MATLAB users often store them, e.g. a
    750 x 2 x N array of N recordings (samples x channels x trials).
``time_axis`` (mat, npz)
    Which axis of one recording is time: ``0`` (default; MATLAB's samples x
    channels) or ``1`` (channels x samples, vibrissa's own layout). A 1-D
    recording is one channel.
``labels``
    Per-trial labels read from the file: ``{"label": "variable"}`` (mat/npz; a
    variable with one value per trial, or shaped like the trial axes) or
    ``{"label": "column"}`` / ``["column", ...]`` (CSV).
``constants``
    Labels with one value for every trial, e.g. ``{"texture": "P80"}``.
``ragged``
    ``"error"`` (default): recordings of different lengths raise a
    :class:`ImportMappingError` naming the first cell/trial that differs from
    the first.
    ``"crop"``: every recording is cut to the shortest, keeping its *first*
    samples (so recordings must start at the same event); the attribute
    ``cropped_from_samples`` records the longest original length.
``empty``
    ``"error"`` (default) or ``"skip"``: what to do with empty cells (MATLAB
    ``[]``, a missing trial); skipped cells give no trial.
``t0_s``
    Time of the first sample relative to the alignment point (s; default 0).
    E.g. ``-0.325`` for recordings aligned to start 325 ms before the peak.
``units``
    Units of the signal (default ``"V"``).
``attrs``
    Extra dataset attributes (``protocol``, ``whisker``, ``robot``, ...).
    ``protocol`` defaults to ``"imported"``.
``layout``, ``trial_column``, ``time_column`` (CSV)
    See below.

CSV layouts
-----------
``"layout": "long"`` (default): one row per sample, with a trial-id column
(``trial_column``, default ``"trial"``), optionally a time column in seconds
(``time_column``, default ``"time"`` if present; ``null`` to ignore), one
column per channel (``channels``; default every other numeric column that is
not a label) and label columns (``labels``), which must be constant within a
trial. Trials are taken in order of first appearance; samples in file order,
or sorted by time when there is a time column. Example::

    trial,time,x,y,speed_mm_s,texture
    0,0.000,2.51,2.50,36,P80
    0,0.001,2.53,2.49,36,P80
    ...

``"layout": "wide"``: one row per trial, label columns plus, for every channel
``c``, sample columns ``c_0, c_1, ...`` in time order. A recording shorter than
the others leaves its last cells empty (a ragged recording).

MATLAB v7.3 (HDF5) files
------------------------
Read with :mod:`h5py` assuming MATLAB's own layout: each variable is an HDF5
dataset whose ``MATLAB_class`` attribute names its class, stored with its
dimensions reversed (MATLAB is column-major), so it is transposed back here; a
cell array is a dataset of object references (class ``cell``) to datasets in
the ``#refs#`` group; an empty array is a dims vector with attribute
``MATLAB_empty``; ``char`` arrays are UTF-16 code units; structs are groups.
Complex, sparse and object-class (``MATLAB_class`` ``"function_handle"``,
classdef objects) data are not supported and raise :class:`ImportMappingError`.

Errors
------
Every problem with the source file or the mapping raises
:class:`ImportMappingError` (a :class:`ValueError`) with a one-line message
naming the file, the variable/column, the cell (MATLAB style, 1-based:
``cell data{2,3,17}``) or trial, and what to change: unknown or malformed
mapping keys, a missing variable/field/column, ragged or empty recordings,
non-numeric cells, NaN or infinite samples (how many, and the first one),
``cell_axes`` that do not match the cell array's shape, an unknown file type,
an unreadable, corrupt or truncated file. A source that does not exist raises
:class:`FileNotFoundError`.

Safety
------
The source file is only ever opened for reading; NPZ files are read without
pickle support. :func:`import_file` writes the Dataset through
:func:`vibrissa.data.save_dataset` (atomic) and refuses to write over its
source.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import tomllib
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.data.dataset import make_dataset

__all__ = [
    "FORMATS",
    "ImportMapping",
    "ImportMappingError",
    "detect_format",
    "import_file",
    "import_recording",
    "load_mapping",
    "parse_axis_option",
    "parse_range",
]

#: File formats :func:`import_recording` reads.
FORMATS = ("mat", "csv", "npz")

_EXTENSIONS = {".mat": "mat", ".csv": "csv", ".txt": "csv", ".npz": "npz"}
_COMMON_KEYS = {
    "format", "sample_rate_hz", "channels", "labels", "constants", "ragged", "empty", "t0_s",
    "units", "attrs",
}
_ARRAY_KEYS = {"signal", "cell_axes", "time_axis", "trial_axes"}
_CSV_KEYS = {"layout", "trial_column", "time_column"}
_UNSET = object()
#: Labels that count things: integer-valued ranges of these stay integers.
_INTEGER_LABELS = frozenset({"set", "run", "order", "direction"})




class ImportMappingError(ValueError):
    """A recording cannot be imported as asked: bad mapping, bad or unreadable file.

    The message names the mapping key, variable, cell, column or line at fault.
    """


# --------------------------------------------------------------------------- mapping


@dataclass(frozen=True)
class ImportMapping:
    """A validated mapping (see the module docstring for the meaning of each key).

    Build it with :func:`load_mapping`.
    """

    format: str | None = None
    sample_rate_hz: float | str | None = None
    channels: tuple[str, ...] | None = None
    signal: str | None = None
    cell_axes: tuple[dict[str, Any], ...] | None = None
    time_axis: int = 0
    labels: dict[str, str] = field(default_factory=dict)
    constants: dict[str, Any] = field(default_factory=dict)
    ragged: str = "error"
    empty: str = "error"
    t0_s: float = 0.0
    units: str = "V"
    attrs: dict[str, Any] = field(default_factory=dict)
    trial_axes: str = "first"
    layout: str = "long"
    trial_column: str = "trial"
    time_column: Any = _UNSET  # _UNSET: "time" if present; None: no time column
    raw: dict[str, Any] = field(default_factory=dict, compare=False)


def _check_axis_entry(i: int, entry: Any) -> dict[str, Any]:
    where = f"mapping 'cell_axes'[{i}]"
    if isinstance(entry, str):
        entry = {"name": entry}
    if not isinstance(entry, Mapping):
        raise ImportMappingError(f"{where} must be an object with a 'name', got {entry!r}")
    entry = dict(entry)
    allowed = {"name", "values", "start", "stop", "num", "step", "from"}
    extra = sorted(set(entry) - allowed)
    if extra:
        raise ImportMappingError(f"{where} has unknown key(s) {extra}; allowed: {sorted(allowed)}")
    name = entry.get("name")
    if not isinstance(name, str) or not name:
        raise ImportMappingError(f"{where} needs a 'name' (a label such as 'speed_mm_s')")
    ways = [k for k in ("values", "from") if k in entry] + (["start"] if "start" in entry else [])
    if len(ways) > 1:
        raise ImportMappingError(
            f"{where} ({name!r}) gives its values in more than one way: {ways}"
        )
    if "start" in entry:
        if ("num" in entry) == ("step" in entry):
            raise ImportMappingError(
                f"{where} ({name!r}) needs either 'num' (with 'stop') or 'step' with 'start'"
            )
        if "num" in entry and "stop" not in entry:
            raise ImportMappingError(f"{where} ({name!r}) needs 'stop' with 'num'")
        for k in ("start", "stop", "step", "num"):
            if k in entry and not _is_number(entry[k]):
                raise ImportMappingError(
                    f"{where} ({name!r}): {k!r} must be a number, got {entry[k]!r}"
                )
        if "step" in entry and float(entry["step"]) == 0:
            raise ImportMappingError(f"{where} ({name!r}): 'step' must not be 0")
    elif any(k in entry for k in ("stop", "num", "step")):
        raise ImportMappingError(f"{where} ({name!r}): 'stop'/'num'/'step' need 'start'")
    if "values" in entry and (
        isinstance(entry["values"], str | bytes) or not isinstance(entry["values"], Sequence)
    ):
        raise ImportMappingError(f"{where} ({name!r}): 'values' must be a list")
    if "from" in entry and not isinstance(entry["from"], str):
        raise ImportMappingError(f"{where} ({name!r}): 'from' must be a variable name")
    return entry


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def load_mapping(source: Mapping[str, Any] | str | os.PathLike[str] | None) -> ImportMapping:
    """Read and validate a mapping.

    Parameters
    ----------
    source
        A dict, a path to a ``.json`` or ``.toml`` file, or ``None`` (an empty
        mapping, to be completed by command-line options).

    Returns
    -------
    ImportMapping

    Raises
    ------
    ImportMappingError
        If the file cannot be parsed or a key is unknown or malformed (the
        message names the key).
    """
    if source is None:
        raw: dict[str, Any] = {}
    elif isinstance(source, Mapping):
        raw = dict(source)
    else:
        p = Path(source)
        if not p.is_file():
            raise ImportMappingError(f"mapping file {p} does not exist")
        text = p.read_text(encoding="utf-8")
        try:
            raw = tomllib.loads(text) if p.suffix.lower() == ".toml" else json.loads(text)
        except (ValueError, tomllib.TOMLDecodeError) as exc:
            kind = "TOML" if p.suffix.lower() == ".toml" else "JSON"
            raise ImportMappingError(f"mapping file {p} is not valid {kind}: {exc}") from None
        if not isinstance(raw, dict):
            raise ImportMappingError(f"mapping file {p} must hold an object (key: value pairs)")
    unknown = sorted(set(raw) - _COMMON_KEYS - _ARRAY_KEYS - _CSV_KEYS)
    if unknown:
        raise ImportMappingError(
            f"unknown mapping key(s) {unknown}; known: "
            f"{sorted(_COMMON_KEYS | _ARRAY_KEYS | _CSV_KEYS)}"
        )
    kw: dict[str, Any] = {"raw": raw}
    fmt = raw.get("format")
    if fmt is not None:
        if fmt not in FORMATS:
            raise ImportMappingError(
                f"mapping 'format' must be one of {list(FORMATS)}, got {fmt!r}"
            )
        kw["format"] = fmt
    fs = raw.get("sample_rate_hz")
    if fs is not None:
        if isinstance(fs, str):
            kw["sample_rate_hz"] = fs
        elif not _is_number(fs) or fs <= 0:
            raise ImportMappingError(
                f"mapping 'sample_rate_hz' must be a positive number, got {fs!r}"
            )
        else:
            kw["sample_rate_hz"] = float(fs)
    if raw.get("channels") is not None:
        ch = raw["channels"]
        if isinstance(ch, str):
            ch = [c.strip() for c in ch.split(",")]
        if not isinstance(ch, Sequence) or not ch or not all(isinstance(c, str) and c for c in ch):
            raise ImportMappingError(f"mapping 'channels' must be a list of names, got {ch!r}")
        if len(set(ch)) != len(ch):
            raise ImportMappingError(f"mapping 'channels' has repeated names: {list(ch)}")
        kw["channels"] = tuple(ch)
    if raw.get("signal") is not None:
        if not isinstance(raw["signal"], str):
            raise ImportMappingError(
                f"mapping 'signal' must be a variable name, got {raw['signal']!r}"
            )
        kw["signal"] = raw["signal"]
    if raw.get("cell_axes") is not None:
        axes = raw["cell_axes"]
        if isinstance(axes, str) or not isinstance(axes, Sequence) or not axes:
            raise ImportMappingError("mapping 'cell_axes' must be a non-empty list of axes")
        entries = tuple(_check_axis_entry(i, a) for i, a in enumerate(axes))
        names = [e["name"] for e in entries if e["name"] != "trial"]
        if len(set(names)) != len(names):
            raise ImportMappingError(f"mapping 'cell_axes' repeats a label name: {names}")
        kw["cell_axes"] = entries
    if "time_axis" in raw:
        ta = raw["time_axis"]
        if isinstance(ta, bool) or not isinstance(ta, int) or ta not in (0, 1, -1, -2):
            raise ImportMappingError(f"mapping 'time_axis' must be 0 or 1, got {ta!r}")
        kw["time_axis"] = ta
    labels = raw.get("labels")
    if labels is not None:
        if isinstance(labels, Sequence) and not isinstance(labels, str):
            labels = {str(c): str(c) for c in labels}
        if not isinstance(labels, Mapping) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in labels.items()
        ):
            raise ImportMappingError(
                "mapping 'labels' must map label names to variable/column names, "
                f"got {labels!r}"
            )
        kw["labels"] = dict(labels)
    consts = raw.get("constants")
    if consts is not None:
        if not isinstance(consts, Mapping) or not all(
            isinstance(v, str | int | float) and not isinstance(v, bool) for v in consts.values()
        ):
            raise ImportMappingError(
                f"mapping 'constants' must map label names to a number or string, got {consts!r}"
            )
        kw["constants"] = dict(consts)
    for key, choices in (("ragged", ("error", "crop")), ("empty", ("error", "skip")),
                         ("layout", ("long", "wide")), ("trial_axes", ("first", "last"))):
        if key in raw:
            if raw[key] not in choices:
                raise ImportMappingError(
                    f"mapping {key!r} must be one of {list(choices)}, got {raw[key]!r}"
                )
            kw[key] = raw[key]
    if "t0_s" in raw:
        if not _is_number(raw["t0_s"]):
            raise ImportMappingError(f"mapping 't0_s' must be a number (s), got {raw['t0_s']!r}")
        kw["t0_s"] = float(raw["t0_s"])
    if "units" in raw:
        if not isinstance(raw["units"], str):
            raise ImportMappingError(f"mapping 'units' must be a string, got {raw['units']!r}")
        kw["units"] = raw["units"]
    if "attrs" in raw:
        if not isinstance(raw["attrs"], Mapping):
            raise ImportMappingError("mapping 'attrs' must be an object")
        kw["attrs"] = dict(raw["attrs"])
    if "trial_column" in raw:
        if not isinstance(raw["trial_column"], str):
            raise ImportMappingError("mapping 'trial_column' must be a column name")
        kw["trial_column"] = raw["trial_column"]
    if "time_column" in raw:
        if raw["time_column"] is not None and not isinstance(raw["time_column"], str):
            raise ImportMappingError("mapping 'time_column' must be a column name or null")
        kw["time_column"] = raw["time_column"]
    all_labels = [e["name"] for e in kw.get("cell_axes", ()) if e["name"] != "trial"]
    all_labels += list(kw.get("labels", {})) + list(kw.get("constants", {}))
    dup = sorted({n for n in all_labels if all_labels.count(n) > 1})
    if dup:
        raise ImportMappingError(f"label(s) {dup} given more than once in the mapping")
    return ImportMapping(**kw)


def _round_values(v: np.ndarray) -> np.ndarray:
    return np.round(v, 9) + 0.0  # + 0.0 turns -0.0 into 0.0


def parse_range(text: str) -> list[Any]:
    """Values from a command-line axis specification.

    Parameters
    ----------
    text
        ``"a:b"`` (MATLAB ``a:b``, step 1), ``"a:step:b"`` (MATLAB colon
        syntax, ``b`` included when reached) giving floats, or a comma-separated
        list ``"1,2,4"`` / ``"P80,P180"`` (numbers if all parse, integers where
        written without a point; else strings).

    Returns
    -------
    list

    Raises
    ------
    ImportMappingError
        If a range is malformed or empty.
    """
    text = text.strip()
    if ":" in text:
        parts = text.split(":")
        try:
            nums = [float(p) for p in parts]
        except ValueError:
            raise ImportMappingError(
                f"range {text!r} must be start:stop or start:step:stop"
            ) from None
        if len(nums) == 2:
            start, step, stop = nums[0], 1.0, nums[1]
        elif len(nums) == 3:
            start, step, stop = nums
        else:
            raise ImportMappingError(f"range {text!r} must be start:stop or start:step:stop")
        if step == 0 or not all(math.isfinite(x) for x in (start, step, stop)):
            raise ImportMappingError(f"range {text!r} needs a finite, non-zero step")
        n = math.floor((stop - start) / step + 1e-9) + 1
        if n < 1:
            raise ImportMappingError(f"range {text!r} is empty")
        return [float(v) for v in _round_values(start + step * np.arange(n))]
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise ImportMappingError("empty list of values")
    try:
        nums2 = [float(t) for t in items]
    except ValueError:
        return items
    return [
        int(x) if x.is_integer() and "." not in t else x
        for x, t in zip(nums2, items, strict=True)
    ]


def parse_axis_option(text: str) -> dict[str, Any]:
    """One ``cell_axes`` entry from a command-line ``--axis`` value.

    Parameters
    ----------
    text
        ``NAME=SPEC`` (``SPEC`` read by :func:`parse_range`; integer-valued
        ranges of ``set``/``run``/``order``/``direction`` give integers),
        ``NAME=@VARIABLE`` (values from a variable of the source file) or a bare
        ``NAME`` (index labels, or none for ``trial``).

    Returns
    -------
    dict
        The mapping entry, e.g. ``{"name": "set", "values": [1, 2, 3, 4]}``.

    Raises
    ------
    ImportMappingError
        Naming the option if the name is empty or the values malformed.
    """
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not name:
        raise ImportMappingError(f"--axis {text!r}: give NAME=VALUES, e.g. speed_mm_s=36:7.2:216")
    if not sep:
        return {"name": name}
    spec = spec.strip()
    if spec.startswith("@"):
        return {"name": name, "from": spec[1:]}
    try:
        values = parse_range(spec)
    except ValueError as exc:
        raise ImportMappingError(f"--axis {text!r}: {exc}") from None
    if name in _INTEGER_LABELS and all(
        isinstance(v, int | float) and float(v).is_integer() for v in values
    ):
        values = [int(v) for v in values]
    return {"name": name, "values": values}


def _axis_values(
    entry: dict[str, Any], size: int, where: str, source: _Source | None, what: str = ""
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
            vals = _round_values(np.linspace(start, float(entry["stop"]), num))
        else:
            step = float(entry["step"])
            vals = _round_values(start + step * np.arange(size))
            if "stop" in entry and not math.isclose(
                float(vals[-1]), float(entry["stop"]), rel_tol=1e-9, abs_tol=1e-9
            ):
                raise ImportMappingError(
                    f"{where} ({name!r}): {size} values from {start:g} in steps of {step:g} end "
                    f"at {float(vals[-1]):g}, not at 'stop' {float(entry['stop']):g}; "
                    f"{what or 'the signal'} has {size} along this axis"
                )
        if name in _INTEGER_LABELS and np.all(vals == np.round(vals)):
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


# --------------------------------------------------------------------------- sources


class _Source:
    """A file's named arrays (MATLAB dimension order)."""

    kind = "?"

    def names(self) -> list[str]:
        raise NotImplementedError

    def get(self, name: str) -> np.ndarray:
        raise NotImplementedError

    def pick_signal(self, name: str | None) -> str:
        if name is not None:
            return name
        names = self.names()
        if len(names) != 1:
            raise ImportMappingError(
                f"the file holds variables {names}; say which is the signal with 'signal'"
            )
        return names[0]


class _DictSource(_Source):
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


#: What h5py raises on damaged files (besides ValueError).
_H5_ERRORS = (OSError, KeyError, RuntimeError, TypeError)


class _H5MatSource(_Source):
    """MATLAB v7.3 file read with h5py (see the module docstring)."""

    kind = "mat v7.3"

    def __init__(self, path: Path, f: Any) -> None:
        self.path = path
        self.f = f

    def names(self) -> list[str]:
        try:
            return sorted(k for k in self.f.keys() if not k.startswith("#"))
        except _H5_ERRORS as exc:
            raise ImportMappingError(
                f"{self.path}: cannot list its variables (corrupt or truncated file?): {exc}"
            ) from None

    def get(self, name: str) -> np.ndarray:
        try:
            return self._get(name)
        except _H5_ERRORS as exc:  # damaged HDF5 objects
            raise ImportMappingError(
                f"{self.path}: variable {name!r} cannot be read (corrupt or truncated "
                f"file?): {exc}"
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
                    if isinstance(obj, h5py.Group) else []
                )
                raise ImportMappingError(
                    f"{self.path}: {where} has no variable/field {part!r}; it has {have}"
                )
            obj = obj[part]
            walked = f"{walked}.{part}" if walked else part
        if isinstance(obj, h5py.Group):
            raise ImportMappingError(f"{self.path}: {name!r} is a struct; name one of its fields")
        return self._read(obj, name)

    def _read(self, ds: Any, where: str) -> np.ndarray:
        import h5py

        cls = ds.attrs.get("MATLAB_class", b"")
        cls = cls.decode() if isinstance(cls, bytes) else str(cls)
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


@contextmanager
def _open_source(path: Path, fmt: str) -> Iterator[_Source]:
    if fmt == "npz":
        try:
            with np.load(path, allow_pickle=False) as z:
                variables = {k: _npz_get(path, z, k) for k in z.files}
        except ValueError as exc:
            raise ImportMappingError(f"{path}: {exc}") from None
        except Exception as exc:  # zipfile.BadZipFile, OSError, EOFError
            raise ImportMappingError(f"{path}: cannot be read as an NPZ file: {exc}") from None
        yield _DictSource(path, variables, "npz")
        return
    import h5py

    if h5py.is_hdf5(path):
        try:
            f = h5py.File(path, "r")
        except OSError as exc:
            raise ImportMappingError(
                f"{path}: cannot be read as a MATLAB v7.3 (HDF5) file: {exc}"
            ) from None
        with f:
            yield _H5MatSource(path, f)
        return
    import scipy.io

    try:
        variables = scipy.io.loadmat(
            path, squeeze_me=False, struct_as_record=True, chars_as_strings=True
        )
    except NotImplementedError as exc:
        raise ImportMappingError(f"{path}: unsupported MATLAB file: {exc}") from None
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError, ...
        raise ImportMappingError(f"{path}: cannot be read as a MATLAB .mat file: {exc}") from None
    yield _DictSource(path, variables, "mat v5")


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


# --------------------------------------------------------------------------- helpers


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


def _sample_rate(mapping: ImportMapping, source: _Source | None) -> float:
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


def _equalise(
    recs: list[np.ndarray], names: list[str], ragged: str
) -> tuple[np.ndarray, int | None]:
    """Stack recordings (n_channels, n_samples_i) into one array, cropping if allowed."""
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
                "set \"ragged\": \"crop\" (--crop) to cut all to the shortest"
            )
        cropped_from = int(lengths.max())
        n = int(lengths.min())
        if n == 0:
            raise ImportMappingError(
                f"{names[int(np.argmin(lengths))]} has no samples; cannot crop"
            )
        recs = [r[:, :n] for r in recs]
    return np.stack(recs), cropped_from


def _file_sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


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


def _check_keys(mapping: ImportMapping, fmt: str) -> None:
    bad = _CSV_KEYS if fmt != "csv" else _ARRAY_KEYS
    wrong = sorted(set(mapping.raw) & bad)
    if wrong:
        raise ImportMappingError(f"mapping key(s) {wrong} do not apply to {fmt} files")


# --------------------------------------------------------------------------- arrays (mat/npz)


def _import_array(source: _Source, mapping: ImportMapping) -> dict[str, Any]:
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
                f"{nm} is empty; set \"empty\": \"skip\" (--skip-empty) to leave it out"
            )
        recs.append(_numeric_recording(c, nm, mapping.time_axis, matlab_vectors=is_cell))
        rec_names.append(nm)
        kept_idx.append(gi)
        keep_mask.append(True)
    if not recs:
        raise ImportMappingError(f"signal {name!r} holds no recordings")
    signal, cropped_from = _equalise(recs, rec_names, mapping.ragged)
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
    return {"signal": signal, "labels": labels, "cropped_from": cropped_from,
            "sample_rate_hz": _sample_rate(mapping, source), "time": None, "signal_name": name}


# --------------------------------------------------------------------------- CSV


def _read_csv(path: Path) -> Any:
    import pandas as pd

    try:
        return pd.read_csv(path)
    except UnicodeDecodeError:
        raise ImportMappingError(f"{path}: is not a text CSV file") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise ImportMappingError(f"{path}: cannot be read as CSV: {exc}") from None


def _numeric_column(df: Any, col: str, path: Path) -> np.ndarray:
    import pandas as pd

    s = df[col]
    num = pd.to_numeric(s, errors="coerce")
    bad = num.isna() & s.notna()
    if bool(bad.any()):
        row = int(np.flatnonzero(bad.to_numpy())[0])
        raise ImportMappingError(
            f"{path}: column {col!r} must hold numbers; line {row + 2} has {s.iloc[row]!r}"
        )
    return num.to_numpy(dtype=float)


def _import_csv(path: Path, mapping: ImportMapping) -> dict[str, Any]:
    df = _read_csv(path)
    cols = [str(c) for c in df.columns]
    df.columns = cols
    label_cols = dict(mapping.labels)
    for label, col in label_cols.items():
        if col not in cols:
            raise ImportMappingError(
                f"{path}: no column {col!r} (label {label!r}); columns: {cols}"
            )
    if mapping.layout == "wide":
        return _import_csv_wide(path, df, mapping, label_cols)
    tcol = mapping.trial_column
    if tcol not in cols:
        raise ImportMappingError(
            f"{path}: no trial column {tcol!r} (long layout: one row per sample); "
            f"columns: {cols}. Set 'trial_column', or \"layout\": \"wide\""
        )
    time_col = mapping.time_column
    if time_col is _UNSET:
        time_col = "time" if "time" in cols else None
    if time_col is not None and time_col not in cols:
        raise ImportMappingError(f"{path}: no time column {time_col!r}; columns: {cols}")
    used = {tcol, time_col, *label_cols.values()}
    if mapping.channels is not None:
        chans = list(mapping.channels)
        missing = [c for c in chans if c not in cols]
        if missing:
            raise ImportMappingError(f"{path}: no channel column(s) {missing}; columns: {cols}")
    else:
        chans = [c for c in cols if c not in used and df[c].dtype.kind in "iuf"]
        if not chans:
            raise ImportMappingError(f"{path}: no numeric channel columns; give 'channels'")
    values = np.column_stack([_numeric_column(df, c, path) for c in chans])
    trial_ids = df[tcol].to_numpy()
    if df[tcol].isna().any():
        raise ImportMappingError(f"{path}: column {tcol!r} has empty cells")
    times = _numeric_column(df, time_col, path) if time_col else None
    _, first, inverse = np.unique(trial_ids.astype(str), return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")  # trials in order of first appearance
    recs, names, rec_times, labels_rows = [], [], [], []
    for u in order:
        rows = np.flatnonzero(inverse == u)
        tid = trial_ids[rows[0]]
        tid = tid.item() if isinstance(tid, np.generic) else tid
        nm = f"trial {tid!r} of {path.name}"
        if times is not None:
            rows = rows[np.argsort(times[rows], kind="stable")]
            rec_times.append(times[rows])
        block = values[rows]
        finite = np.isfinite(block)
        if not finite.all():
            r, c = np.argwhere(~finite)[0]
            raise ImportMappingError(
                f"{nm} has {int(np.count_nonzero(~finite))} empty, NaN or infinite sample "
                f"value(s); the first is column {chans[int(c)]!r} on line {int(rows[r]) + 2}"
            )
        recs.append(block.T)
        names.append(nm)
        row_labels = {}
        for label, col in label_cols.items():
            vals = df[col].iloc[rows]
            if vals.nunique(dropna=False) != 1:
                raise ImportMappingError(
                    f"{nm}: label column {col!r} is not constant within the trial "
                    f"({sorted(map(str, vals.unique()))[:5]})"
                )
            row_labels[label] = vals.iloc[0]
        labels_rows.append(row_labels)
    signal, cropped_from = _equalise(recs, names, mapping.ragged)
    n_t = signal.shape[2]
    time = None
    fs = mapping.sample_rate_hz
    if times is not None:
        tt = [t[:n_t] for t in rec_times]
        if n_t > 1 and fs is None:
            d = np.median(np.diff(tt[0]))
            if not d > 0:
                raise ImportMappingError(f"{path}: time column {time_col!r} does not increase")
            fs = 1.0 / float(d)
        if all(np.allclose(t, tt[0], rtol=0, atol=1e-9) for t in tt):
            time = tt[0]
    if fs is None:
        raise ImportMappingError(
            "the sampling rate is not given: set 'sample_rate_hz' in the mapping"
        )
    if isinstance(fs, str):
        raise ImportMappingError("'sample_rate_hz' must be a number for CSV files")
    labels = {label: _label_values([r[label] for r in labels_rows]) for label in label_cols}
    return {"signal": signal, "labels": labels, "cropped_from": cropped_from,
            "sample_rate_hz": float(fs), "time": time, "channels": chans, "signal_name": None}


def _label_values(vals: list[Any]) -> np.ndarray:
    arr = np.asarray(vals)
    return arr.astype(str) if arr.dtype.kind in "OSU" else arr


def _import_csv_wide(
    path: Path, df: Any, mapping: ImportMapping, label_cols: dict[str, str]
) -> dict[str, Any]:
    cols = list(df.columns)
    chans = list(mapping.channels) if mapping.channels is not None else None
    if chans is None:
        prefixes = sorted({m.group(1) for c in cols if (m := re.fullmatch(r"(.+)_(\d+)", c))
                           and c not in label_cols.values()})
        if not prefixes:
            raise ImportMappingError(f"{path}: no sample columns named CHANNEL_0, CHANNEL_1, ...")
        chans = prefixes
    blocks = []
    for ch in chans:
        idx = sorted(
            (int(m.group(1)), c) for c in cols if (m := re.fullmatch(re.escape(ch) + r"_(\d+)", c))
        )
        if not idx:
            raise ImportMappingError(
                f"{path}: no sample columns {ch}_0, {ch}_1, ... for channel {ch!r}"
            )
        expected = list(range(len(idx)))
        if [i for i, _ in idx] != expected:
            raise ImportMappingError(
                f"{path}: sample columns of channel {ch!r} are not {ch}_0..{ch}_{len(idx) - 1}"
            )
        blocks.append(np.column_stack([_numeric_column(df, c, path) for _, c in idx]))
    recs, names = [], []
    for i in range(len(df)):
        nm = f"row {i + 2} of {path.name}"
        rec = [b[i] for b in blocks]
        lengths = []
        for ch, r in zip(chans, rec, strict=True):
            finite = np.isfinite(r)
            n = int(np.argmin(finite)) if not finite.all() else r.size
            if finite[n:].any():
                raise ImportMappingError(
                    f"{nm}: channel {ch!r} has an empty or NaN sample inside the recording"
                )
            lengths.append(n)
        if len(set(lengths)) != 1:
            raise ImportMappingError(f"{nm}: channels have different numbers of samples {lengths}")
        recs.append(np.stack([r[: lengths[0]] for r in rec]))
        names.append(nm)
    if not recs:
        raise ImportMappingError(f"{path}: has no rows")
    signal, cropped_from = _equalise(recs, names, mapping.ragged)
    if mapping.sample_rate_hz is None or isinstance(mapping.sample_rate_hz, str):
        raise ImportMappingError("the sampling rate is not given: set 'sample_rate_hz' (a number)")
    labels = {label: _label_values(df[col].tolist()) for label, col in label_cols.items()}
    return {"signal": signal, "labels": labels, "cropped_from": cropped_from,
            "sample_rate_hz": float(mapping.sample_rate_hz), "time": None, "channels": chans,
            "signal_name": None}


# --------------------------------------------------------------------------- public API


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
        Where signals and labels are (see the module docstring): an
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
    _check_keys(m, fmt)
    if fmt == "csv":
        res = _import_csv(path, m)
        kind = "csv"
    else:
        with _open_source(path, fmt) as src:
            res = _import_array(src, m)
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
            signal, sample_rate_hz=fs, channels=channels, time=time, labels=labels,
            attrs=attrs, units=m.units,
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
