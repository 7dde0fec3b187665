"""Benchmark dataset generation: wall time, throughput and peak memory.

Usage::

    .venv/bin/python benchmarks/bench_generation.py [--protocol radial-distance] [--quick]
        [--workers N] [--out benchmarks/results/generation.json]

Generates into a temporary directory (nothing is cached) and writes a JSON record.
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
from vibrissa.experiments.generate import generate
from vibrissa.experiments.protocols import get_protocol


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--protocol", default="radial-distance")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--out", default="benchmarks/results/generation.json")
    ap.add_argument(
        "--keep",
        default=None,
        help="directory to keep the dataset in, named as `vibrissa reproduce` "
        "caches it (e.g. vibrissa-out/radial-distance/data)",
    )
    args = ap.parse_args()
    proto = get_protocol(args.protocol, quick=args.quick)
    with tempfile.TemporaryDirectory() as tmp:
        where = Path(args.keep) if args.keep else Path(tmp)
        path = where / f"{proto.name}-{proto.fingerprint()}.nc"
        t0 = time.perf_counter()
        ds = generate(proto, path, workers=args.workers, restart=True)
        wall = time.perf_counter() - t0
        size = path.stat().st_size
    self_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    child_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    record = {
        "protocol": proto.name,
        "quick": args.quick,
        "n_trials": int(ds.sizes["trial"]),
        "workers": args.workers or os.cpu_count(),
        "wall_seconds": round(wall, 2),
        "trials_per_second": round(ds.sizes["trial"] / wall, 2),
        "peak_rss_parent_mb": round(self_mb, 1),
        "peak_rss_largest_worker_mb": round(child_mb, 1),
        "file_mb": round(size / 1e6, 2),
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "processor": platform.machine(),
        },
    }
    out = Path(args.out)
    atomic_write_text(out, json.dumps(record, indent=2))
    print(json.dumps(record, indent=2))


if __name__ == "__main__":
    main()
