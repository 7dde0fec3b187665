"""Identify the XY robot's retract move from the thesis' own observables (issue 30).

The thesis gives the stage's speeds (720 mm/s retraction) and repeatability only;
its acceleration, jerk and where the retract move ends are open. This script runs
``vibrissa identify`` (every observable, the protocols' own settings) over a grid of
those parameters and writes, per setting, every observable's value and verdict, so
the choice in ``vibrissa.robots.xy_stage.XYStage`` and the trade-offs behind it are
on record::

    .venv/bin/python scripts/identify_stage.py --json docs/runs/identify_stage.json

Admissible settings let the robot's approach start from rest at the retract target
and reach the fastest chapter-4 speed (216 mm/s) before touching the whisker:
``clearance >= 216^2 / (2 a)``. The setting chosen is the admissible one meeting
the most observables; ties go to the chapter-5 fraction of ringing trials nearest
one half ("ringing after contact on some trials but not others", 5.5). It takes
about 30 s per setting and core.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

ACCELERATIONS_M_S2 = (3.0, 5.0, 10.0, 20.0)
CLEARANCES_MM = (0.5, 1.0, 2.0, 3.0, 5.0, 10.0)
JERKS_M_S3 = (float("inf"), 500.0, 100.0)
FASTEST_MM_S = 216.0


def _one(setting: tuple[float, float, float]) -> dict[str, Any]:
    from vibrissa.experiments.identify import identify
    from vibrissa.robots.xy_stage import XYStage

    acc, clearance, jerk = setting
    stage = dataclasses.replace(
        XYStage(),
        acceleration_mm_s2=acc * 1e3,
        retract_clearance_mm=clearance,
        jerk_mm_s3=jerk * 1e3,
    )
    obs = identify(stage=stage)
    return {
        "acceleration_m_s2": acc,
        "retract_clearance_mm": clearance,
        "jerk_m_s3": None if jerk == float("inf") else jerk,
        "n_within": sum(o.within for o in obs),
        "values": {o.key: o.value for o in obs},
        "within": {o.key: o.within for o in obs},
        "detail": {
            "physical_contact_chapter5_median_ms": obs[5].detail.get("physical_contact_median_ms"),
            "trial_peaks_by_band": obs[0].detail.get("trial_peaks_by_band"),
        },
    }


def derive(out: dict[str, Any]) -> dict[str, Any]:
    """The figures the docs quote, computed from the grid (``out["derived"]``)."""
    rows = out["grid"]
    c = out["chosen"]
    chosen = next(
        r
        for r in rows
        if r["acceleration_m_s2"] == c["acceleration_m_s2"]
        and r["retract_clearance_mm"] == c["retract_clearance_mm"]
    )
    far = max(
        (r for r in rows if r["acceleration_m_s2"] == c["acceleration_m_s2"]),
        key=lambda r: r["retract_clearance_mm"],
    )
    ring_ok = [r for r in rows if r["within"]["ringing_chapter5"]]
    dur_ok = [r for r in ring_ok if r["within"]["contact_duration_chapter5_ms"]]
    fast_ok = [r for r in ring_ok if r["within"]["above_216_mm_s"]]
    both = [
        r
        for r in rows
        if r["within"]["contact_duration_chapter5_ms"]
        and r["within"]["above_216_mm_s"]
        and r["within"]["ringing_chapter5"]
    ]
    return {
        "n_settings": len(rows),
        "n_admissible": sum(r["admissible"] for r in rows),
        "max_within": max(r["n_within"] for r in rows),
        "chosen_values": chosen["values"],
        "far_clearance_mm": far["retract_clearance_mm"],
        "highest_resonance_hz": max(r["values"]["resonance_hz"] for r in rows + out["jerk"]),
        "far_values": far["values"],
        "n_meeting_duration_fast_and_ringing": len(both),
        "best_above_216_where_ringing_and_duration_met": max(
            (r["values"]["above_216_mm_s"] for r in dur_ok), default=None
        ),
        "shortest_duration_ms_where_ringing_and_above_216_met": min(
            (r["values"]["contact_duration_chapter5_ms"] for r in fast_ok), default=None
        ),
        "accelerations_meeting_above_216_m_s2": sorted({r["acceleration_m_s2"] for r in fast_ok}),
    }


def main(argv: list[str] | None = None) -> int:
    """Run the grid and write the JSON record."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", type=Path, required=True, help="output file")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument(
        "--derive-only",
        action="store_true",
        help="recompute the derived figures of an existing --json file (no simulation)",
    )
    args = ap.parse_args(argv)
    if args.derive_only:
        try:
            out = json.loads(args.json.read_text())
            missing = [k for k in ("grid", "jerk", "chosen") if k not in out]
            if missing:
                raise KeyError(", ".join(missing))
        except (OSError, ValueError, KeyError) as e:
            ap.error(f"--json: {args.json} is not a record of this script ({e})")
        for r in out["grid"] + out["jerk"]:  # the passive push is identify's own record now
            r["detail"].pop("ringing_chapter4_passive_push_median", None)
        out["derived"] = derive(out)
        _write(args.json, out)
        return 0
    if args.workers < 1:
        ap.error("--workers must be >= 1")
    if not args.json.parent.is_dir():
        ap.error(f"--json: folder {args.json.parent} does not exist")
    settings = [(a, c, float("inf")) for a in ACCELERATIONS_M_S2 for c in CLEARANCES_MM]
    print(f"identify_stage: {len(settings)} settings x ~170 trials", file=sys.stderr)
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(_one, settings))
    for r in rows:
        r["admissible"] = r["retract_clearance_mm"] >= FASTEST_MM_S**2 / (
            2 * r["acceleration_m_s2"] * 1e3
        )
    best = min(
        (r for r in rows if r["admissible"]),
        key=lambda r: (-r["n_within"], abs(r["values"]["ringing_chapter5"] - 0.5)),
    )
    jerk_rows = []
    if JERKS_M_S3[1:]:
        with ProcessPoolExecutor(args.workers) as pool:
            jerk_rows = list(
                pool.map(
                    _one,
                    [
                        (best["acceleration_m_s2"], best["retract_clearance_mm"], j)
                        for j in JERKS_M_S3[1:]
                    ],
                )
            )
    from vibrissa import __version__

    out = {
        "meta": {
            "command": ".venv/bin/python scripts/identify_stage.py --json "
            "docs/runs/identify_stage.json",
            "vibrissa_version": __version__,
            "date": datetime.now(UTC).isoformat(timespec="seconds"),
            "dataset": None,
        },
        "grid": rows,
        "jerk": jerk_rows,
        "chosen": {
            "acceleration_m_s2": best["acceleration_m_s2"],
            "retract_clearance_mm": best["retract_clearance_mm"],
            "n_within": best["n_within"],
            "rule": "admissible (clearance >= 216^2 / 2a), most observables within, then "
            "the chapter-5 fraction of ringing trials nearest 0.5",
        },
    }
    out["derived"] = derive(out)
    _write(args.json, out)
    for r in rows + jerk_rows:
        print(
            f"a={r['acceleration_m_s2']:g} m/s2 c={r['retract_clearance_mm']:g} mm "
            f"j={r['jerk_m_s3']} within={r['n_within']} "
            + " ".join(f"{k}={v:.3g}" for k, v in r["values"].items() if v is not None),
            file=sys.stderr,
        )
    return 0


def _write(path: Path, out: dict[str, Any]) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump(out, fh, indent=1, sort_keys=True)
        fh.write("\n")
    os.replace(tmp, path)


if __name__ == "__main__":
    raise SystemExit(main())
