"""The rod's mass in the nonlinear dynamics: energy at release, and speed (issue 32, item 1).

Usage::

    .venv/bin/python benchmarks/rod_mass_dynamics.py [--out FILE] [--repeats N]

Two measurements on the full nonlinear rod (``simulate``), for the lumped and the
consistent mass (``RodModel(mass=...)``):

- **release**: the xy-robot whisker (28 elements, its configured damping) deflected
  statically by a tip force to 30 mm and released, 20 ms at each time step of
  :data:`STEPS_S`. The energy (elastic plus kinetic, each with the model's own mass
  matrix) after the first step and its largest value, relative to the initial. The
  consistent mass runs twice: as ``simulate`` starts it (the forces over the mass
  matrix's row sums) and with the exact ``M^-1 F`` start, put in for this measurement
  only. ``tests/whisker/test_simulate.py::test_free_vibration_is_passive`` allows 0.1 %.
- **speed**: the standard 1.5 s pole contact of ``vibrissa bench physics`` (without the
  Hall chain) at :data:`ELEMENTS`, best of ``--repeats`` timed runs on one core, with the
  Newton iterations it took.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import importlib
import json
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import machine

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.whisker import RodModel, preset
from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
from vibrissa.whisker.simulate import PoleContact, free_vibration, simulate

# the module itself (``vibrissa.whisker.simulate`` the attribute is the function)
simulate_module = importlib.import_module("vibrissa.whisker.simulate")

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "rod_mass_dynamics.json"
#: Time steps (s) of the release.
STEPS_S = (2.5e-4, 1.25e-4, 6.25e-5)
#: Element counts of the speed measurement.
ELEMENTS = (8, 12, 28)
TIP_DEFLECTION_MM = 30.0
RELEASE_S = 0.02


@contextlib.contextmanager
def exact_start() -> Iterator[None]:
    """Within the block ``simulate`` starts from ``M^-1 F`` over the moving nodes."""
    original = simulate_module._initial_acceleration

    def start(rod, damping, x, v, theta=0.0, theta_dot=0.0):  # type: ignore[no-untyped-def]
        a = original(rod, damping, x, v, theta, theta_dot)
        row_sums = rod.mass.copy()
        row_sums[:-1] += rod.mass_off
        row_sums[1:] += rod.mass_off
        forces = a * row_sums[:, None]  # the forces back (zero on the fixed nodes)
        free = np.flatnonzero(rod.free)
        ab = np.zeros((2, free.size))
        ab[0, 1:] = rod.mass_off[free[:-1]]
        ab[1] = rod.mass[free]
        out = np.zeros_like(a)
        out[free] = scipy.linalg.solveh_banded(ab, forces[free])
        return out

    simulate_module._initial_acceleration = start
    try:
        yield
    finally:
        simulate_module._initial_acceleration = original


def release(mass: str, start: str, dt_s: float) -> dict[str, float]:
    """Energy (%, relative to the start) after the first step and at its largest."""
    model = RodModel(preset("xy-robot"), mass=mass)
    ctx = exact_start() if start == "exact" else contextlib.nullcontext()
    with ctx:
        res = free_vibration(
            model,
            tip_deflection_mm=TIP_DEFLECTION_MM,
            duration_s=RELEASE_S,
            dt_s=dt_s,
            record_every=1,
        )
    assert res.states_m is not None and res.velocities_m_s is not None
    e = np.array(
        [
            model.elastic_energy(x) + model.kinetic_energy(v)
            for x, v in zip(res.states_m, res.velocities_m_s, strict=True)
        ]
    )
    rel = 100.0 * (e / e[0] - 1.0)
    return {"first_step_pct": float(rel[1]), "max_pct": float(rel.max())}


def speed(mass: str, n_elements: int, repeats: int) -> dict[str, Any]:
    """Real-time factor (best of ``repeats``) and Newton iterations of the standard contact."""
    model = RodModel(preset(STANDARD["preset"]), n_elements, mass=mass)
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    T = STANDARD["duration_s"]
    traj = standard_trajectory(model, T)
    res = simulate(model, contact, traj, T, STANDARD["dt_s"])  # compile and warm up
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = simulate(model, contact, traj, T, STANDARD["dt_s"])
        best = min(best, time.perf_counter() - t0)
    return {
        "mass": mass,
        "n_elements": n_elements,
        "real_time_factor": float(T / best),
        "newton_iterations": int(res.newton_iterations.sum()),
        "peak_follicle_moment_nm": float(np.max(np.abs(res.follicle_moment_nm[:, 0]))),
    }


def run(repeats: int) -> dict[str, Any]:
    """Both measurements."""
    releases = []
    for mass, start in (
        ("lumped", "row sums"),
        ("consistent", "row sums"),
        ("consistent", "exact"),
    ):
        for dt in STEPS_S:
            releases.append({"mass": mass, "start": start, "dt_s": dt, **release(mass, start, dt)})
    speeds = [speed(m, n, repeats) for n in ELEMENTS for m in ("lumped", "consistent")]
    return {"release": releases, "speed": speeds}


def main(argv: list[str] | None = None) -> int:
    """Measure, print and write the JSON."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file to write")
    ap.add_argument("--repeats", type=int, default=9, help="timed runs per speed row (best counts)")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats: expected a positive integer")
    if args.out.exists() and not args.out.is_file():
        ap.error(f"--out: {args.out} is not a regular file")
    print(
        f"rod_mass_dynamics: {3 * len(STEPS_S)} releases, {2 * len(ELEMENTS)} speed rows "
        f"x {args.repeats + 1} runs",
        file=sys.stderr,
    )
    with contextlib.suppress(AttributeError, OSError):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    result = run(args.repeats)
    for r in result["release"]:
        print(
            f"release {r['mass']:<10} start {r['start']:<8} dt {r['dt_s'] * 1e6:6.1f} us: "
            f"first step {r['first_step_pct']:+.4f} %, largest {r['max_pct']:+.4f} %"
        )
    for r in result["speed"]:
        print(
            f"standard contact {r['mass']:<10} {r['n_elements']:3d} elements: "
            f"RTF {r['real_time_factor']:6.1f}, Newton {r['newton_iterations']}"
        )
    result["meta"] = {
        "command": "python benchmarks/rod_mass_dynamics.py",
        "repeats": args.repeats,
        "machine": machine(),
        "vibrissa_version": __version__,
        "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    atomic_write_text(args.out, json.dumps(result, indent=1) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
