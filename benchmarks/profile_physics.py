"""Where the physics spends its time: profiles of the standard contact and of a chapter-4 chunk.

Usage::

    .venv/bin/python benchmarks/profile_physics.py [--out FILE] [--trials N] [--top K]

Times (best of 3, without the profiler) and profiles (cProfile, after a warm-up; its
hooks slow short calls, so its totals run high) the standard pole contact of ``vibrissa bench
physics`` (five trials) and a chunk of the chapter-4 grid (``--trials`` trials spread
over the full grid, simulated as ``vibrissa generate`` does), each twice: as
:func:`~vibrissa.whisker.simulate.simulate` runs by default, and with every speed-up
off (nonlinear rod at every step of ``dt``: linear free flight and long steps
disabled). The numba kernels appear as single entries (``run_dynamics`` is the
nonlinear rod, ``modal_advance`` the linear free flight). Writes the top ``--top``
entries by own time and the totals as JSON (default
``benchmarks/results/profile.json``, atomically) and prints them.
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as _dt
import functools
import json
import pstats
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "profile.json"


@contextmanager
def _speedups(on: bool) -> Iterator[None]:
    """Within the block, the XY robot simulates with the speed-ups on or off."""
    import vibrissa.robots.xy_stage as xy

    original = xy.simulate
    if not on:
        xy.simulate = functools.partial(original, linear_free_flight=False, max_stride=1)
    try:
        yield
    finally:
        xy.simulate = original


def _profile(work: Callable[[], Any], top: int) -> dict[str, Any]:
    work()  # warm-up: kernels loaded, caches filled
    walls = []
    for _ in range(3):  # timed without the profiler, whose hooks distort short calls
        t0 = time.perf_counter()
        work()
        walls.append(time.perf_counter() - t0)
    wall = min(walls)
    prof = cProfile.Profile()
    prof.enable()
    work()
    prof.disable()
    stats = pstats.Stats(prof)
    rows = []
    for (file, line, name), (_, ncalls, tottime, cumtime, _) in stats.stats.items():
        rows.append(
            {
                "function": f"{Path(file).name}:{line}({name})",
                "ncalls": int(ncalls),
                "tottime_s": round(tottime, 4),
                "cumtime_s": round(cumtime, 4),
            }
        )
    rows.sort(key=lambda r: -r["tottime_s"])
    return {"wall_seconds": wall, "wall_seconds_profiled": stats.total_tt, "top": rows[:top]}


def _standard(on: bool) -> Callable[[], Any]:
    from vibrissa.whisker import RodModel, preset
    from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
    from vibrissa.whisker.simulate import PoleContact, simulate

    model = RodModel(preset(STANDARD["preset"]))
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    traj = standard_trajectory(model)
    opts = {} if on else {"linear_free_flight": False, "max_stride": 1}

    def work() -> None:
        for _ in range(5):
            simulate(model, contact, traj, STANDARD["duration_s"], STANDARD["dt_s"], **opts)

    return work


def _chapter4_chunk(on: bool, n_trials: int) -> Callable[[], Any]:
    from vibrissa.experiments.protocols import get_protocol
    from vibrissa.experiments.runner import simulate_trials

    protocol = get_protocol("radial-distance", quick=False, seed=0)
    idx = np.linspace(0, protocol.n_trials - 1, n_trials).astype(int)

    def work() -> None:
        with _speedups(on):
            simulate_trials(protocol, idx)

    return work


def run(n_trials: int, top: int) -> dict[str, Any]:
    """Profile both workloads with the speed-ups on and off."""
    out: dict[str, Any] = {}
    for label, on in (("with_speedups", True), ("without_speedups", False)):
        out[label] = {
            "standard_contact_x5": _profile(_standard(on), top),
            f"chapter4_chunk_{n_trials}_trials": _profile(_chapter4_chunk(on, n_trials), top),
        }
        for name, res in out[label].items():
            print(f"{label:17s} {name:28s} {res['wall_seconds']:7.3f} s", file=sys.stderr)
    out["vibrissa_version"] = __version__
    out["created_utc"] = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
    return out


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help=f"JSON file to write (default {DEFAULT_OUT})."
    )
    parser.add_argument(
        "--trials", type=int, default=40, help="Chapter-4 trials in the chunk (default 40)."
    )
    parser.add_argument("--top", type=int, default=12, help="Entries kept (default 12).")
    args = parser.parse_args(argv)
    if args.trials < 1 or args.top < 1:
        parser.error("--trials and --top must be at least 1")
    if args.out.is_dir():
        parser.error(f"--out {args.out} is a directory")
    result = run(args.trials, args.top)
    atomic_write_text(args.out, json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
