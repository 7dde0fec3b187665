"""Identify where CrunchBot's four obstacle whiskers sit from what the thesis reports (issue 31).

The thesis gives no layout: four forward whiskers (with two outer ones angled down to
the floor) on an iRobot Create, "different groups of whiskers make contact with the
walls of an arena depending on the angle of approach" (5.5), each whisker 140 mm outside
its follicle (6.5.4). What it reports of the robot's behaviour constrains it: FWD_2 ends
in HIT_2, a second whisker touching, and only "in some cases" in ABORT on the strain
safety threshold (6.5.5.2). How often a second whisker reaches a surface before the
first is strained past the threshold depends on how far apart the whiskers sit and how
far they splay, so the layout is identified from that stated outcome::

    .venv/bin/python scripts/identify_crunchbot_layout.py \\
        --json docs/runs/identify_crunchbot_layout.json

The family (:func:`~vibrissa.robots.crunchbot.synthetic.front_array_layout`): four whiskers
side by side on the Create's front edge at a pitch (distance between neighbouring
bases), the outer two pointing ``splay`` outward and the inner two a third of that.
Each candidate drives the thesis' FSM in the SLAM arena (truth mode: no classifiers,
floor whiskers off, which changes nothing the FSM reads) for ``--seeds`` runs of
``--seconds``. Chosen: the widest layout (largest splay, then largest pitch) at which
every run ends FWD_2 in HIT_2 more often than in ABORT and some FWD_2 ends in ABORT
over all runs ("ABORT in some cases", run by run). Results are kept in
``<json stem>.runs.jsonl`` beside the output, so an interrupted run resumes.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import itertools
import json
import math
import os
import sys
import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from identify_crunchbot_fsm import _resume, truth_run

from vibrissa.reproduce.provenance import git_commit

#: Candidate pitches (m): units side by side (20 and 30 mm) and the former layout's 48 mm.
PITCHES_M = (0.02, 0.03, 0.048)
#: Candidate splays of the outer whiskers (rad): parallel to the former layout's 0.8.
SPLAYS_RAD = (0.0, 0.3, 0.45, 0.8)
#: The layout before this identification (pitch m, splay rad; ours, without a source).
FORMER = (0.048, 0.8)


def _one(job: tuple[float, float, int, float]) -> dict[str, Any]:
    from vibrissa.robots.crunchbot.synthetic import front_array_layout

    pitch, splay, seed, seconds = job
    layout = front_array_layout(pitch, splay)
    return {"pitch_m": pitch, "splay_rad": splay, **truth_run(seed, seconds, layout=layout)}


def _key(r: dict[str, Any]) -> tuple:
    return (r["pitch_m"], r["splay_rad"], r["seed"], r["seconds"])


def summarise(runs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per layout: FWD_2 ends per run and summed, circuits per 6 minutes."""
    rows = []
    for layout, group in itertools.groupby(sorted(runs, key=_key), key=lambda r: _key(r)[:2]):
        g = list(group)
        ends = [r["counts"]["fwd2_ends"] for r in g]
        hit2 = sum(e["hit_2"] for e in ends)
        abort = sum(e["abort"] for e in ends)
        seconds = sum(r["seconds"] for r in g)
        rows.append(
            {
                "pitch_m": layout[0],
                "splay_rad": layout[1],
                "pitch_mm": layout[0] * 1e3,
                "splay_deg": math.degrees(layout[1]),
                "runs": len(g),
                "fwd2_ends": {"hit_2": hit2, "abort": abort},
                "fwd2_ends_per_run": ends,
                "hit_2_share_of_fwd2_ends": hit2 / (hit2 + abort) if hit2 + abort else None,
                "hit_2_beats_abort_every_run": all(e["hit_2"] > e["abort"] for e in ends),
                "abort_after_fwd1": sum(r["counts"]["abort_after"]["FWD_1"] for r in g),
                "circuits_per_6_min": sum(r["circuits"] for r in g) * 360.0 / seconds,
                "wall_s_per_6_min": sum(r["wall_s"] for r in g) * 360.0 / seconds,
            }
        )
    return rows


def choose(rows: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The widest layout at which HIT_2 ends FWD_2 more often than ABORT in every run.

    Widest: the largest splay, then the largest pitch. Admissible also needs some ABORT
    over all runs (the thesis' "in some cases"). ``None`` if no layout is admissible.
    """
    ok = [r for r in rows if r["hit_2_beats_abort_every_run"] and r["fwd2_ends"]["abort"] > 0]
    if not ok:
        return None
    return max(ok, key=lambda r: (r["splay_rad"], r["pitch_m"]))


def main(argv: list[str] | None = None) -> int:
    """Run every candidate layout (resumable), choose one, write the JSON."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", type=Path, required=True, help="output file")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--seeds", type=int, default=4, help="runs per layout")
    ap.add_argument("--seconds", type=float, default=120.0, help="robot seconds per run")
    args = ap.parse_args(argv)
    if args.workers < 1 or args.seeds < 1 or not (0 < args.seconds <= 3600):
        ap.error("--workers and --seeds must be >= 1 and --seconds in (0, 3600]")
    base = args.json.with_name(args.json.stem)
    jobs = [
        (p, s, seed, args.seconds)
        for s in SPLAYS_RAD
        for p in PITCHES_M
        for seed in range(args.seeds)
    ]
    runs = _resume(base.with_suffix(".runs.jsonl"), _one, jobs, _key, args.workers)
    table = summarise(runs)
    chosen = choose(table)
    out = {
        "meta": {
            "command": "python scripts/identify_crunchbot_layout.py "
            + " ".join(argv or sys.argv[1:]),
            "commit": git_commit(),
            "vibrissa_version": importlib.metadata.version("vibrissa"),
            "date": datetime.now(UTC).date().isoformat(),
            "dataset": None,
            "rule": "the widest layout (largest splay, then pitch) at which every run ends "
            "FWD_2 in HIT_2 more often than in ABORT, with some ABORT over all runs",
        },
        "layouts": table,
        "chosen": chosen,
        "former": next((r for r in table if (r["pitch_m"], r["splay_rad"]) == FORMER), None),
        "runs": runs,
    }
    args.json.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.json.parent, delete=False, suffix=".tmp") as tmp:
        json.dump(out, tmp, indent=1)
    os.replace(tmp.name, args.json)
    print(json.dumps({"chosen": chosen}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
