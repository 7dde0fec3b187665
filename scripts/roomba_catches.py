"""Why do the Roomba's templates transfer one way and not the other? (thesis 6.2, issue 31).

Simulates the clockwise and anticlockwise trials of the floor-texture session (all four
floors, the thesis' 4 trials of 16 s per floor and direction) for each set-up variant
below and measures, per direction and floor:

- the tip's catches: stuck on the sliding floor for at least ``CATCH_MIN_S`` (count per
  trial and fraction of the recording), the median contact force, the trials whose
  sensor reached a rail and the fraction of samples at a rail;
- how loud the kept windows are (RMS about each window's mean per channel, the norm of
  the DC-less magnitude spectrum that the templates' squared error weighs) and their
  spectral centroid;
- the spectral-template results: mean correct per direction and both cross-condition
  scores, with the cross-condition score per floor and where its windows went.

Before any simulation it measures the floors as the tip meets them (``flanks``): the
relief under a sphere of the whisker's tip radius (the envelope a resting tip's lowest
point follows) and the share of it steeper, along the whisker, than the quasi-static
catch limit ``90 deg - tilt - atan(mu)`` of a leading tip (module doc of
:mod:`vibrissa.robots.roomba`).

Variants (``--variants``, comma-separated; the Roomba's parameters,
:class:`vibrissa.robots.roomba.Roomba`):

- ``today``: the set-up of the committed experiment (whisker pointing backward at 30 deg
  to the floor: anticlockwise it trails, clockwise its tip leads; wheels at 100 mm/s);
- ``spin-300``: the same, wheels at 300 mm/s (the thesis gives no speed; the Roomba's
  Open Interface allows up to 500 mm/s): is the catching a matter of speed?
- ``tilt-15``: the same, 15 deg to the floor (the CrunchBot lesson of 6.5.6.1: "angle
  as far back as possible");
- ``yaw-90``: the whisker pointing outward from the rim, so both directions slide the
  floor across it (mirror images);
- ``preload-5``: the whisker pressed 5 mm into the floor instead of 15 mm.

Writes a JSON file (default ``docs/runs/roomba_catches.json``) that names its command and
commit. Usage (from the repository root; ~3-6 min per variant on 2 cores)::

    .venv/bin/python scripts/roomba_catches.py [--variants today,tilt-15] [--seed 0]
        [--trials 4] [--duration 16] [--workers 2] [--out docs/runs/roomba_catches.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import shlex
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy.ndimage import grey_dilation

from vibrissa.evaluate.report_common import write_json
from vibrissa.experiments.generate import generate
from vibrissa.reproduce.provenance import git_commit
from vibrissa.robots.roomba import CATCH_MIN_S, Roomba
from vibrissa.thesis.floor_texture.evaluation import run_floor_texture
from vibrissa.thesis.floor_texture.protocol import floor_protocol
from vibrissa.whisker.floors import FLOORS, make_floor
from vibrissa.whisker.geometry import preset

#: Set-up variants: Roomba parameters replaced.
VARIANTS: dict[str, dict[str, Any]] = {
    "today": {},
    "spin-300": {"spin_wheel_speed_mm_s": 300.0},
    "tilt-15": {"tilt_deg": 15.0},
    "yaw-90": {"mount_yaw_deg": 90.0},
    "preload-5": {"preload_mm": 5.0},
}


def flanks(tilt_deg: float, seed: int) -> dict[str, Any]:
    """Slopes of each floor's relief under the tip, against the leading tip's catch limit."""
    radius = preset("scratchbot").tip_radius_mm
    out: dict[str, Any] = {"tip_radius_mm": radius, "tilt_deg": tilt_deg, "floors": {}}
    for name, spec in FLOORS.items():
        sheet = make_floor(name, seed, 40.0, 40.0)
        h_mm, dx = sheet.heights_m * 1e3, sheet.spacing_m * 1e3
        k = int(radius / dx)
        r = np.arange(-k, k + 1) * dx
        q = radius**2 - r[:, None] ** 2 - r[None, :] ** 2
        ball = np.where(q >= 0, np.sqrt(np.maximum(q, 0.0)) - radius, -np.inf)
        envelope = grey_dilation(h_mm, structure=ball, mode="wrap")
        along = np.degrees(np.arctan(np.abs(np.gradient(envelope, dx, axis=0))))
        limit = 90.0 - tilt_deg - math.degrees(math.atan(spec.friction))
        out["floors"][name] = {
            "friction": spec.friction,
            "catch_limit_deg": limit,
            "slope_p50_deg": float(np.percentile(along, 50)),
            "slope_p90_deg": float(np.percentile(along, 90)),
            "slope_max_deg": float(along.max()),
            "share_steeper_than_limit": float(np.mean(along > limit)),
        }
    return out


def measure(name: str, seed: int, trials: int, duration_s: float, workers: int) -> dict[str, Any]:
    """Simulate one variant's clockwise and anticlockwise trials and measure them."""
    roomba = dataclasses.replace(Roomba(), **VARIANTS[name])
    proto = floor_protocol(
        seed=seed,
        conditions=("clockwise", "anticlockwise"),
        trials_per_condition=trials,
        duration_s=duration_s,
        roomba=roomba,
    )
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        ds = generate(proto, Path(d) / "roomba.nc", workers=workers, chunk_size=2)
        ds = ds.load()
    seconds = time.perf_counter() - t0
    res = run_floor_texture(ds)
    floors = res["meta"]["floors"]
    cross = res["cross_condition"]
    out: dict[str, Any] = {
        "roomba": roomba.to_dict(),
        "simulation_seconds": round(seconds, 1),
        "mean_correct": res["mean_correct"],
        "per_floor_correct": res["per_floor_correct"],
        "cross_condition": {k: cross.get(k) for k in ("cw_on_ccw", "ccw_on_cw")},
        "cross_per_floor": {k: cross.get(f"{k}_per_floor") for k in ("cw_on_ccw", "ccw_on_cw")},
        "cross_confusion": {k: cross.get(f"{k}_confusion") for k in ("cw_on_ccw", "ccw_on_cw")},
        "saturated_trials": res["saturated_trials"],
        "windows": res["windows"],
        "levels": res["levels"],
    }
    # the loudness ratio clockwise / anticlockwise per floor (spectrum norm, RMS x and y)
    lv = res["levels"]
    ratio = {}
    for f in floors:
        cw, ccw = lv["clockwise"][f], lv["anticlockwise"][f]
        if cw["spectrum_norm"] and ccw["spectrum_norm"]:
            ratio[f] = {
                "spectrum_norm": cw["spectrum_norm"] / ccw["spectrum_norm"],
                "rms_x": cw["rms_v"][0] / ccw["rms_v"][0],
                "rms_y": cw["rms_v"][1] / ccw["rms_v"][1],
            }
    out["clockwise_over_anticlockwise"] = ratio
    return out


def _table(name: str, m: dict[str, Any]) -> str:
    lines = [f"== {name} ({m['simulation_seconds']} s)"]
    mc, cr = m["mean_correct"], m["cross_condition"]
    lines.append(
        f"mean correct cw {mc['clockwise']:.2f} ccw {mc['anticlockwise']:.2f}; "
        f"cross cw->ccw {cr['cw_on_ccw']:.2f} ccw->cw {cr['ccw_on_cw']:.2f}"
    )
    lines.append(
        "cond          floor          catches/trial catch%  rail%  F_n     rms_x  rms_y  "
        "|spec|  centroid  cross-correct"
    )
    key = {"clockwise": "ccw_on_cw", "anticlockwise": "cw_on_ccw"}
    for c, per in m["levels"].items():
        for f, e in per.items():
            cc = (m["cross_per_floor"].get(key[c]) or {}).get(f)
            lines.append(
                f"{c:13s} {f:14s} {e.get('catches', 0):6.2f}     "
                f"{100 * e.get('catch_fraction', 0):5.1f}  {100 * e.get('rail_fraction', 0):5.1f}  "
                f"{e.get('contact_force_n', 0):.3f}  {e['rms_v'][0]:.3f}  {e['rms_v'][1]:.3f}  "
                f"{e['spectrum_norm']:6.2f}  {e['centroid_hz'][0]:4.0f}/{e['centroid_hz'][1]:4.0f}"
                f"  {'' if cc is None else f'{cc:.2f}'}"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run the variants asked for and write the JSON file."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--trials", type=int, default=4)
    ap.add_argument("--duration", type=float, default=16.0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default="docs/runs/roomba_catches.json")
    args = ap.parse_args(argv)
    names = [v.strip() for v in args.variants.split(",") if v.strip()]
    unknown = [v for v in names if v not in VARIANTS]
    if unknown:
        ap.error(f"--variants: unknown {unknown[0]!r}; choose from {', '.join(VARIANTS)}")
    result: dict[str, Any] = {
        "meta": {
            "command": shlex.join(["python", "scripts/roomba_catches.py", *sys.argv[1:]]),
            "commit": git_commit(),
            "seed": args.seed,
            "trials_per_direction_and_floor": args.trials,
            "duration_s": args.duration,
            "catch_min_s": CATCH_MIN_S,
            "what": "clockwise and anticlockwise Roomba trials per set-up variant: the "
            "tip's catches, signal levels and the spectral templates' cross-condition "
            "scores (scripts/roomba_catches.py)",
        },
        "flanks": {
            f"tilt-{t:g}": flanks(t, args.seed)
            for t in sorted(
                {float(Roomba().tilt_deg), *(VARIANTS[n].get("tilt_deg", 30.0) for n in names)}
            )
        },
        "variants": {},
    }
    for key, fl in result["flanks"].items():
        for f, e in fl["floors"].items():
            print(
                f"{key} {f:14s} limit {e['catch_limit_deg']:4.0f} deg: slope p50 "
                f"{e['slope_p50_deg']:3.0f} p90 {e['slope_p90_deg']:3.0f} max "
                f"{e['slope_max_deg']:3.0f}; steeper {100 * e['share_steeper_than_limit']:4.1f} %",
                flush=True,
            )
    for name in names:
        m = measure(name, args.seed, args.trials, args.duration, args.workers)
        result["variants"][name] = m
        print(_table(name, m), flush=True)
        write_json(result, Path(args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
