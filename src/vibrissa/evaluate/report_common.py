"""What every experiment's report shares: JSON output, number formats, tables, the header.

The header states what was run, by which version and command, when, with which
seed, and whether it was a quick run; every number below it in a report comes
from the results being reported, or from the thesis (kept as data with its table
and figure numbers).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa._atomic import atomic_write_text

__all__ = ["fmt", "fmt_seconds", "load_results", "md_table", "report_header", "write_json"]


def _default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def write_json(results: Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """Write ``results`` as indented JSON, atomically (NaN is refused: use ``None``).

    Parameters
    ----------
    results : dict
        E.g. a results envelope of :func:`vibrissa.reproduce.run_experiment`.
    path : path-like
        Destination.

    Returns
    -------
    pathlib.Path
    """
    try:
        text = json.dumps(results, indent=2, default=_default, allow_nan=False)
    except ValueError as exc:
        raise ValueError(f"results contain NaN or infinity, not valid JSON: {exc}") from exc
    return atomic_write_text(path, text + "\n")


def load_results(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read results written by :func:`write_json`."""
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


def fmt(x: Any, digits: int = 2) -> str:
    """A number for a table: ``digits`` decimals, small values as ``g``, ``—`` if undefined."""
    if x is None:
        return "—"
    if isinstance(x, float) and not math.isfinite(x):
        return "—"
    if isinstance(x, int | float | np.integer | np.floating):
        v = float(x)
        if v != 0 and abs(v) < 10 ** (-digits):
            return f"{v:.{digits}g}"
        return f"{v:.{digits}f}"
    return str(x)


def fmt_seconds(x: Any) -> str:
    """A duration: ``0.123 s``, ``42 s`` or ``3 min 12 s``; ``—`` if undefined."""
    if x is None:
        return "—"
    x = float(x)
    if x < 60:
        return f"{x:.3g} s"
    m, s = divmod(x, 60.0)
    return f"{int(m)} min {s:.0f} s"


def md_table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A GitHub-flavoured Markdown table (cells converted with ``str``)."""
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def report_header(meta: Mapping[str, Any]) -> str:
    """Title, provenance line and (on quick runs) the quick-run banner of a report.

    Parameters
    ----------
    meta : dict
        The ``meta`` of a results envelope (:func:`vibrissa.reproduce.run_experiment`).

    Returns
    -------
    str
        Markdown, ending with a blank line.
    """
    title = meta.get("title") or meta.get("experiment") or "vibrissa report"
    out = [f"# {title}", ""]
    ds = meta.get("dataset") or {}
    wall = meta.get("wall_seconds") or {}
    cores = meta.get("cores") or {}
    if meta.get("quick"):
        out += [
            f"> **Quick run.** {ds.get('n_trials', '?')} trials on the experiment's reduced "
            "grid: it checks the pipeline end to end; its numbers are not comparable with "
            "the thesis' full grid. Run without `--quick` for the reproduction.",
            "",
        ]
    reused = " (reused from the cache)" if ds.get("reused") else ""
    out += [
        f"- vibrissa {meta.get('vibrissa_version', '?')}, command `{meta.get('command', '?')}`",
        f"- started {meta.get('started_at', '?')}, seed {meta.get('seed', '?')}, "
        f"{'quick' if meta.get('quick') else 'full'} grid, "
        f"{cores.get('available', '?')} cores",
        f"- dataset `{Path(str(ds.get('path', '?'))).name}`{reused}: "
        f"{ds.get('n_trials', '?')} trials; generation {fmt_seconds(wall.get('generate'))}, "
        f"evaluation {fmt_seconds(wall.get('evaluate'))}",
    ]
    if "variability_sources" in ds:
        on = ", ".join(ds["variability_sources"]) or "none"
        out.append(f"- trial-to-trial variability simulated (`robots.xy_variability`): {on}")
    out.append("")
    return "\n".join(out) + "\n"
