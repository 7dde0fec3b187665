"""Benchmark the whole Roomba floor-texture reproduction (thesis 6.2), quick and full.

Usage::

    .venv/bin/python benchmarks/bench_floor_texture.py [--workers N]
        [--out benchmarks/results/floor_texture.json]

Runs ``run_experiment("floor-texture")`` from scratch in temporary directories, first
``--quick`` (budget 60 s) then the full session (48 trials of 16 s at 2 kHz; budget
600 s on 2 cores, simulation included), and records each run's wall seconds per stage
(generate, evaluate, report, total), its mean-correct figures and the machine's load
average when it started (other people's work shares the cores).
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
    with tempfile.TemporaryDirectory() as tmp:
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = run_experiment("floor-texture", Path(tmp) / "out", quick=quick, workers=workers)
        wall = time.perf_counter() - t0
    return {
        "wall_seconds": round(wall, 2),
        "stages": res["meta"]["wall_seconds"],
        "budget_seconds": BUDGET_S["quick" if quick else "full"],
        "within_budget": wall <= BUDGET_S["quick" if quick else "full"],
        "load_average_at_start": round(load, 2),
        "n_trials": res["meta"]["dataset"]["n_trials"],
        "mean_correct": res["mean_correct"],
        "cross_condition": {k: res["cross_condition"].get(k) for k in ("cw_on_ccw", "ccw_on_cw")},
        "naive_bayes_mean_correct": res["naive_bayes"]["mean_correct"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--workers", type=int, default=None, help="generation processes")
    ap.add_argument("--out", default="benchmarks/results/floor_texture.json")
    args = ap.parse_args()
    out = {
        "machine": {
            "cores": os.cpu_count(),
            "python": platform.python_version(),
            "platform": platform.platform(),
        },
        "quick": _run(True, args.workers),
        "full": _run(False, args.workers),
    }
    atomic_write_text(Path(args.out), json.dumps(out, indent=2) + "\n")
    print(json.dumps({k: out[k]["wall_seconds"] for k in ("quick", "full")}))


if __name__ == "__main__":
    main()
