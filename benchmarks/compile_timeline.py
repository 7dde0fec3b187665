"""Where a cold start's time goes: every numba compilation of a quick reproduction.

Usage::

    .venv/bin/python benchmarks/compile_timeline.py [--experiment radial-distance]
        [--out benchmarks/results/compile_timeline.json]

The README's first command runs in a fresh clone, so numba compiles every kernel the
reproduction touches before it can cache them; that time is spent outside the
reproduction's stage clocks (``meta.wall_seconds``). This runs
``vibrissa reproduce EXPERIMENT --quick --workers 1`` twice in child processes sharing
one new, empty numba cache directory: the first run compiles (cold), the second loads
the cache (warm). A listener on numba's ``numba:compile`` events records, in the cold
run, when each function's compilation started (seconds since the process started), how
long it took (including the functions compiled inside it, which are listed too, with
their nesting depth), and the total time with a compilation under way. One worker, so
that one process compiles everything in sequence (with more, each worker compiles the
kernels it needs itself).

Writes JSON atomically (default ``benchmarks/results/compile_timeline.json``) and prints
the cold and warm wall times and the slowest top-level compilations.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "compile_timeline.json"

#: The child: listen to numba's compile events, run the quick reproduction, dump them.
CHILD = r"""
import json, sys, time
T0 = time.perf_counter()
from numba.core import event
events = []
depth = [0]
class _Listener(event.Listener):
    def on_start(self, ev):
        d = ev.data["dispatcher"]
        events.append(["start", time.perf_counter() - T0, depth[0],
                       f"{d.py_func.__module__}.{d.py_func.__qualname__}"])
        depth[0] += 1
    def on_end(self, ev):
        depth[0] -= 1
        d = ev.data["dispatcher"]
        events.append(["end", time.perf_counter() - T0, depth[0],
                       f"{d.py_func.__module__}.{d.py_func.__qualname__}"])
event.register("numba:compile", _Listener())
from vibrissa.cli import app
experiment, out, dump = sys.argv[1], sys.argv[2], sys.argv[3]
try:
    app(["reproduce", experiment, "--quick", "--workers", "1", "--out", out],
        standalone_mode=False)
finally:
    with open(dump, "w") as fh:
        json.dump({"wall_seconds": time.perf_counter() - T0, "events": events}, fh)
"""


def compilations(events: list[list[Any]]) -> list[dict[str, Any]]:
    """Pair start and end events into compilations ``{function, start_s, seconds, depth}``.

    ``events`` are ``[kind, time_s, depth, function]`` in the order numba emitted them
    (a compilation inside another one starts and ends between its parent's events).
    Returned in the order they started.
    """
    open_: list[tuple[int, dict[str, Any]]] = []
    out: list[dict[str, Any]] = []
    for kind, t, depth, fn in events:
        if kind == "start":
            row = {"function": fn, "start_s": t, "seconds": 0.0, "depth": depth}
            open_.append((len(out), row))
            out.append(row)
        else:
            if not open_:
                raise ValueError(f"compile event for {fn} ends without its start")
            if open_[-1][1]["function"] != fn:
                raise ValueError(
                    f"compile event for {fn} ends inside that of {open_[-1][1]['function']}"
                )
            _, row = open_.pop()
            row["seconds"] = t - row["start_s"]
    if open_:
        raise ValueError(f"compile of {open_[-1][1]['function']} never ended")
    return out


def compile_seconds(rows: list[dict[str, Any]]) -> float:
    """Total time with a compilation under way (the top-level ones' durations)."""
    return sum(r["seconds"] for r in rows if r["depth"] == 0)


def _run(experiment: str, cache: Path, work: Path, tag: str) -> dict[str, Any]:
    dump = work / f"{tag}.json"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    t0 = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-c", CHILD, experiment, str(work / f"out-{tag}"), str(dump)],
        env=env,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - t0
    if proc.returncode != 0 or not dump.is_file():
        raise RuntimeError(f"the {tag} run failed: {proc.stderr.strip()[-400:]}")
    data = json.loads(dump.read_text())
    data["process_wall_seconds"] = wall
    return data


def main(argv: list[str] | None = None) -> int:
    """Parse the options, run cold and warm, write the JSON."""
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--experiment", default="radial-distance", help="what to reproduce")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file to write")
    args = ap.parse_args(argv)
    from vibrissa.reproduce import experiments

    names = list(experiments())
    if args.experiment not in names:
        ap.error(f"--experiment: unknown {args.experiment!r}; choose one of {', '.join(names)}")
    if args.out.exists() and not args.out.is_file():
        ap.error(f"--out: {args.out} is not a regular file (a directory, FIFO or device)")
    if not args.out.parent.is_dir():
        ap.error(f"--out: no such directory: {args.out.parent}")
    print(
        f"compile_timeline: {args.experiment} --quick twice (cold, then warm numba cache)"
        f" -> {args.out}",
        file=sys.stderr,
    )
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="vibrissa-compile-") as tmp:
        work = Path(tmp)
        cache = work / "numba-cache"
        cold = _run(args.experiment, cache, work, "cold")
        warm = _run(args.experiment, cache, work, "warm")
    rows = compilations(cold["events"])
    top = sorted((r for r in rows if r["depth"] == 0), key=lambda r: -r["seconds"])
    result = {
        "what": __doc__.split("\n\n")[0],
        "experiment": args.experiment,
        "command": f"vibrissa reproduce {args.experiment} --quick --workers 1",
        "machine": machine(),
        "load_average_at_start": round(load, 2),
        "cold_wall_seconds": round(cold["process_wall_seconds"], 1),
        "warm_wall_seconds": round(warm["process_wall_seconds"], 1),
        "compile_seconds": round(compile_seconds(rows), 1),
        "warm_compile_seconds": round(float(compile_seconds(compilations(warm["events"]))), 1),
        "top_level": [
            {
                "function": r["function"],
                "start_s": round(r["start_s"], 1),
                "seconds": round(r["seconds"], 2),
            }
            for r in top
        ],
        "all": [
            {k: (round(v, 2) if isinstance(v, float) else v) for k, v in r.items()} for r in rows
        ],
        "meta": {
            "command": "python benchmarks/compile_timeline.py"
            + ("" if args.experiment == "radial-distance" else f" --experiment {args.experiment}"),
            "vibrissa_version": __version__,
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        },
    }
    atomic_write_text(args.out, json.dumps(result, indent=2) + "\n")
    print(
        f"cold {result['cold_wall_seconds']:.1f} s (compiling {result['compile_seconds']:.1f} s),"
        f" warm {result['warm_wall_seconds']:.1f} s",
        file=sys.stderr,
    )
    for r in top[:8]:
        print(f"  {r['seconds']:6.1f} s  {r['function']}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
