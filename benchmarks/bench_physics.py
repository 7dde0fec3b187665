"""Real-time factor of the standard pole-contact trial over time steps and element counts.

Usage::

    .venv/bin/python benchmarks/bench_physics.py [--out FILE] [--repeats N]

For dt in (0.125, 0.25) ms and n_elements in (24, 48) it times the standard
scenario of ``vibrissa bench physics`` (xy-robot whisker, pole at r = 140 mm,
100 mm/s in for 0.3 s, 720 mm/s out by 36 mm, 1.5 s, Hall output at 4 kHz; best
of N runs after a warm-up, one core), measures the peak memory of one trial of
the standard configuration (dt 0.25 ms, default elements) with tracemalloc, and
writes everything as JSON (default ``benchmarks/results/physics.json``, written
atomically).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import sys
from pathlib import Path
from typing import Any

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.whisker.benchmark import MEMORY_METHOD, SCENARIO, STANDARD, physics_benchmark

DT_S = (1.25e-4, 2.5e-4)
N_ELEMENTS = (24, 48)
DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "physics.json"

_ROW_KEYS = (
    "dt_s",
    "n_elements",
    "real_time_factor",
    "free_flight_real_time_factor",
    "whisking_in_air_real_time_factor",
    "contact_real_time_factor",
    "linear_free_flight_fraction",
    "wall_seconds",
    "wall_seconds_all",
    "cpu_seconds",
    "n_steps",
    "peak_follicle_moment_nm",
    "peak_hall_x_v",
)


def run(repeats: int = 3) -> dict[str, Any]:
    """Run the benchmark grid and the memory trial.

    Parameters
    ----------
    repeats : int
        Timed runs per configuration (the fastest counts).

    Returns
    -------
    dict
        ``scenario``, ``standard`` (its parameters), ``runs`` (one row per dt and
        element count), ``memory`` (peak MB of one standard trial and the method),
        versions and a timestamp.
    """
    runs = []
    for n in N_ELEMENTS:
        for dt in DT_S:
            r = physics_benchmark(dt_s=dt, n_elements=n, repeats=repeats, measure_memory=False)
            runs.append({k: r[k] for k in _ROW_KEYS})
            print(
                f"n_elements={n:3d} dt={dt * 1e3:.3f} ms: real-time factor "
                f"{r['real_time_factor']:6.1f} ({r['wall_seconds']:.3f} s wall)",
                file=sys.stderr,
            )
    # before/after on the same machine in the same run: every speed-up off, then on
    std_cfg = {"repeats": repeats, "measure_memory": False}
    without = physics_benchmark(speedups=False, **std_cfg)
    with_ = physics_benchmark(speedups=True, **std_cfg)
    print(
        f"standard trial: real-time factor {with_['real_time_factor']:.1f} "
        f"(without the speed-ups {without['real_time_factor']:.1f})",
        file=sys.stderr,
    )
    std = physics_benchmark(repeats=1, measure_memory=True)
    print(f"memory of one standard trial: {std['peak_memory_mb']:.2f} MB", file=sys.stderr)
    return {
        "scenario": SCENARIO,
        "standard": dict(STANDARD),
        "runs": runs,
        "standard_trial": {k: with_[k] for k in _ROW_KEYS},
        "standard_trial_without_speedups": {k: without[k] for k in _ROW_KEYS},
        "speedup": with_["real_time_factor"] / without["real_time_factor"],
        "memory": {
            "dt_s": std["dt_s"],
            "n_elements": std["n_elements"],
            "peak_memory_mb": std["peak_memory_mb"],
            "peak_memory_method": MEMORY_METHOD,
            "process_max_rss_mb": std["process_max_rss_mb"],
            "real_time_factor_single_run": std["real_time_factor"],
        },
        "python": std["python"],
        "machine": std["machine"],
        "cpu_count": std["cpu_count"],
        "vibrissa_version": __version__,
        "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help=f"JSON file to write (default {DEFAULT_OUT})."
    )
    parser.add_argument(
        "--repeats",
        type=int,
        default=3,
        help="Timed runs per configuration; the fastest counts (default 3).",
    )
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    result = run(args.repeats)
    atomic_write_text(args.out, json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
