"""Benchmark the whole SCRATCHbot reproduction (thesis 6.3), quick and full.

Usage::

    .venv/bin/python benchmarks/bench_scratchbot.py [--workers N]
        [--out benchmarks/results/scratchbot.json]

Runs ``run_experiment("scratchbot")`` from scratch in temporary directories, first
``--quick`` (4 whisks per condition; budget 60 s) then the full grid (3 distances x
3 whisk frequencies x 12 whisks, plus the three closed-loop RCP runs; budget 600 s on
2 cores, simulation included), and records each run's wall seconds per stage, the
6.3 relations and the machine's load average when it started.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import run_experiment

BUDGET_S = {"quick": 60.0, "full": 600.0}


def _run(quick: bool, workers: int | None) -> dict:
    key = "quick" if quick else "full"
    with tempfile.TemporaryDirectory() as tmp:
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = run_experiment("scratchbot", Path(tmp) / "out", quick=quick, workers=workers)
        wall = time.perf_counter() - t0
    return {"wall_seconds": round(wall, 2), "stages": res["meta"]["wall_seconds"],
            "budget_seconds": BUDGET_S[key], "within_budget": wall <= BUDGET_S[key],
            "load_average_at_start": round(load, 2),
            "n_trials": res["meta"]["dataset"]["n_trials"], "relations": res["relations"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workers", type=int, default=None, help="generation processes")
    ap.add_argument("--out", default="benchmarks/results/scratchbot.json")
    args = ap.parse_args()
    runs = {"quick": _run(True, args.workers), "full": _run(False, args.workers)}
    machine = {"cores": os.cpu_count(), "python": platform.python_version(),
               "platform": platform.platform()}
    atomic_write_text(Path(args.out), json.dumps({"machine": machine, **runs}, indent=2) + "\n")
    print(json.dumps({k: v["wall_seconds"] for k, v in runs.items()}))


if __name__ == "__main__":
    main()
