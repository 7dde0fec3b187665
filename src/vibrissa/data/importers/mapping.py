"""The import mapping: where signals and labels are in a source file.

A mapping (a dict, or a JSON/TOML file) is validated by :func:`load_mapping`
into an :class:`ImportMapping`; every format reader takes one. Unknown or
malformed keys raise :class:`ImportMappingError` naming the key. The keys, and
the command-line forms read by :func:`parse_range` and
:func:`parse_axis_option`, are described in ``docs/importing.md``.
"""

from __future__ import annotations

import json
import math
import os
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "FORMATS",
    "FILE_ATTRS",
    "INTEGER_LABELS",
    "UNSET",
    "ImportMapping",
    "ImportMappingError",
    "check_keys",
    "is_number",
    "load_mapping",
    "parse_axis_option",
    "parse_range",
    "round_values",
]

#: File formats :func:`import_recording` reads.
FORMATS = ("mat", "csv", "npz")

_COMMON_KEYS = {
    "format",
    "sample_rate_hz",
    "channels",
    "labels",
    "constants",
    "ragged",
    "empty",
    "t0_s",
    "units",
    "attrs",
}
_ARRAY_KEYS = {"signal", "cell_axes", "time_axis", "trial_axes"}
_CSV_KEYS = {"layout", "trial_column", "time_column"}
#: Default of :attr:`ImportMapping.time_column`: ``"time"`` if the file has that column.
UNSET = object()
#: Labels that count things: integer-valued ranges of these stay integers.
INTEGER_LABELS = frozenset({"set", "run", "order", "direction"})


class ImportMappingError(ValueError):
    """A recording cannot be imported as asked: bad mapping, bad or unreadable file.

    The message names the mapping key, variable, cell, column or line at fault.
    """


#: Dataset attributes the import itself sets, from the file and the mapping's own
#: fields; the mapping's ``attrs`` may not contradict them (nor any ``vibrissa_*``).
FILE_ATTRS = frozenset(
    {
        "sample_rate_hz",
        "source_file",
        "source_format",
        "source_sha256",
        "import_mapping",
        "cropped_from_samples",
    }
)


def _free_attrs(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """The mapping's ``attrs``, refused if they set one the import takes from the file."""
    taken = sorted(str(k) for k in attrs if str(k) in FILE_ATTRS or str(k).startswith("vibrissa_"))
    if taken:
        raise ImportMappingError(
            f"mapping 'attrs' cannot set {taken}: the import takes them from the file and "
            "the mapping's other fields (the sampling rate from 'sample_rate_hz' or the "
            "time column)"
        )
    return dict(attrs)


@dataclass(frozen=True)
class ImportMapping:
    """A validated mapping (``docs/importing.md`` gives the meaning of each key).

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
    time_column: Any = UNSET  # UNSET: "time" if present; None: no time column
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
            if k in entry and not is_number(entry[k]):
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


def is_number(v: Any) -> bool:
    """Whether ``v`` is a finite real number (``bool`` is not a number here)."""
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
            what = "is a directory, not a file" if p.is_dir() else "does not exist"
            raise ImportMappingError(f"mapping file {p} {what}")
        try:
            text = p.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            raise ImportMappingError(f"mapping file {p} is not UTF-8 text") from None
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
        elif not is_number(fs) or fs <= 0:
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
                f"mapping 'labels' must map label names to variable/column names, got {labels!r}"
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
    for key, choices in (
        ("ragged", ("error", "crop")),
        ("empty", ("error", "skip")),
        ("layout", ("long", "wide")),
        ("trial_axes", ("first", "last")),
    ):
        if key in raw:
            if raw[key] not in choices:
                raise ImportMappingError(
                    f"mapping {key!r} must be one of {list(choices)}, got {raw[key]!r}"
                )
            kw[key] = raw[key]
    if "t0_s" in raw:
        if not is_number(raw["t0_s"]):
            raise ImportMappingError(f"mapping 't0_s' must be a number (s), got {raw['t0_s']!r}")
        kw["t0_s"] = float(raw["t0_s"])
    if "units" in raw:
        if not isinstance(raw["units"], str):
            raise ImportMappingError(f"mapping 'units' must be a string, got {raw['units']!r}")
        kw["units"] = raw["units"]
    if "attrs" in raw:
        if not isinstance(raw["attrs"], Mapping):
            raise ImportMappingError("mapping 'attrs' must be an object")
        kw["attrs"] = _free_attrs(raw["attrs"])
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


def round_values(v: np.ndarray) -> np.ndarray:
    """Axis values rounded to 9 decimals, so that ``36 + 7.2 * 1`` is the literal ``43.2``."""
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
        return [float(v) for v in round_values(start + step * np.arange(n))]
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise ImportMappingError("empty list of values")
    try:
        nums2 = [float(t) for t in items]
    except ValueError:
        return items
    return [
        int(x) if x.is_integer() and "." not in t else x for x, t in zip(nums2, items, strict=True)
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
    if name in INTEGER_LABELS and all(
        isinstance(v, int | float) and float(v).is_integer() for v in values
    ):
        values = [int(v) for v in values]
    return {"name": name, "values": values}


def check_keys(mapping: ImportMapping, fmt: str) -> None:
    """Reject the mapping keys that do not apply to files of format ``fmt``.

    Parameters
    ----------
    mapping
        The validated mapping (its ``raw`` keys are checked).
    fmt
        ``"mat"``, ``"csv"`` or ``"npz"``.

    Raises
    ------
    ImportMappingError
        Naming the keys, e.g. CSV keys (``layout``) for a MATLAB file.
    """
    bad = _CSV_KEYS if fmt != "csv" else _ARRAY_KEYS
    wrong = sorted(set(mapping.raw) & bad)
    if wrong:
        raise ImportMappingError(f"mapping key(s) {wrong} do not apply to {fmt} files")
