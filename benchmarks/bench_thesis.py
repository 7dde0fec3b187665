"""One number for the whole thesis: the six full reproductions from a clean cache (issue 32).

Usage::

    .venv/bin/python benchmarks/bench_thesis.py [--out FILE] [--workers N] [--quick]
                                                [--only NAME[,NAME...]]

Runs ``radial-distance`` and ``angle-texture`` (chapters 4 and 5), ``floor-texture``,
``scratchbot``, ``biotact-g1`` and ``crunchbot-slam`` (chapter 6) one after another, each
on its full grid in a fresh temporary directory (nothing cached: every dataset is
simulated), on the machine's cores, and records each one's wall time, its stages
(simulation, evaluation, figures, report: ``meta.wall_seconds`` of its results), its
number of trials, the load average when it started, and the total against issue 32's
budget of 10 minutes on 2 cores. The machine (cores, CPU model, memory) is recorded with
them. The JSON (default ``benchmarks/results/thesis.json``) is written atomically after
every reproduction; rerunning with the same ``--out`` resumes after the last one written
(``--restart`` starts again).

``--keep DIR`` keeps each reproduction's output (report, figures, ``results.json``, the
dataset) in ``DIR/NAME`` instead of a temporary directory, with the equivalent
``vibrissa reproduce NAME --out DIR/NAME`` as its recorded command: one run then both
times the thesis and makes the committed results of ``docs/runs``. A kept directory
that already exists is refused before any work (its cached dataset would make the
timing a reuse, not a reproduction).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import machine

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import run_experiment
from vibrissa.thesis.claims import EXPERIMENTS

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "thesis.json"
#: The thesis' six reproductions, in chapter order: the claims ledger's experiments but
#: ``identify`` (a fit of the simulated robot, not a reproduction).
THESIS = tuple(e for e in EXPERIMENTS if e != "identify")
#: Issue 32's budget for all six, full grids, on 2 cores (s).
BUDGET_S = 600.0


def one(name: str, quick: bool, workers: int | None, keep: Path | None = None) -> dict[str, Any]:
    """Run one reproduction from scratch (kept in ``keep / name`` if given); its times."""
    with tempfile.TemporaryDirectory(prefix=f"bench-thesis-{name}-") as tmp:
        out = Path(tmp) / "out" if keep is None else keep / name
        command = None
        if keep is not None:
            flags = ["--quick"] if quick else []
            flags += [f"--workers {workers}"] if workers else []
            command = " ".join(["vibrissa reproduce", name, "--out", str(out), *flags, "--json"])
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = run_experiment(name, out, quick=quick, workers=workers, command=command)
        wall = time.perf_counter() - t0
    meta = res["meta"]
    return {
        "wall_seconds": round(wall, 2),
        "stages_seconds": meta.get("wall_seconds"),
        "n_trials": (meta.get("dataset") or {}).get("n_trials"),
        "load_average_at_start": round(load, 2),
    }


def main(argv: list[str] | None = None) -> int:
    """Run what is not yet in ``--out``; print and write the times."""
    ap = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file (resumed)")
    ap.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    ap.add_argument("--quick", action="store_true", help="the quick grids instead")
    ap.add_argument("--only", default="", help="comma list of reproductions (default: all six)")
    ap.add_argument("--restart", action="store_true", help="ignore what --out already holds")
    ap.add_argument(
        "--keep", type=Path, default=None, help="keep each reproduction's output in KEEP/NAME"
    )
    args = ap.parse_args(argv)
    names = [n for n in args.only.split(",") if n] or list(THESIS)
    unknown = sorted(set(names) - set(THESIS))
    if unknown:
        ap.error(f"--only: unknown reproduction(s) {', '.join(unknown)}; choose from {THESIS}")
    if args.workers is not None and args.workers < 1:
        ap.error("--workers: expected a positive integer")
    if args.out.exists() and not args.out.is_file():
        ap.error(f"--out: {args.out} is not a regular file")
    if args.keep is not None and args.keep.exists() and not args.keep.is_dir():
        ap.error(f"--keep: {args.keep} is not a directory")
    done: dict[str, Any] = {}
    if args.out.is_file() and not args.restart:
        old = json.loads(args.out.read_text())
        if old.get("quick") == args.quick and old.get("workers") == args.workers:
            done = dict(old.get("runs", {}))
    todo = [n for n in names if n not in done]
    if args.keep is not None:
        there = [n for n in todo if (args.keep / n).exists()]
        if there:
            ap.error(f"--keep: {args.keep} already holds {', '.join(there)} (remove it first)")
    print(
        f"bench_thesis: {len(todo)} of {len(names)} reproductions to run "
        f"({'quick' if args.quick else 'full'} grids) -> {args.out}",
        file=sys.stderr,
    )
    for name in todo:
        print(f"  {name} ...", file=sys.stderr, flush=True)
        done[name] = one(name, args.quick, args.workers, args.keep)
        total = sum(v["wall_seconds"] for k, v in done.items() if k in names)
        result = {
            "quick": args.quick,
            "workers": args.workers,
            "machine": machine(),
            "runs": done,
            "total_seconds": round(total, 1),
            "budget_seconds": BUDGET_S,
            "complete": all(n in done for n in names),
            "within_budget": total <= BUDGET_S and all(n in done for n in names),
            "meta": {
                "command": " ".join(["python benchmarks/bench_thesis.py", *sys.argv[1:]]),
                "vibrissa_version": __version__,
                "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
            },
        }
        atomic_write_text(args.out, json.dumps(result, indent=1) + "\n")
        print(f"  {name}: {done[name]['wall_seconds']:.0f} s", file=sys.stderr, flush=True)
    summary = {n: done[n]["wall_seconds"] for n in names if n in done}
    print(json.dumps({**summary, "total": round(sum(summary.values()), 1)}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
