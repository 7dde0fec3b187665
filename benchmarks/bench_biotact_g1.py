"""Benchmark the whole BIOTACT G1 reproduction (thesis 6.4), quick and full.

Usage::

    .venv/bin/python benchmarks/bench_biotact_g1.py [--workers N]
        [--out benchmarks/results/biotact_g1.json]

Runs ``run_experiment("biotact-g1")`` from scratch in temporary directories: first
``--quick`` (2 textures x 2 distances x 3 strategies x 2 whisks; budget 60 s), then
the full session (3 x 3 classes x 3 strategies x 12 whisks; budget 600 s on 2 cores,
simulation included). Records each run's wall seconds per stage, the machine's load
average when it started and the run's answer to the thesis' claim (RCP7 beats
unmodulated whisking for naive Bayes after few training whisks).
"""

from __future__ import annotations

from reproduce_budget import bench_main

if __name__ == "__main__":
    bench_main(
        "biotact-g1",
        "benchmarks/results/biotact_g1.json",
        __doc__,
        lambda res: {"checks": res["checks"]},
    )
