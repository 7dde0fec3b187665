"""Benchmark tactile SLAM (thesis 6.5.3): one 6-minute sensor log through the particle filter.

Usage::

    .venv/bin/python benchmarks/bench_slam.py [--steps 720] [--particles 100]
        [--seed 0] [--repeats 1] [--out benchmarks/results/slam.json]

Builds a synthetic sensor log of the SLAM arena (``vibrissa.robots.crunchbot``: exact
ray-cast whisker contacts, 10 % odometry error, the 6.5.3 FSM) cut to ``--steps`` FSM
steps (720 steps of 0.5 s are the thesis' 6-minute run), then times ``run_slam`` with
``--particles`` particles in each mapping mode (budget 60 s per run on this machine,
aim 20 s; issue 16). Records wall seconds per mode (best of ``--repeats``), per-step
milliseconds, the log's own generation time and the machine's load average at the start,
plus each run's map error (eq. 6.3) and mean trajectory error against the true pose.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

from vibrissa._atomic import atomic_write_text
from vibrissa.robots.crunchbot import PRESETS, synthetic_log
from vibrissa.slam import MODES, SlamSettings, map_error, run_slam, smooth_ground_truth

BUDGET_S = 60.0
AIM_S = 20.0


def _log(steps: int, seed: int):
    """A SLAM-arena log of at least ``steps`` steps, cut to ``steps``."""
    seconds = 0.5 * steps
    while True:
        log = synthetic_log(PRESETS["slam"], seconds, seed=seed)
        if log.n_steps >= steps:
            return log.head(steps)
        seconds *= 1.5


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--steps", type=int, default=720, help="FSM steps of 0.5 s (720 = 6 min)")
    ap.add_argument("--particles", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--out", default="benchmarks/results/slam.json")
    args = ap.parse_args()
    if args.steps <= 0 or args.particles <= 0 or args.repeats <= 0:
        ap.error("--steps, --particles and --repeats must be positive")
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    log = _log(args.steps, args.seed)
    log_s = time.perf_counter() - t0
    truth = smooth_ground_truth(PRESETS["slam"].occupancy_grid())
    modes = {}
    for mode in MODES:
        settings = SlamSettings(n_particles=args.particles, mode=mode)
        walls = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            run = run_slam(log, settings, seed=args.seed)
            walls.append(time.perf_counter() - t0)
        err = np.hypot(*(run.pose_estimate[:, :2] - log.true_pose[:, :2]).T)
        wall = min(walls)
        modes[mode] = {
            "wall_seconds": round(wall, 3),
            "ms_per_step": round(1000 * wall / log.n_steps, 3),
            "within_budget": wall <= BUDGET_S,
            "within_aim": wall <= AIM_S,
            "map_error": round(map_error(run.best_map(), truth), 4),
            "trajectory_error_mm_mean": round(1000 * float(err.mean()), 1),
            "n_resamples": run.n_resamples,
        }
    machine = {
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "platform": platform.platform(),
    }
    out = {
        "machine": machine,
        "load_average_at_start": round(load, 2),
        "command": "benchmarks/bench_slam.py "
        + " ".join(f"--{k} {v}" for k, v in vars(args).items() if k != "out"),
        "n_steps": log.n_steps,
        "n_particles": args.particles,
        "nominal_seconds": float(0.5 * log.n_steps),
        "log_generation_seconds": round(log_s, 3),
        "budget_seconds": BUDGET_S,
        "aim_seconds": AIM_S,
        "modes": modes,
    }
    atomic_write_text(Path(args.out), json.dumps(out, indent=2) + "\n")
    print(json.dumps({k: v["wall_seconds"] for k, v in modes.items()}))


if __name__ == "__main__":
    main()
