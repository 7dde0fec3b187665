"""Time-step convergence of CrunchBot's obstacle whiskers on their own recorded calls.

Usage::

    .venv/bin/python benchmarks/profile_crunchbot_calls.py --seconds 360 --save-calls CALLS.pkl
    .venv/bin/python benchmarks/crunchbot_timestep.py CALLS.pkl [--top 60]
        [--out benchmarks/results/crunchbot_timestep.json]

Replays the ``--top`` slowest recorded calls of one kind (``--kind``: wall (plane)
contacts, the default; pole contacts; no object) of a CrunchBot run with each
internal step of :data:`STEPS_S` and compares each with the finest: the magnet's tilt
``tan_x`` at the Hall samples (RMS difference over the call, relative to the reference's
RMS), the share of samples in contact, the largest contact force and the wall time and
Newton iterations per step. A step is converged for these contacts when its tilt
differs from the finest by little and its contact share and peak force agree; the
robot's default (``ObstacleWhiskers.dt_s``) should be the largest such step.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import machine

from vibrissa._atomic import atomic_write_text

#: Internal steps tried (s), coarsest first; the last is the reference.
STEPS_S = (2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5, 1.5625e-5, 7.8125e-6)
DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "crunchbot_timestep.json"
SAMPLE_S = 5e-4  # the Hall sensors' 2 kHz


def main(argv: list[str] | None = None) -> int:
    """Replay, compare, write JSON."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("calls", type=Path, help="pickle of profile_crunchbot_calls.py --save-calls")
    ap.add_argument("--top", type=int, default=60)
    ap.add_argument(
        "--kind",
        choices=("wall", "pole", "none"),
        default="wall",
        help="which recorded calls: wall (plane) contacts, pole contacts, or no object",
    )
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT)
    args = ap.parse_args(argv)
    if not args.calls.exists():
        ap.error(f"calls: no such file: {args.calls}")
    if not args.calls.is_file():
        ap.error(f"calls: not a regular file (a directory, FIFO or device): {args.calls}")
    if args.top < 1:
        ap.error("--top: expected a positive integer")
    from vibrissa.whisker.rod import SimulationError
    from vibrissa.whisker.simulate import PoleContact, SurfaceContact, simulate

    kind = {"wall": SurfaceContact, "pole": PoleContact, "none": type(None)}[args.kind]

    try:
        with args.calls.open("rb") as fh:
            saved = pickle.load(fh)
        if not isinstance(saved, list) or not all(
            isinstance(c, tuple) and len(c) == 2 and len(c[1]) == 6 for c in saved
        ):
            raise ValueError("not a list of recorded calls")
    except (OSError, EOFError, ValueError, TypeError, pickle.UnpicklingError) as exc:
        ap.error(f"calls: not a pickle of profile_crunchbot_calls.py --save-calls ({exc})")
    calls = sorted(
        (c for c in saved if isinstance(c[1][1], kind) and not c[0]["failed"]),
        key=lambda c: -c[0]["wall_s"],
    )[: args.top]
    print(f"{len(calls)} {args.kind} calls x {len(STEPS_S)} steps", file=sys.stderr)
    per_dt: dict[float, dict[str, list[float]]] = {
        dt: {"wall_s": [], "iters": [], "steps": [], "rel_rms": [], "contact": [], "fmax": []}
        for dt in STEPS_S
    }
    failed = {dt: 0 for dt in STEPS_S}
    for _, (model, contact, traj, duration, a, kw) in calls:
        tans: dict[float, np.ndarray] = {}
        for dt in STEPS_S:
            k = dict(kw)
            k["dt_s"] = dt
            t0 = time.perf_counter()
            try:
                res = simulate(model, contact, traj, duration, *a, **k)
            except SimulationError:
                failed[dt] += 1
                continue
            wall = time.perf_counter() - t0
            step = int(round(SAMPLE_S / dt))
            tans[dt] = res.tan_xy[::step, 0]
            f = res.contact_force_n
            d = per_dt[dt]
            d["wall_s"].append(wall)
            d["iters"].append(float(res.newton_iterations.sum()))
            d["steps"].append(float(f.size - 1))
            d["contact"].append(float((f[::step] > 0).mean()))
            d["fmax"].append(float(f.max()))
        ref = tans.get(STEPS_S[-1])
        for dt, tan in tans.items():
            if ref is not None:
                n = min(tan.size, ref.size)
                scale = float(np.sqrt(np.mean(ref[:n] ** 2))) or 1.0
                per_dt[dt]["rel_rms"].append(
                    float(np.sqrt(np.mean((tan[:n] - ref[:n]) ** 2))) / scale
                )
    rows = []
    for dt in STEPS_S:
        d = per_dt[dt]
        err = d["rel_rms"]
        rows.append(
            {
                "dt_us": dt * 1e6,
                "calls": len(d["wall_s"]),
                "failed": failed[dt],
                "wall_s": round(float(np.sum(d["wall_s"])), 3),
                "newton_per_step": round(float(np.sum(d["iters"]) / max(np.sum(d["steps"]), 1)), 2),
                "tan_rel_rms_median": round(float(np.median(err)), 4) if err else None,
                "tan_rel_rms_p90": round(float(np.percentile(err, 90)), 4) if err else None,
                "contact_share_mean": round(float(np.mean(d["contact"])), 3),
                "peak_force_n_median": round(float(np.median(d["fmax"])), 4),
            }
        )
        print(json.dumps(rows[-1]), file=sys.stderr)
    out = {
        "what": __doc__.splitlines()[0],
        "kind": args.kind,
        "calls": len(calls),
        "simulated_s": round(float(sum(c[1][3] for c in calls)), 3),
        "reference_dt_us": STEPS_S[-1] * 1e6,
        "rows": rows,
        "machine": machine(),
        "meta": {
            "command": " ".join(["python benchmarks/crunchbot_timestep.py", *sys.argv[1:]]),
            "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        },
    }
    atomic_write_text(args.out, json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
