"""What the Roomba's floors cost the solver: Newton iterations and time per floor (issue 32).

Usage::

    .venv/bin/python benchmarks/profile_floor_contact.py [--seconds S]
        [--out benchmarks/results/floor_contact.json]

The full floor-texture reproduction is the second-longest of the thesis
(``benchmarks/results/thesis.json``). This script runs one trial of each floor and
movement condition of its full protocol, shortened to ``--seconds`` recorded seconds
(default 1.5, after the 0.6 s settle), twice: as the reproduction runs it and with every
step at ``dt`` (``max_stride=1``: no long steps). Per trial it reports the simulated and
wall seconds of the ``simulate`` call, its real-time factor, the Newton iterations per
row of the result (mean, 99th percentile, largest), the fraction of rows with none
(inside a long step or in linear free flight), and the wall microseconds per counted
iteration. Compare the last with ``benchmarks/results/plane_contact.json``'s pole and
flat-wall cases (CPU seconds over iterations there): iterations a long step tried and
threw away, and steps a failed Newton solve halved, are not counted in a result's
``newton_iterations``, so a large cost per counted iteration points at them.

One untimed trial first loads the kernels. Counts do not depend on the machine's load;
times do (the load average is recorded).
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime as _dt
import importlib
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import get_experiment

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "floor_contact.json"
#: The solver settings compared: the reproduction's own, and fixed steps.
VARIANTS: dict[str, dict[str, Any]] = {"as_run": {}, "fixed_steps": {"max_stride": 1}}


def profile(seconds: float) -> dict[str, Any]:
    """Run one trial per floor and condition under each variant; the counts and times."""
    roomba = importlib.import_module("vibrissa.robots.roomba")
    original = roomba.simulate
    caught: list[tuple[Any, float]] = []
    options: dict[str, Any] = {}

    def spy(*args: Any, **kwargs: Any) -> Any:
        t0 = time.perf_counter()
        res = original(*args, **{**kwargs, **options})
        caught.append((res, time.perf_counter() - t0))
        return res

    protocol = get_experiment("floor-texture").protocol_for(False, 0, {})
    protocol = dataclasses.replace(protocol, duration_s=float(seconds))
    first: dict[tuple[str, str], int] = {}
    for i, spec in enumerate(protocol.trials()):
        first.setdefault((spec.floor, spec.condition), i)
    roomba.simulate = spy
    try:
        protocol.simulate_trials([0])  # load the kernels
        out: dict[str, Any] = {}
        for variant, opts in VARIANTS.items():
            options.clear()
            options.update(opts)
            rows = {}
            for (floor, condition), i in sorted(first.items()):
                caught.clear()
                protocol.simulate_trials([i])
                res, wall = caught[0]
                it = res.newton_iterations
                sim = float(res.time_s[-1] - res.time_s[0])
                rows[f"{floor}, {condition}"] = {
                    "simulated_seconds": round(sim, 3),
                    "wall_seconds": round(wall, 4),
                    "real_time_factor": round(sim / wall, 2),
                    "newton_iterations_per_row": round(float(it.mean()), 3),
                    "newton_iterations_p99": float(np.percentile(it, 99)),
                    "newton_iterations_max": int(it.max()),
                    "rows_without_iterations": round(float(np.mean(it == 0)), 3),
                    "wall_us_per_counted_iteration": round(1e6 * wall / max(int(it.sum()), 1), 1),
                }
                print(f"  {variant}: {floor}, {condition}: {rows[f'{floor}, {condition}']}")
            out[variant] = rows
    finally:
        roomba.simulate = original
    return out


def main(argv: list[str] | None = None) -> int:
    """Parse the options, profile, write the JSON."""
    ap = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--seconds", type=float, default=1.5, help="recorded seconds per trial")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file")
    args = ap.parse_args(argv)
    if not np.isfinite(args.seconds) or not 0.0 < args.seconds <= 16.0:
        ap.error(f"--seconds: expected a number in (0, 16], got {args.seconds}")
    if args.out.exists() and not args.out.is_file():
        ap.error(f"--out: {args.out} is not a file")
    print(
        f"profile_floor_contact: 12 trials x {len(VARIANTS)} variants -> {args.out}",
        file=sys.stderr,
    )
    load = os.getloadavg()[0]
    cases = profile(args.seconds)
    result = {
        "what": "Newton iterations and wall time: one floor-texture trial per floor and condition.",
        "recorded_seconds": args.seconds,
        "variants": {k: v or "the reproduction's settings" for k, v in VARIANTS.items()},
        "load_average_at_start": round(load, 2),
        "load_average_at_end": round(os.getloadavg()[0], 2),
        "cases": cases,
        "meta": {
            "command": " ".join(["python benchmarks/profile_floor_contact.py", *sys.argv[1:]]),
            "vibrissa_version": __version__,
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        },
    }
    atomic_write_text(args.out, json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
