"""Shared by the whole-reproduction benchmarks: time ``run_experiment`` quick and full
against the issue's budgets (60 s quick, 600 s full on 2 cores, simulation included)
and write the timings, the machine and each run's own numbers as JSON."""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import run_experiment

BUDGET_S = {"quick": 60.0, "full": 600.0}


def timed_run(
    name: str, quick: bool, workers: int | None, extract: Callable[[dict], dict[str, Any]]
) -> dict[str, Any]:
    """Run experiment ``name`` from scratch in a temporary directory; return its wall
    seconds per stage, the budget, the load average at the start and ``extract(results)``."""
    key = "quick" if quick else "full"
    with tempfile.TemporaryDirectory() as tmp:
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = run_experiment(name, Path(tmp) / "out", quick=quick, workers=workers)
        wall = time.perf_counter() - t0
    return {
        "wall_seconds": round(wall, 2),
        "stages": res["meta"]["wall_seconds"],
        "budget_seconds": BUDGET_S[key],
        "within_budget": wall <= BUDGET_S[key],
        "load_average_at_start": round(load, 2),
        "n_trials": res["meta"]["dataset"]["n_trials"],
        **extract(res),
    }


def bench_main(
    name: str, default_out: str, doc: str | None, extract: Callable[[dict], dict[str, Any]]
) -> None:
    """The command line of a whole-reproduction benchmark: quick, then full."""
    ap = argparse.ArgumentParser(
        description=doc, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--workers", type=int, default=None, help="generation processes")
    ap.add_argument("--out", default=default_out)
    args = ap.parse_args()
    runs = {k: timed_run(name, k == "quick", args.workers, extract) for k in ("quick", "full")}
    machine = {
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "platform": platform.platform(),
    }
    atomic_write_text(Path(args.out), json.dumps({"machine": machine, **runs}, indent=2) + "\n")
    print(json.dumps({k: v["wall_seconds"] for k, v in runs.items()}))
