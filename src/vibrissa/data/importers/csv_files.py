"""CSV files: one row per sample (long layout) or one row per trial (wide layout).

Long layout: a trial-id column, an optional time column (s), one column per
channel and label columns constant within a trial; trials in order of first
appearance, samples in file order or sorted by time. Wide layout: label
columns plus ``CHANNEL_0, CHANNEL_1, ...`` sample columns; a shorter recording
leaves its last cells empty. Read with :mod:`pandas`. See ``docs/importing.md``.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.importers._common import equalise
from vibrissa.data.importers.mapping import UNSET, ImportMapping, ImportMappingError

__all__ = ["import_csv"]


def import_csv(path: Path, mapping: ImportMapping) -> dict[str, Any]:
    """The recordings and labels of a CSV file, long or wide layout.

    Parameters
    ----------
    path
        The ``.csv``/``.txt`` file (opened for reading only).
    mapping
        ``layout``, ``trial_column``, ``time_column``, ``channels``,
        ``labels`` (label -> column), ``ragged`` and ``sample_rate_hz`` (Hz;
        inferred from a time column in seconds when not given).

    Returns
    -------
    dict
        ``signal`` (n_trials, n_channels, n_samples) float array, ``labels``
        (label -> one value per trial), ``cropped_from`` (samples, or ``None``),
        ``sample_rate_hz`` (Hz), ``time`` (s, shared by every trial, or
        ``None``), ``channels`` and ``signal_name`` (``None``).

    Raises
    ------
    ImportMappingError
        Naming the column, trial or line at fault.
    """
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
            f'columns: {cols}. Set \'trial_column\', or "layout": "wide"'
        )
    time_col = mapping.time_column
    if time_col is UNSET:
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
        for c in cols:
            if c not in used and c not in chans:
                _refuse_mixed_column(df, c, path)
        if not chans:
            raise ImportMappingError(f"{path}: no numeric channel columns; give 'channels'")
    values = np.column_stack([_numeric_column(df, c, path) for c in chans])
    trial_ids = df[tcol].to_numpy()
    if df[tcol].isna().any():
        raise ImportMappingError(f"{path}: column {tcol!r} has empty cells")
    times = _time_column(df, time_col, path) if time_col else None
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
            _check_time_steps(times[rows], rows, nm, time_col)
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
    signal, cropped_from = equalise(recs, names, mapping.ragged)
    n_t = signal.shape[2]
    time = None
    fs = mapping.sample_rate_hz
    if times is not None:
        tt = [t[:n_t] for t in rec_times]
        if n_t > 1:
            fs = _time_column_rate(tt, names, path, time_col, fs)
        if all(np.allclose(t, tt[0], rtol=0, atol=1e-9) for t in tt):
            time = tt[0]
    if fs is None:
        raise ImportMappingError(
            "the sampling rate is not given: set 'sample_rate_hz' in the mapping"
        )
    if isinstance(fs, str):
        raise ImportMappingError("'sample_rate_hz' must be a number for CSV files")
    labels = {label: _label_values([r[label] for r in labels_rows]) for label in label_cols}
    return {
        "signal": signal,
        "labels": labels,
        "cropped_from": cropped_from,
        "sample_rate_hz": float(fs),
        "time": time,
        "channels": chans,
        "signal_name": None,
    }


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


def _refuse_mixed_column(df: Any, col: str, path: Path) -> None:
    """Refuse a column of numbers with a non-numeric cell (it would be dropped as text)."""
    import pandas as pd

    s = df[col]
    if s.dtype.kind == "b":
        return
    num = pd.to_numeric(s, errors="coerce")
    bad = num.isna() & s.notna()
    if bool(num.notna().any()) and bool(bad.any()):
        row = int(np.flatnonzero(bad.to_numpy())[0])
        raise ImportMappingError(
            f"{path}: column {col!r} holds numbers but line {row + 2} has {s.iloc[row]!r}; "
            "a channel column must hold only numbers (or list the channels in 'channels', "
            "or map the column as a label)"
        )


def _time_column(df: Any, col: str, path: Path) -> np.ndarray:
    """The time column (s), refusing empty, NaN or infinite cells."""
    times = _numeric_column(df, col, path)
    bad = ~np.isfinite(times)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        cell = df[col].iloc[row]
        raise ImportMappingError(
            f"{path}: time column {col!r} must hold finite times (s); line {row + 2} has "
            f"{'an empty cell' if _is_empty(cell) else _cell_text(cell)}"
        )
    return times


def _cell_text(cell: Any) -> str:
    return repr(cell) if isinstance(cell, str) else f"{float(cell):g}"


def _is_empty(value: Any) -> bool:
    """Whether a cell read by pandas is empty (NaN/None)."""
    import pandas as pd

    return bool(pd.isna(value))


#: How far one time step may stray from a trial's median step (fraction of it).
_STEP_TOLERANCE = 0.5
#: How far a trial's median time step may differ from the first trial's (fraction).
_RATE_TOLERANCE = 0.01


def _check_time_steps(t: np.ndarray, rows: np.ndarray, nm: str, col: str) -> None:
    """Refuse repeated times and uneven steps of one trial (``t`` sorted, ``rows`` its rows)."""
    if t.size < 2:
        return
    with np.errstate(over="ignore", invalid="ignore"):
        steps = np.diff(t)
    same = np.flatnonzero(steps == 0)
    if same.size:
        i = int(same[0])
        a, b = sorted((int(rows[i]) + 2, int(rows[i + 1]) + 2))
        raise ImportMappingError(
            f"{nm}: time column {col!r} repeats the time {t[i]:g} s on lines {a} and {b}; "
            "every sample of a trial needs its own time"
        )
    med = float(np.median(steps))
    with np.errstate(over="ignore", invalid="ignore"):
        off = ~np.isfinite(steps) | (np.abs(steps - med) > _STEP_TOLERANCE * med)
    if not np.isfinite(med) or med <= 0 or off.any():
        i = int(np.flatnonzero(off)[0]) if off.any() else 0
        a, b = int(rows[i]) + 2, int(rows[i + 1]) + 2
        raise ImportMappingError(
            f"{nm}: time column {col!r} is not evenly spaced: it steps from {t[i]:g} s "
            f"(line {a}) to {t[i + 1]:g} s (line {b}) where the median step is {med:g} s "
            "(a missing sample or a wrong time?)"
        )


def _time_column_rate(
    tt: list[np.ndarray], names: list[str], path: Path, col: str, given: Any
) -> float:
    """The sampling rate (Hz) the time column says, checked across trials and against ``given``."""
    steps = [float(np.median(np.diff(t))) for t in tt]
    for nm, d in zip(names, steps, strict=True):
        if abs(d - steps[0]) > _RATE_TOLERANCE * steps[0]:
            raise ImportMappingError(
                f"{nm}: time column {col!r} is sampled at {1 / d:g} Hz but {names[0]} at "
                f"{1 / steps[0]:g} Hz; every trial must have the same sampling rate"
            )
    rate = 1.0 / steps[0]
    if not np.isfinite(rate) or rate <= 0:
        raise ImportMappingError(
            f"{path}: time column {col!r} gives no finite sampling rate (step {steps[0]:g} s)"
        )
    if abs(rate - round(rate)) <= 1e-6 * rate:  # 999.9999999999991 Hz from 0.001 s steps
        rate = float(round(rate))
    if given is None:
        return rate
    if isinstance(given, str):
        raise ImportMappingError("'sample_rate_hz' must be a number for CSV files")
    if abs(rate - float(given)) > _RATE_TOLERANCE * float(given):
        raise ImportMappingError(
            f"{path}: time column {col!r} is sampled at {rate:g} Hz but 'sample_rate_hz' is "
            f"{float(given):g} Hz; correct 'sample_rate_hz', or set \"time_column\": null "
            "to ignore the time column"
        )
    return float(given)


def _label_values(vals: list[Any]) -> np.ndarray:
    arr = np.asarray(vals)
    return arr.astype(str) if arr.dtype.kind in "OSU" else arr


def _import_csv_wide(
    path: Path, df: Any, mapping: ImportMapping, label_cols: dict[str, str]
) -> dict[str, Any]:
    cols = list(df.columns)
    chans = list(mapping.channels) if mapping.channels is not None else None
    if chans is None:
        prefixes = sorted(
            {
                m.group(1)
                for c in cols
                if (m := re.fullmatch(r"(.+)_(\d+)", c)) and c not in label_cols.values()
            }
        )
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
    signal, cropped_from = equalise(recs, names, mapping.ragged)
    if mapping.sample_rate_hz is None or isinstance(mapping.sample_rate_hz, str):
        raise ImportMappingError("the sampling rate is not given: set 'sample_rate_hz' (a number)")
    labels = {label: _label_values(df[col].tolist()) for label, col in label_cols.items()}
    return {
        "signal": signal,
        "labels": labels,
        "cropped_from": cropped_from,
        "sample_rate_hz": float(mapping.sample_rate_hz),
        "time": None,
        "channels": chans,
        "signal_name": None,
    }
