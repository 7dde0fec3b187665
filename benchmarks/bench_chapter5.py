"""Benchmark the whole chapter-5 reproduction and every classifier on its test set.

Usage::

    .venv/bin/python benchmarks/bench_chapter5.py [--quick] [--workers N]
        [--out benchmarks/results/chapter5.json] [--keep DIR]

Runs ``run_experiment("angle-texture")`` (:mod:`vibrissa.reproduce`) from scratch in a
temporary directory (dataset generation, numba start-up, every classifier, texture
alone, the sequential curve and the figures), then records:

* ``reproduction_wall_seconds`` - the whole job; the issue's budget is 600 s;
* per classifier ``classify_seconds`` - classifying the complete test set (704
  trials x 2 channels x 6,001 samples on the full grid) with one fitted model;
  budget 5 s - plus ``fit_seconds`` and ``texture_alone_seconds`` (88 refits, one
  per speed-angle combination);
* peak resident memory of the process and of its largest worker.

``--keep DIR`` keeps the outputs (report, figures, dataset) in DIR instead of a
temporary directory.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import tempfile
import time
from pathlib import Path

from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import run_experiment

CLASSIFY_BUDGET_S = 5.0
REPRODUCTION_BUDGET_S = 600.0


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--quick", action="store_true", help="the small grid (3 x 3 x 4 x 4)")
    ap.add_argument("--workers", type=int, default=None, help="generation processes")
    ap.add_argument("--out", default="benchmarks/results/chapter5.json")
    ap.add_argument("--keep", default=None, help="keep the outputs in this directory")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        where = Path(args.keep) if args.keep else Path(tmp) / "angle-texture"
        t0 = time.perf_counter()
        res = run_experiment("angle-texture", where, quick=args.quick, workers=args.workers)
        wall = time.perf_counter() - t0
    if res["meta"]["dataset"]["reused"]:
        raise SystemExit(f"{where} already held the dataset; use an empty --keep directory")
    classifiers = {
        name: {
            "classify_seconds": round(e["classify_seconds"], 3),
            "fit_seconds": round(e["fit_seconds"], 3),
            "texture_alone_seconds": (
                None if e["texture_alone_seconds"] is None else round(e["texture_alone_seconds"], 3)
            ),
        }
        for name, e in res["classifiers"].items()
    }
    slowest = max(classifiers, key=lambda k: classifiers[k]["classify_seconds"])
    record = {
        "protocol": "angle-texture",
        "quick": args.quick,
        "n_trials": res["meta"]["n_trials"],
        "n_train": res["meta"]["split"]["n_train"],
        "n_test": res["meta"]["split"]["n_test"],
        "workers": args.workers or os.cpu_count(),
        "reproduction_wall_seconds": round(wall, 1),
        "generate_seconds": res["meta"]["wall_seconds"]["generate"],
        "evaluate_seconds": res["meta"]["wall_seconds"]["evaluate"],
        "slowest_classifier": slowest,
        "slowest_classify_seconds": classifiers[slowest]["classify_seconds"],
        "budgets": {
            "classify_seconds": CLASSIFY_BUDGET_S,
            "reproduction_wall_seconds": REPRODUCTION_BUDGET_S,
        },
        "within_budgets": {
            "classify_seconds": classifiers[slowest]["classify_seconds"] <= CLASSIFY_BUDGET_S,
            "reproduction_wall_seconds": wall <= REPRODUCTION_BUDGET_S,
        },
        "peak_rss_parent_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        "peak_rss_largest_worker_mb": round(
            resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024, 1
        ),
        "classifiers": classifiers,
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "processor": platform.machine(),
        },
    }
    atomic_write_text(Path(args.out), json.dumps(record, indent=2))
    print(json.dumps(record, indent=2))


if __name__ == "__main__":
    main()
