"""The Dataset schema shared by simulated and imported recordings.

An :class:`xarray.Dataset` with

- data variable ``signal`` of dims ``(trial, channel, time)`` (float64, ``units``
  attribute, volts for Hall-sensor output);
- coordinate ``channel`` (strings) and ``time`` (seconds; relative to the
  alignment point for robot trials);
- per-trial coordinates (dim ``trial``) for every contact parameter that applies:
  ``radial_distance_mm``, ``speed_mm_s``, ``angle_deg``, ``texture`` (string),
  ``direction`` (+1/-1), ``run``, ``set``, ``order`` and any other label a user
  imports;
- attrs ``sample_rate_hz``, ``whisker``, ``robot``, ``protocol_params`` (JSON
  strings), ``protocol``, ``seed``, ``vibrissa_version``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from vibrissa import __version__
from vibrissa.data.schema import encode_texture, parse_whisker

__all__ = [
    "KNOWN_LABELS",
    "as_arrays",
    "attr_value",
    "concat_datasets",
    "coordinate_attrs",
    "signal_coords",
    "label_names",
    "make_dataset",
    "select",
    "validate_dataset",
    "whisker_params",
]

_RESERVED = frozenset({"trial", "channel", "time", "signal"})

#: Contact parameters with a conventional name and unit.
KNOWN_LABELS = (
    "radial_distance_mm",
    "speed_mm_s",
    "angle_deg",
    "texture",
    "direction",
    "run",
    "set",
    "order",
)


#: ``long_name`` and ``units`` of the coordinates vibrissa writes (``units`` "1": a
#: count or flag; no ``units`` for text).
_COORD_ATTRS: dict[str, tuple[str, str | None]] = {
    "trial": ("trial index", "1"),
    "channel": ("sensor channel", None),
    "time": ("time from the alignment point", "s"),
    "radial_distance_mm": ("radial distance of the contact from the whisker base", "mm"),
    "speed_mm_s": ("speed of the contact", "mm/s"),
    "angle_deg": ("angle of the direction of motion", "degree"),
    "texture": ("surface texture", None),
    "direction": ("direction of motion (+1 or -1)", "1"),
    "run": ("run (recording session)", "1"),
    "set": ("recorded set", "1"),
    "order": ("position in the recording session", "1"),
    "contact_onset_s": ("time of contact onset", "s"),
    "threshold_time_s": ("time the threshold was crossed", "s"),
    "retract_start_s": ("time the retraction started", "s"),
    "contact_end_s": ("time contact ended", "s"),
    "slipped_off": ("the whisker slipped off the object (0 or 1)", "1"),
    "saturated": ("the sensor saturated (0 or 1)", "1"),
    "latency_s": ("latency of the robot's response", "s"),
    "contact_duration_s": ("duration of contact", "s"),
    "peak_deflection_v": ("peak deflection", "V"),
}
_UNIT_SUFFIXES = (
    ("_mm_s", "mm/s"),
    ("_mm", "mm"),
    ("_ms", "ms"),
    ("_s", "s"),
    ("_hz", "Hz"),
    ("_deg", "degree"),
    ("_v", "V"),
)


def signal_coords(
    n_trials: int,
    channels: Sequence[str],
    n_samples: int,
    sample_rate_hz: float,
    time_long_name: str,
    labels: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The ``trial``, ``channel`` and ``time`` coordinates and ``labels`` of a simulated dataset.

    The ``labels`` are per trial (name -> one value per trial), with their attributes.

    ``time`` runs from 0 in steps of ``1 / sample_rate_hz`` s; ``time_long_name`` says
    from what.
    """
    coords: dict[str, Any] = {
        "trial": np.arange(int(n_trials)),
        "channel": np.array(list(channels)),
        "time": (
            "time",
            np.arange(int(n_samples)) / float(sample_rate_hz),
            {"units": "s", "long_name": time_long_name},
        ),
    }
    for name, vals in (labels or {}).items():
        coords[name] = ("trial", vals, coordinate_attrs(name, vals))
    return coords


def coordinate_attrs(name: str, values: Any = None) -> dict[str, str]:
    """``long_name`` and ``units`` attributes of the coordinate ``name``.

    Parameters
    ----------
    name
        A coordinate: the schema's own (``time``, ``radial_distance_mm``, ...) or
        any label, whose unit is read from its name's suffix (``_mm``, ``_mm_s``,
        ``_s``, ``_ms``, ``_hz``, ``_deg``, ``_v``).
    values
        The coordinate's values; text gets no ``units``.

    Returns
    -------
    dict
        ``long_name`` always; ``units`` when known.
    """
    long_name, units = _COORD_ATTRS.get(name, (name.replace("_", " "), None))
    if name not in _COORD_ATTRS:
        units = next((u for suffix, u in _UNIT_SUFFIXES if name.endswith(suffix)), None)
    if values is not None and np.asarray(values).dtype.kind in "OUS":
        units = None
    return {"long_name": long_name} if units is None else {"long_name": long_name, "units": units}


def make_dataset(
    signal: np.ndarray,
    *,
    sample_rate_hz: float,
    channels: Sequence[str] | None = None,
    time: np.ndarray | None = None,
    labels: Mapping[str, Sequence[Any]] | None = None,
    attrs: Mapping[str, Any] | None = None,
    units: str = "V",
) -> xr.Dataset:
    """Build a validated Dataset from arrays.

    Parameters
    ----------
    signal
        Shape ``(n_trials, n_channels, n_timepoints)``; a 2-D array is taken as one
        channel.
    sample_rate_hz
        Sampling rate (Hz).
    channels
        Channel names (default ``x``, ``y``, ... or ``ch0``...).
    time
        Time of each sample (s); default ``index / sample_rate_hz``.
    labels
        Per-trial labels, each of length ``n_trials``.
    attrs
        Extra attributes; dicts are stored as JSON strings.
    units
        Units of the signal.

    Returns
    -------
    xarray.Dataset
        Dims ``(trial, channel, time)``, labels as per-trial coordinates (each
        with ``long_name`` and, when known, ``units``: :func:`coordinate_attrs`),
        attrs ``sample_rate_hz``, ``vibrissa_version`` and those given (``None``
        values dropped).

    Raises
    ------
    ValueError
        If the signal is not 2-D/3-D real numbers or holds NaN/inf, if the
        channel names, time values or a label do not match the signal's shape,
        if a label uses a reserved name (``trial``, ``channel``, ``time``,
        ``signal``) or if ``sample_rate_hz`` is not positive.
    """
    x = np.asarray(signal)
    if x.ndim == 2:
        x = x[:, None, :]
    if x.ndim != 3:
        raise ValueError(
            f"signal must have shape (n_trials, n_channels, n_timepoints), got {x.shape}"
        )
    if not np.issubdtype(x.dtype, np.number) or np.issubdtype(x.dtype, np.complexfloating):
        raise ValueError(f"signal must be real numbers, got dtype {x.dtype}")
    x = x.astype(np.float64)
    n, c, t = x.shape
    if channels is None:
        channels = ["x", "y", "z"][:c] if c <= 3 else [f"ch{i}" for i in range(c)]
    channels = [str(ch) for ch in channels]
    if len(channels) != c:
        raise ValueError(f"{len(channels)} channel names given for {c} channels")
    fs = float(sample_rate_hz)
    if not np.isfinite(fs) or fs <= 0:
        raise ValueError(f"sample_rate_hz must be positive and finite, got {sample_rate_hz!r}")
    tt = np.arange(t) / fs if time is None else np.asarray(time, dtype=float)
    if tt.shape != (t,):
        raise ValueError(f"time must have {t} values, got shape {tt.shape}")
    coords: dict[str, Any] = {
        "trial": ("trial", np.arange(n), coordinate_attrs("trial")),
        "channel": ("channel", np.array(channels), coordinate_attrs("channel")),
        "time": ("time", tt, coordinate_attrs("time")),
    }
    for name, values in (labels or {}).items():
        name = str(name)
        if name in _RESERVED:
            raise ValueError(f"label name {name!r} is reserved (one of {sorted(_RESERVED)})")
        arr = np.asarray(values)
        if arr.shape != (n,):
            raise ValueError(
                f"label {name!r} has {arr.shape[0] if arr.ndim == 1 else arr.shape} "
                f"value(s) for {n} trials"
            )
        if arr.dtype.kind in "OUS":
            arr = np.array([_to_str(v) for v in arr], dtype=str)
        elif arr.dtype.kind not in "biuf":
            raise ValueError(f"label {name!r} must hold numbers or strings, got dtype {arr.dtype}")
        coords[name] = ("trial", arr, coordinate_attrs(name, arr))
    at: dict[str, Any] = {"sample_rate_hz": fs, "vibrissa_version": __version__}
    for k, v in (attrs or {}).items():
        if v is not None:
            at[str(k)] = attr_value(v)
    ds = xr.Dataset(
        {"signal": (("trial", "channel", "time"), x, {"units": units})}, coords=coords, attrs=at
    )
    validate_dataset(ds)
    return ds


def _to_str(v: Any) -> str:
    return v.decode("utf-8") if isinstance(v, bytes | np.bytes_) else str(v)


def attr_value(value: Any) -> Any:
    """``value`` in a form NetCDF attributes can hold.

    Dicts and lists become JSON strings, booleans integers, numpy scalars
    Python scalars; strings and numbers pass unchanged.
    """
    if isinstance(value, bool | np.bool_):
        return int(value)
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, dict | list | tuple):
        return json.dumps(value, sort_keys=True, default=str)
    return value


def validate_dataset(ds: xr.Dataset) -> xr.Dataset:
    """Check ``ds`` against the schema and return it unchanged.

    Parameters
    ----------
    ds
        The dataset to check.

    Returns
    -------
    xarray.Dataset
        ``ds`` itself, so that calls can be chained.

    Raises
    ------
    TypeError
        If ``ds`` is not an :class:`xarray.Dataset`.
    ValueError
        Naming the problem: no ``signal`` variable, wrong dims, no samples,
        non-float or non-finite signal, missing or malformed ``channel``/``time``
        coordinates, a label without one value per trial, a non-positive
        ``sample_rate_hz``.
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"expected an xarray.Dataset, got {type(ds).__name__}")
    if "signal" not in ds.data_vars:
        raise ValueError("dataset has no 'signal' variable")
    sig = ds["signal"]
    if sig.dims != ("trial", "channel", "time"):
        raise ValueError(f"'signal' must have dims (trial, channel, time), got {sig.dims}")
    if sig.sizes["trial"] < 1 or sig.sizes["time"] < 1:
        raise ValueError("dataset holds no samples")
    vals = sig.values
    if not np.issubdtype(vals.dtype, np.floating):
        raise ValueError(f"'signal' must be floating point, got {vals.dtype}")
    bad = int(np.size(vals) - np.count_nonzero(np.isfinite(vals)))
    if bad:
        raise ValueError(f"'signal' contains {bad} NaN or infinite value(s)")
    if "channel" not in ds.coords:
        raise ValueError("dataset has no 'channel' coordinate")
    chans = [str(c) for c in np.asarray(ds["channel"].values).ravel()]
    if ds["channel"].dims != ("channel",) or len(set(chans)) != len(chans):
        raise ValueError(f"'channel' must be distinct names along dim 'channel', got {chans}")
    if "time" not in ds.coords:
        raise ValueError("dataset has no 'time' coordinate")
    tt = np.asarray(ds["time"].values)
    if ds["time"].dims != ("time",) or tt.dtype.kind not in "iuf":
        raise ValueError(f"'time' must be numbers (s) along dim 'time', got dtype {tt.dtype}")
    if not np.all(np.isfinite(tt)) or np.any(np.diff(tt) <= 0):
        raise ValueError("'time' must be finite and strictly increasing")
    fs = ds.attrs.get("sample_rate_hz")
    try:
        ok = fs is not None and float(fs) > 0 and np.isfinite(float(fs))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"attribute 'sample_rate_hz' must be positive, got {fs!r}")
    for name, coord in ds.coords.items():
        if "trial" in coord.dims and name != "trial" and coord.dims != ("trial",):
            raise ValueError(f"label {name!r} must have dims ('trial',), got {coord.dims}")
        if coord.dims == ("trial",) and coord.size != sig.sizes["trial"]:
            raise ValueError(f"label {name!r} does not have one value per trial")
    return ds


def label_names(ds: xr.Dataset) -> list[str]:
    """Names of the per-trial coordinates (labels) of ``ds``, in dataset order."""
    return [str(k) for k, c in ds.coords.items() if c.dims == ("trial",) and k != "trial"]


def as_arrays(
    ds: xr.Dataset, labels: Sequence[str], *, encode_textures: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The arrays classifiers take: ``X`` and the multi-target label ``y``.

    Numeric labels stay numbers and string labels stay strings: ``y`` is float64
    when every requested label is numeric, an array of strings when every one is
    a string, and otherwise an ``object`` array whose numeric columns hold Python
    floats and whose string columns hold ``str`` (e.g. ``["angle_deg",
    "speed_mm_s", "texture"]`` gives rows like ``[30.0, 36.0, "p80"]``). The
    classifiers need numeric rows for mixed labels: pass ``encode_textures=True``
    to get the ``texture`` column as its code (:func:`vibrissa.data.encode_texture`,
    smooth to coarse), as the chapter-5 classifiers expect.

    Parameters
    ----------
    ds
        A dataset of the schema.
    labels
        Names of the per-trial labels forming the columns of ``y``, e.g.
        ``["radial_distance_mm", "speed_mm_s"]``. A single string is taken as
        one name.
    encode_textures
        Replace the texture names of a ``texture`` column by their integer codes
        (as floats); textures without a code raise a ``ValueError`` naming them.

    Returns
    -------
    X : numpy.ndarray
        Shape ``(n_trials, n_channels, n_timepoints)``, float64.
    y : numpy.ndarray
        Shape ``(n_trials, n_labels)``: float64 if every column is numeric, str if
        every one is a string, otherwise object (numbers as float, strings as str).

    Raises
    ------
    KeyError
        If a requested label is missing (the message lists those present).
    """
    if isinstance(labels, str):
        labels = [labels]
    labels = list(labels)
    present = label_names(ds)
    missing = [name for name in labels if name not in present]
    if missing:
        raise KeyError(f"dataset has no label(s) {missing}; it has {present}")
    X = np.asarray(ds["signal"].values, dtype=float)
    cols = [np.asarray(ds[name].values) for name in labels]
    if encode_textures:
        cols = [
            encode_texture(c).astype(float) if name == "texture" else c
            for name, c in zip(labels, cols, strict=True)
        ]
    if not cols:
        return X, np.empty((X.shape[0], 0))
    numeric = [c.dtype.kind in "fiub" for c in cols]
    if all(numeric):
        return X, np.column_stack([c.astype(float) for c in cols])
    if not any(numeric):
        return X, np.column_stack([c.astype(str) for c in cols])
    y = np.empty((X.shape[0], len(cols)), dtype=object)
    for k, (c, is_num) in enumerate(zip(cols, numeric, strict=True)):
        y[:, k] = [float(v) for v in c] if is_num else [str(v) for v in c]
    return X, y


def _matches(vals: np.ndarray, wanted: Any) -> np.ndarray:
    wanted_arr = np.asarray(
        list(wanted) if isinstance(wanted, list | tuple | set | np.ndarray) else [wanted]
    )
    if vals.dtype.kind in "fiu" and wanted_arr.dtype.kind in "fiub":
        # physical values such as 36 + 7.2 k mm/s: compare with a relative tolerance
        w = wanted_arr.astype(float).ravel()
        close = np.isclose(vals[:, None].astype(float), w[None, :], rtol=1e-9, atol=1e-12)
        return close.any(axis=1)
    return np.isin(vals.astype(str), wanted_arr.astype(str))


def select(ds: xr.Dataset, **criteria: Any) -> xr.Dataset:
    """The trials whose labels take the given values.

    Parameters
    ----------
    ds
        A dataset of the schema.
    **criteria
        ``label=value`` or ``label=[value, ...]`` (any of the values). Numeric
        labels are compared with a relative tolerance of 1e-9, so that
        ``speed_mm_s=43.2`` finds ``36 + 7.2``; a callable value is applied to
        the label's array and must return a boolean mask.

    Returns
    -------
    xarray.Dataset
        The selected trials (possibly none), in their original order.

    Raises
    ------
    KeyError
        If a criterion names a label the dataset does not have.
    """
    present = label_names(ds)
    mask = np.ones(ds.sizes["trial"], dtype=bool)
    for name, value in criteria.items():
        if name not in present:
            raise KeyError(f"dataset has no label {name!r}; it has {present}")
        vals = np.asarray(ds[name].values)
        if callable(value):
            m = np.asarray(value(vals), dtype=bool)
            if m.shape != vals.shape:
                raise ValueError(f"criterion for {name!r} must return one boolean per trial")
            mask &= m
        else:
            mask &= _matches(vals, value)
    return ds.isel(trial=np.flatnonzero(mask))


def concat_datasets(datasets: Sequence[xr.Dataset]) -> xr.Dataset:
    """Concatenate datasets along ``trial``.

    Parameters
    ----------
    datasets
        Datasets of the schema with the same channels, time coordinate, sample
        rate and label names.

    Returns
    -------
    xarray.Dataset
        Trials of all inputs in order, renumbered ``0..n-1``; attributes of the
        first dataset.

    Raises
    ------
    ValueError
        If the list is empty or the datasets differ in sample rate, channels,
        time coordinate or label names (the message names the first offender).
    """
    datasets = list(datasets)
    if not datasets:
        raise ValueError("no datasets to concatenate")
    for i, d in enumerate(datasets):
        try:
            validate_dataset(d)
        except ValueError as exc:
            raise ValueError(f"dataset {i}: {exc}") from None
    first = datasets[0]
    names = set(label_names(first))
    for i, d in enumerate(datasets[1:], start=1):
        if float(d.attrs["sample_rate_hz"]) != float(first.attrs["sample_rate_hz"]):
            raise ValueError(
                f"dataset {i} has sample rate {d.attrs['sample_rate_hz']} Hz, "
                f"dataset 0 has {first.attrs['sample_rate_hz']} Hz"
            )
        if list(d["channel"].values) != list(first["channel"].values):
            raise ValueError(
                f"dataset {i} has channels {list(d['channel'].values)}, "
                f"dataset 0 has {list(first['channel'].values)}"
            )
        if d.sizes["time"] != first.sizes["time"] or not np.allclose(
            d["time"].values, first["time"].values, rtol=1e-9, atol=1e-12
        ):
            raise ValueError(f"dataset {i} has a different time coordinate from dataset 0")
        other = set(label_names(d))
        if other != names:
            raise ValueError(
                f"dataset {i} has labels {sorted(other)}, dataset 0 has {sorted(names)}"
            )
    # the first dataset's time coordinate for all (they agree within rounding)
    aligned = [d.assign_coords(time=first["time"]) for d in datasets]
    out = xr.concat(
        aligned,
        dim="trial",
        data_vars="all",
        coords="different",
        compat="equals",
        combine_attrs="override",
        join="exact",
    )
    return out.assign_coords(trial=np.arange(out.sizes["trial"]))


def whisker_params(ds: xr.Dataset) -> dict[str, Any]:
    """The ``whisker`` attribute parsed from JSON ({} if absent)."""
    return parse_whisker(ds.attrs.get("whisker"), name="attribute 'whisker'")
