"""Benchmark the chapter-4 classifiers and evaluation protocol on a dataset.

Usage::

    .venv/bin/python benchmarks/bench_chapter4.py [--dataset FILE.nc]
        [--out benchmarks/results/chapter4.json]

(default dataset: the one `vibrissa reproduce radial-distance` cached)

Measures, for every classifier, the time to fit on one complete training set and to
classify one complete test set (2,626 trials each on the thesis grid), and the wall
time of the whole protocol (all training fractions, five seeds).
"""

from __future__ import annotations

import argparse
import glob
import json
import time
from pathlib import Path

from vibrissa._atomic import atomic_write_text
from vibrissa.classify import chapter4_classifiers
from vibrissa.data import load_dataset, whisker_params
from vibrissa.evaluate.chapter4 import run_chapter4


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--dataset", default=None)
    ap.add_argument("--out", default="benchmarks/results/chapter4.json")
    args = ap.parse_args()
    path = args.dataset or next(
        iter(sorted(glob.glob("vibrissa-out/radial-distance/data/*.nc"))), None
    )
    if path is None:
        raise SystemExit("no dataset: run `vibrissa reproduce radial-distance` or pass --dataset")
    ds = load_dataset(path)
    clfs = chapter4_classifiers(float(ds.attrs["sample_rate_hz"]), whisker_params(ds))
    t0 = time.perf_counter()
    res = run_chapter4(ds, clfs, keep_predictions=False)
    wall = time.perf_counter() - t0
    record = {
        "dataset": str(path),
        "n_trials": int(ds.sizes["trial"]),
        "n_train": res["meta"]["split"]["n_train"],
        "n_test": res["meta"]["split"]["n_test"],
        "protocol_wall_seconds": round(wall, 2),
        "classifiers": {
            name: {
                "fit_seconds": round(e["fit_seconds"], 3),
                "classify_seconds": round(e["classify_seconds"], 3),
            }
            for name, e in res["classifiers"].items()
        },
    }
    atomic_write_text(Path(args.out), json.dumps(record, indent=2))
    print(json.dumps(record, indent=2))


if __name__ == "__main__":
    main()
