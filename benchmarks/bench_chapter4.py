"""Benchmark the chapter-4 evaluation stage as `vibrissa reproduce radial-distance` runs it.

Usage::

    .venv/bin/python benchmarks/bench_chapter4.py [--dataset FILE.nc] [--workers N]
        [--profile N] [--out benchmarks/results/chapter4.json]

(default dataset: the one `vibrissa reproduce radial-distance` cached)

Runs the experiment's evaluation on the dataset exactly as the reproduction does (the
author's split with every reduced training fraction and seed, then the "other split"),
with ``--workers`` processes (default: all cores), and records its wall time and, per
classifier, the seconds its fits and classifications took summed over every fit (the
full training sets, the reduced ones, the other split; with workers these add time
spent in parallel, so their sum exceeds the wall time). ``--profile N`` runs it under
cProfile instead (in this process: use ``--workers 1`` to see the fits) and prints the
N costliest functions by own time; the profiled run is not recorded.
"""

from __future__ import annotations

import argparse
import cProfile
import glob
import json
import os
import platform
import pstats
import time
from pathlib import Path
from typing import Any

from vibrissa._atomic import atomic_write_text
from vibrissa.data import load_dataset
from vibrissa.evaluate.jobs import resolve_workers
from vibrissa.reproduce import get_experiment


def _fits(results: dict[str, Any]) -> dict[str, list[dict[str, Any]]]:
    """Every fit of each classifier: the full training set, each reduced set, the other split."""
    fits: dict[str, list[dict[str, Any]]] = {n: [e] for n, e in results["classifiers"].items()}
    for per in results["training_fractions"].values():
        for name, entry in per.items():
            fits[name] += (entry or {}).get("per_seed", [])
    for name, entry in results["other_split"]["classifiers"].items():
        fits[name].append(entry)
    return fits


def classifier_times(results: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Per classifier: fits, summed fit and classify seconds, and the full training set's."""
    out = {}
    for name, fits in _fits(results).items():
        fit = sum(f.get("fit_seconds") or 0.0 for f in fits)
        classify = sum(f.get("classify_seconds") or 0.0 for f in fits)
        full = results["classifiers"][name]
        out[name] = {
            "n_fits": len(fits),
            "fit_seconds": round(fit, 3),
            "classify_seconds": round(classify, 3),
            "total_seconds": round(fit + classify, 3),
            "full_training_set": {
                "fit_seconds": round(full["fit_seconds"], 3),
                "classify_seconds": round(full["classify_seconds"], 3),
            },
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--dataset", default=None)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--profile", type=int, default=0, metavar="N")
    ap.add_argument("--out", default="benchmarks/results/chapter4.json")
    args = ap.parse_args()
    path = args.dataset or next(
        iter(sorted(glob.glob("vibrissa-out/radial-distance/data/*.nc"))), None
    )
    if path is None:
        raise SystemExit("no dataset: run `vibrissa reproduce radial-distance` or pass --dataset")
    workers = resolve_workers(args.workers)
    ds = load_dataset(path)
    exp = get_experiment("radial-distance")
    options = {o.name: o.default for o in exp.options}

    def evaluate() -> dict[str, Any]:
        return exp.evaluate(ds, seed=0, progress=None, options=options, workers=workers)

    if args.profile:
        prof = cProfile.Profile()
        prof.runcall(evaluate)
        pstats.Stats(prof).sort_stats("tottime").print_stats(args.profile)
        return
    t0 = time.perf_counter()
    res = evaluate()
    wall = time.perf_counter() - t0
    times = classifier_times(res)
    record = {
        "dataset": str(path),
        "n_trials": int(ds.sizes["trial"]),
        "split": res["meta"]["split"],
        "fractions": res["meta"]["fractions"],
        "n_seeds": res["meta"]["n_seeds"],
        "workers": workers,
        "evaluate_wall_seconds": round(wall, 2),
        "n_fits": sum(t["n_fits"] for t in times.values()),
        "fit_and_classify_seconds": round(sum(t["total_seconds"] for t in times.values()), 2),
        "classifiers": times,
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
