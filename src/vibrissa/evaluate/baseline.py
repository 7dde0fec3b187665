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

__all__ = ["MAX_BASELINE_BYTES", "compact_results", "load_baseline"]

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


#: Largest baseline read (bytes): a full chapter-4 results.json is about 10 MB.
MAX_BASELINE_BYTES = 256 * 1024 * 1024


def load_baseline(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a baseline (full ``results.json`` or compact); label it by its file if unlabelled.

    Raises
    ------
    ValueError
        One line naming ``--baseline``: the file is missing, not a regular file (a
        directory, a FIFO or a device, which would block or never end), larger than
        :data:`MAX_BASELINE_BYTES`, not JSON, nested too deep to read, or has no
        ``classifiers`` or a ``meta`` that is not an object.
    """
    import stat

    p = Path(path)
    try:
        st = p.stat()
    except OSError:
        raise ValueError(f"--baseline: no such file {str(p)!r}") from None
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"--baseline: {str(p)!r} is not a regular file")
    if st.st_size > MAX_BASELINE_BYTES:
        raise ValueError(
            f"--baseline: {str(p)!r} is {st.st_size} bytes, more than a results JSON "
            f"({MAX_BASELINE_BYTES} at most)"
        )
    try:
        data = json.loads(p.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"--baseline: {str(p)!r} is not a results JSON ({exc})") from None
    except RecursionError:
        raise ValueError(
            f"--baseline: {str(p)!r} is nested too deep to be a results JSON"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("classifiers"), dict):
        raise ValueError(f"--baseline: {str(p)!r} has no 'classifiers' (not a results JSON)")
    meta = data.setdefault("meta", {})
    if not isinstance(meta, dict):
        raise ValueError(f"--baseline: {str(p)!r} has a 'meta' that is not an object")
    meta.setdefault("label", str(p))
    return data
