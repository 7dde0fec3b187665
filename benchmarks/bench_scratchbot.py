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

from reproduce_budget import bench_main

if __name__ == "__main__":
    bench_main(
        "scratchbot",
        "benchmarks/results/scratchbot.json",
        __doc__,
        lambda res: {"relations": res["relations"]},
    )
