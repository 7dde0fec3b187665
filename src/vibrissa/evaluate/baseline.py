"""An earlier run's results, set beside a new run's in the reports ("before / after").

A *baseline* is a ``results.json`` of an earlier ``vibrissa reproduce`` run, or its
compact form (:func:`compact_results`: the summary statistics only, small enough
to keep in the repository, e.g. ``docs/runs/``). Reports show, per classifier,
thesis / baseline / this run.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["compact_results", "load_baseline"]

_STATS = ("mean", "std")
_PARAMS4 = ("radius_mm", "speed_mm_s")


def compact_results(results: Mapping[str, Any], label: str) -> dict[str, Any]:
    """The summary of a chapter-4 or chapter-5 results dict, labelled.

    Keeps, per classifier, the mean and std of the signed errors (chapter 4) or the
    kappas (chapter 5); drops predictions and per-seed detail.
    """
    meta = dict(results.get("meta", {}))
    out: dict[str, Any] = {
        "meta": {
            "label": str(label),
            "n_trials": meta.get("n_trials"),
            "protocol": results.get("protocol", {}).get("name")
            if isinstance(results.get("protocol"), Mapping)
            else results.get("protocol"),
            "fingerprint": meta.get("fingerprint"),
        },
        "classifiers": {},
    }
    for name, entry in results.get("classifiers", {}).items():
        if "kappa" in entry and isinstance(entry["kappa"], Mapping):
            out["classifiers"][name] = {"kappa": dict(entry["kappa"])}
            continue
        out["classifiers"][name] = {
            p: ({s: entry[p][s] for s in _STATS} if isinstance(entry.get(p), Mapping) else None)
            for p in _PARAMS4
        }
    return out


def load_baseline(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a baseline (full ``results.json`` or compact); label it by its file if unlabelled.

    Raises
    ------
    ValueError
        If the file is missing, not JSON, or has no ``classifiers``.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--baseline: no such file {str(p)!r}")
    try:
        data = json.loads(p.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"--baseline: {str(p)!r} is not a results JSON ({exc})") from None
    if not isinstance(data, dict) or not isinstance(data.get("classifiers"), dict):
        raise ValueError(f"--baseline: {str(p)!r} has no 'classifiers' (not a results JSON)")
    meta = data.setdefault("meta", {})
    meta.setdefault("label", str(p))
    return data
