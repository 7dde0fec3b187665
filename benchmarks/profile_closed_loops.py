"""Where the whisking robots' closed loops spend their time (issue 32, item 3: the profile).

Usage::

    .venv/bin/python benchmarks/profile_closed_loops.py [--out FILE] [--only NAME,...]
        [--crunchbot-seconds S]

Profiles (``cProfile``, one process, one core) the quick reproductions of SCRATCHbot,
BIOTACT G1 and the Roomba's floor texture (and, with ``--only crunchbot``, a CrunchBot run
of ``--crunchbot-seconds`` robot seconds: its obstacle whiskers simulate in worker threads,
which cProfile does not see, so that profile shows the main thread only; for its physics
use ``benchmarks/profile_crunchbot_calls.py``), and splits each one's time into

- ``solver``: the compiled rod kernels (``vibrissa.whisker._kernels``: the Newton steps,
  the modal free flight, the contact search) -- the physics' own cost;
- ``linearisation``: building models' dense tangent stiffness and eigenproblems
  (``RodModel`` frequencies, damping, linear modes, Hall calibration);
- ``step_setup``: :func:`vibrissa.whisker.simulate.simulate` itself outside the kernels
  (checking and preparing every call the loops make, one per control step);
- ``provenance``: fingerprinting the code for the results' ``meta``;
- ``other``: everything else (controllers, the robots' Python loops, classifiers,
  reports, imports).

It writes the split and the 25 functions with the most time of their own, per loop, as
JSON (default ``benchmarks/results/closed_loops_profile.json``).
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as _dt
import json
import os
import pstats
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "closed_loops_profile.json"
LOOPS = ("scratchbot", "biotact-g1", "floor-texture", "crunchbot")


def _category(filename: str, function: str) -> str:
    if filename.endswith(os.path.join("whisker", "_kernels.py")):
        return "solver"
    if function in ("_dense_stiffness", "_plane_modes", "linear_modes") or "eig" in function:
        return "linearisation"  # eigenproblems, numpy's and LAPACK's own entries included
    if filename.endswith(os.path.join("whisker", "simulate.py")):
        return "step_setup"
    if "provenance" in filename or filename.endswith("ast.py"):
        return "provenance"
    return "other"


def split(stats: pstats.Stats) -> tuple[dict[str, float], list[dict[str, Any]]]:
    """Own time per category, and the functions with most own time."""
    raw: dict[Any, Any] = stats.stats  # type: ignore[attr-defined]
    cats: dict[str, float] = {}
    rows = []
    for (filename, line, function), (_cc, calls, tottime, cumtime, _callers) in raw.items():
        cat = _category(filename, function)
        cats[cat] = cats.get(cat, 0.0) + tottime
        rows.append(
            {
                "function": f"{Path(filename).name}:{line}({function})",
                "calls": calls,
                "own_seconds": round(tottime, 3),
                "cumulative_seconds": round(cumtime, 3),
                "category": cat,
            }
        )
    rows.sort(key=lambda r: -r["own_seconds"])
    return {k: round(v, 4) for k, v in sorted(cats.items())}, rows[:25]


def _reproduction(name: str) -> Callable[[], Any]:
    def run() -> Any:
        from vibrissa.reproduce import run_experiment

        with tempfile.TemporaryDirectory() as tmp:
            return run_experiment(name, Path(tmp) / "o", quick=True, workers=1, figures=False)

    return run


def _crunchbot(seconds: float) -> Callable[[], Any]:
    """The robot alone (no SLAM), with classifiers trained on the quick set beforehand."""
    from vibrissa.robots.crunchbot.arena import PRESETS
    from vibrissa.thesis.crunchbot_slam.protocol import default_robot

    run_robot, train = default_robot()
    classifiers = train(0, quick=True) if train is not None else None

    def run() -> Any:
        return run_robot(PRESETS["slam"], seconds, 0, classifiers=classifiers)

    return run


def profile(run: Callable[[], Any]) -> dict[str, Any]:
    """Run once under cProfile; the wall time and the split."""
    prof = cProfile.Profile()
    t0 = time.perf_counter()
    prof.enable()
    run()
    prof.disable()
    wall = time.perf_counter() - t0
    cats, top = split(pstats.Stats(prof))
    return {"wall_seconds": round(wall, 2), "own_seconds_by_category": cats, "top": top}


def main(argv: list[str] | None = None) -> int:
    """Profile each loop; print the split; write the JSON."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    ap.add_argument("--only", default="", help=f"comma list of {', '.join(LOOPS)}")
    ap.add_argument("--crunchbot-seconds", type=float, default=60.0)
    args = ap.parse_args(argv)
    names = [n for n in args.only.split(",") if n] or [n for n in LOOPS if n != "crunchbot"]
    if set(names) - set(LOOPS) or not 0 < args.crunchbot_seconds <= 3600:
        ap.error(f"--only: choose from {', '.join(LOOPS)}; 0 < --crunchbot-seconds <= 3600")
    loops: dict[str, Callable[[], Callable[[], Any]]] = {
        "scratchbot": lambda: _reproduction("scratchbot"),
        "biotact-g1": lambda: _reproduction("biotact-g1"),
        "floor-texture": lambda: _reproduction("floor-texture"),
        "crunchbot": lambda: _crunchbot(args.crunchbot_seconds),
    }
    out: dict[str, Any] = {}
    for name in names:
        print(f"profiling {name} ...", file=sys.stderr, flush=True)
        out[name] = profile(loops[name]())
        print(f"  {name}: {json.dumps(out[name]['own_seconds_by_category'])}", file=sys.stderr)
    result = {
        "loops": out,
        "crunchbot_seconds": args.crunchbot_seconds,
        "load_average_at_end": round(os.getloadavg()[0], 2),
        "machine": machine(),
        "meta": {
            "command": " ".join(["python benchmarks/profile_closed_loops.py", *sys.argv[1:]]),
            "vibrissa_version": __version__,
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        },
    }
    atomic_write_text(args.out, json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
