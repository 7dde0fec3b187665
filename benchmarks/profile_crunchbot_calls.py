"""Where a CrunchBot run spends its physics time: every obstacle-whisker ``simulate`` call.

Usage::

    .venv/bin/python benchmarks/profile_crunchbot_calls.py [--seconds 60] [--seed 0]
        [--save-calls FILE.pkl] [--out benchmarks/results/crunchbot_calls.json]

Trains the classifiers on the quick set (their accuracy does not change the physics'
cost), runs the simulated robot in the ``slam`` arena for ``--seconds`` and records
each call the four obstacle whiskers make to :func:`vibrissa.whisker.simulate.simulate`:
its wall time, whether it failed (the robot then retries with half the step, and after
two halvings without the object), the contact kind, whether the follicle housing turned,
the simulated duration and the Newton iterations. Writes totals per (contact, housing)
group, the failures' cost and the twenty slowest calls as JSON (atomically) and prints
them. ``--save-calls`` also pickles every call's arguments, so a change to the solver
can be timed on exactly these calls (``replay`` below) without running the robot again.

Replay::

    .venv/bin/python benchmarks/profile_crunchbot_calls.py --replay FILE.pkl [--top 200]

times the ``--top`` slowest recorded plane-contact calls again on this checkout and
prints their wall time, Newton iterations and failures.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import time
from collections import defaultdict
from pathlib import Path

from vibrissa._atomic import atomic_write_text


def _record(seconds: float, seed: int) -> tuple[list[dict], list[tuple], float]:
    import vibrissa.robots.crunchbot.obstacle_whiskers as ow
    from vibrissa.robots.crunchbot import PRESETS
    from vibrissa.thesis.crunchbot_slam.protocol import default_robot

    rows: list[dict] = []
    args: list[tuple] = []
    original = ow.simulate

    def timed(model, contact, traj, duration, *a, **kw):
        t0 = time.perf_counter()
        row = {
            "contact": type(contact).__name__ if contact is not None else "none",
            "turning": kw.get("base_motion") is not None,
            "simulated_s": float(duration),
            "dt_s": kw.get("dt_s"),
            "failed": True,
            "newton_iterations": 0,
        }
        try:
            res = original(model, contact, traj, duration, *a, **kw)
            row["failed"] = False
            row["newton_iterations"] = int(res.newton_iterations.sum())
            return res
        finally:
            row["wall_s"] = time.perf_counter() - t0
            rows.append(row)
            args.append((model, contact, traj, duration, a, kw))

    run, train = default_robot()
    classifiers = train(seed, quick=True)
    rows.clear()
    args.clear()
    ow.simulate = timed
    try:
        t0 = time.perf_counter()
        run(PRESETS["slam"], seconds, seed, classifiers=classifiers)
        wall = time.perf_counter() - t0
    finally:
        ow.simulate = original
    return rows, args, wall


def _summary(rows: list[dict]) -> dict:
    groups: dict[str, dict] = defaultdict(
        lambda: {"calls": 0, "wall_s": 0.0, "simulated_s": 0.0, "newton_iterations": 0}
    )
    for r in rows:
        key = (
            "failed"
            if r["failed"]
            else f"{r['contact']}, " + ("housing turning" if r["turning"] else "housing still")
        )
        g = groups[key]
        g["calls"] += 1
        g["wall_s"] += r["wall_s"]
        g["simulated_s"] += 0.0 if r["failed"] else r["simulated_s"]
        g["newton_iterations"] += r["newton_iterations"]
    for g in groups.values():
        g["wall_s"] = round(g["wall_s"], 3)
        g["simulated_s"] = round(g["simulated_s"], 3)
        g["real_time_factor"] = (
            round(g["simulated_s"] / g["wall_s"], 2) if g["wall_s"] > 0 else None
        )
    return dict(sorted(groups.items(), key=lambda kv: -kv[1]["wall_s"]))


def _replay(path: Path, top: int) -> None:
    from vibrissa.whisker.rod import SimulationError
    from vibrissa.whisker.simulate import SurfaceContact, simulate

    with path.open("rb") as fh:
        saved = pickle.load(fh)
    calls = sorted(
        (c for c in saved if isinstance(c[1][1], SurfaceContact)), key=lambda c: -c[0]["wall_s"]
    )[:top]
    wall = 0.0
    iters = 0
    fails = 0
    for _, (model, contact, traj, duration, a, kw) in calls:
        t0 = time.perf_counter()
        try:
            iters += int(simulate(model, contact, traj, duration, *a, **kw).newton_iterations.sum())
        except SimulationError:
            fails += 1
        wall += time.perf_counter() - t0
    recorded = sum(c[0]["wall_s"] for c in calls)
    print(
        f"{len(calls)} plane-contact calls: {wall:.2f} s wall (recorded {recorded:.2f} s), "
        f"{iters} Newton iterations, {fails} failed"
    )


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--seconds", type=float, default=60.0, help="robot seconds")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--save-calls", type=Path, default=None)
    ap.add_argument("--replay", type=Path, default=None)
    ap.add_argument("--top", type=int, default=200)
    ap.add_argument("--out", type=Path, default=Path("benchmarks/results/crunchbot_calls.json"))
    args = ap.parse_args()
    if args.replay is not None:
        if not args.replay.is_file():
            ap.error(f"--replay: no such file: {args.replay}")
        _replay(args.replay, args.top)
        return
    if not args.seconds > 0:
        ap.error("--seconds must be positive")
    load = os.getloadavg()[0]
    rows, call_args, wall = _record(args.seconds, args.seed)
    if args.save_calls is not None:
        tmp = args.save_calls.with_name(args.save_calls.name + ".tmp")
        with tmp.open("wb") as fh:
            pickle.dump(list(zip(rows, call_args, strict=True)), fh)
        tmp.replace(args.save_calls)
    slowest = sorted(rows, key=lambda r: -r["wall_s"])[:20]
    out = {
        "what": __doc__.split("\n\n")[0],
        "robot_seconds": args.seconds,
        "seed": args.seed,
        "load_average_at_start": round(load, 2),
        "robot_wall_seconds": round(wall, 3),
        "simulate_wall_seconds": round(sum(r["wall_s"] for r in rows), 3),
        "failed_calls": sum(r["failed"] for r in rows),
        "groups": _summary(rows),
        "slowest_calls": [
            {k: (round(v, 4) if isinstance(v, float) else v) for k, v in r.items()} for r in slowest
        ],
    }
    atomic_write_text(args.out, json.dumps(out, indent=2) + "\n")
    print(
        f"robot {wall:.1f} s wall for {args.seconds:g} s; simulate calls "
        f"{out['simulate_wall_seconds']:.1f} s, {out['failed_calls']} failed"
    )
    for name, g in out["groups"].items():
        print(
            f"  {name:36s} {g['calls']:4d} calls {g['wall_s']:7.2f} s wall "
            f"{g['simulated_s']:7.2f} s simulated, {g['newton_iterations']} iterations"
        )


if __name__ == "__main__":
    main()
