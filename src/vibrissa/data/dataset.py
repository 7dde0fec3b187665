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

__all__ = [
    "KNOWN_LABELS",
    "as_arrays",
    "concat_datasets",
    "label_names",
    "make_dataset",
    "select",
    "validate_dataset",
    "whisker_params",
]

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
        "trial": np.arange(n),
        "channel": np.array(channels),
        "time": ("time", tt, {"units": "s"}),
    }
    for name, values in (labels or {}).items():
        arr = np.asarray(values)
        if arr.shape != (n,):
            raise ValueError(f"label {name!r} has {arr.shape} values for {n} trials")
        if arr.dtype.kind in "OU":
            arr = arr.astype(str)
        coords[str(name)] = ("trial", arr)
    at: dict[str, Any] = {"sample_rate_hz": fs, "vibrissa_version": __version__}
    for k, v in (attrs or {}).items():
        at[k] = json.dumps(v, sort_keys=True, default=str) if isinstance(v, dict | list) else v
    ds = xr.Dataset(
        {"signal": (("trial", "channel", "time"), x, {"units": units})}, coords=coords, attrs=at
    )
    validate_dataset(ds)
    return ds


def validate_dataset(ds: xr.Dataset) -> xr.Dataset:
    """Check ``ds`` against the schema; raise ``ValueError`` naming the problem."""
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
    fs = ds.attrs.get("sample_rate_hz")
    try:
        ok = fs is not None and float(fs) > 0 and np.isfinite(float(fs))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"attribute 'sample_rate_hz' must be positive, got {fs!r}")
    for name, coord in ds.coords.items():
        if coord.dims == ("trial",) and coord.size != sig.sizes["trial"]:
            raise ValueError(f"label {name!r} does not have one value per trial")
    return ds


def label_names(ds: xr.Dataset) -> list[str]:
    """Names of the per-trial coordinates (labels) of ``ds``."""
    return [str(k) for k, c in ds.coords.items() if c.dims == ("trial",) and k != "trial"]


def as_arrays(ds: xr.Dataset, labels: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """``X`` (n_trials, n_channels, n_timepoints) and ``y`` (n_trials, n_labels).

    Raises
    ------
    KeyError
        If a requested label is missing (the message lists those present).
    """
    missing = [name for name in labels if name not in ds.coords]
    if missing:
        raise KeyError(f"dataset has no label(s) {missing}; it has {label_names(ds)}")
    X = np.asarray(ds["signal"].values, dtype=float)
    cols = [np.asarray(ds[name].values) for name in labels]
    y = np.column_stack(cols) if cols else np.empty((X.shape[0], 0))
    if all(c.dtype.kind in "fiub" for c in cols):
        y = y.astype(float)
    return X, y


def select(ds: xr.Dataset, **criteria: Any) -> xr.Dataset:
    """Trials whose labels equal the given values (a value may be a list of values)."""
    mask = np.ones(ds.sizes["trial"], dtype=bool)
    for name, value in criteria.items():
        if name not in ds.coords:
            raise KeyError(f"dataset has no label {name!r}; it has {label_names(ds)}")
        vals = np.asarray(ds[name].values)
        wanted = value if isinstance(value, list | tuple | np.ndarray) else [value]
        mask &= np.isin(vals, wanted)
    return ds.isel(trial=np.flatnonzero(mask))


def concat_datasets(datasets: Sequence[xr.Dataset]) -> xr.Dataset:
    """Concatenate datasets along ``trial`` (same channels, time and sample rate)."""
    if not datasets:
        raise ValueError("no datasets to concatenate")
    first = datasets[0]
    for d in datasets[1:]:
        if d.attrs.get("sample_rate_hz") != first.attrs.get("sample_rate_hz"):
            raise ValueError("datasets have different sample rates")
        if d.sizes["time"] != first.sizes["time"] or list(d["channel"].values) != list(
            first["channel"].values
        ):
            raise ValueError("datasets have different channels or numbers of samples")
    out = xr.concat(
        datasets, dim="trial", data_vars="all", coords="different", combine_attrs="override"
    )
    return out.assign_coords(trial=np.arange(out.sizes["trial"]))


def whisker_params(ds: xr.Dataset) -> dict[str, Any]:
    """The ``whisker`` attribute parsed from JSON ({} if absent)."""
    w = ds.attrs.get("whisker")
    if not w:
        return {}
    if isinstance(w, dict):
        return w
    try:
        return json.loads(w)
    except ValueError as exc:
        raise ValueError(f"attribute 'whisker' is not valid JSON: {exc}") from None
