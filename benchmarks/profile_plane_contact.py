"""Newton iterations per step: a flat wall against the standard pole contact.

Usage::

    .venv/bin/python benchmarks/profile_plane_contact.py
        [--out benchmarks/results/plane_contact.json]

CrunchBot's runs spend nearly all their time in wall contacts (issue 16). This script
counts what a step costs there, against the physics benchmark's standard pole contact
(:mod:`vibrissa.whisker.benchmark`):

* ``pole``: the standard scenario's first 0.4 s (xy-robot whisker, 28 elements);
* ``wall``: the ``crunchbot`` whisker as the simulated robot builds it (16 elements), a flat
  face (friction 0.3) at ``angle`` deg to the whisker pushed 40 mm toward its base over
  0.25 s from 135 mm and held, for 0.5 s, with the follicle housing still or turning at
  0.3 rad/s (CrunchBot's TURN rate), and once more without friction.

Reports per case Newton iterations per step, steps, contact rows and CPU seconds of one
``simulate`` call (after one untimed call that loads the kernels), or where the solver
gave up. Counts do not depend on the machine's load; CPU seconds do.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

from vibrissa._atomic import atomic_write_text
from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.simulate import (
    BaseMotion,
    PoleContact,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import Surface

DT_S = 2.5e-4


def _count(run) -> dict:
    try:
        run()
    except SimulationError as exc:  # a finding, not a crash: say where it gave up
        return {"failed": str(exc)}
    t0 = time.process_time()
    res = run()
    cpu = time.process_time() - t0
    it = res.newton_iterations
    steps = len(it) - 1
    return {
        "newton_iterations_per_step": round(float(it.sum()) / steps, 2),
        "steps": steps,
        "contact_rows": int((res.contact_force_n > 0).sum()),
        "cpu_seconds": round(cpu, 4),
    }


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--out", default="benchmarks/results/plane_contact.json")
    args = ap.parse_args()
    cases: dict[str, dict] = {}
    xy = RodModel(preset(STANDARD["preset"]), n_elements=28)
    pole = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    cases["pole"] = _count(lambda: simulate(xy, pole, standard_trajectory(xy), 0.4, DT_S))
    crunch = RodModel(preset("crunchbot"), n_elements=16)
    flat = Surface(np.zeros((4, 4)), 1e-3, 0.3, "wall")
    t = np.linspace(0.0, 0.5, 1001)
    push = Trajectory(
        t, np.column_stack([np.zeros_like(t), 135.0 - 40.0 * np.minimum(t / 0.25, 1.0)])
    )
    turn = BaseMotion(t, 0.3 * t, np.full_like(t, 0.3))
    for angle in (30.0, 60.0):
        for label, motion, friction in (
            ("still", None, 0.3),
            ("turning", turn, 0.3),
            ("turning, no friction", turn, 0.0),
        ):
            wall = SurfaceContact(flat, angle_deg=angle, side=1, friction=friction)
            cases[f"wall {angle:.0f} deg, {label}"] = _count(
                lambda wall=wall, motion=motion: simulate(
                    crunch, wall, push, 0.5, DT_S, base_motion=motion
                )
            )
    # the pushes above start with the tip inside the inclined wall (4.5 mm at 60 deg):
    # an impulsive start; this one starts outside it, as a whisker meets a wall
    outside = Trajectory(
        t, np.column_stack([np.zeros_like(t), 150.0 - 40.0 * np.minimum(t / 0.25, 1.0)])
    )
    wall = SurfaceContact(flat, angle_deg=60.0, side=1, friction=0.3)
    cases["wall 60 deg, still, from outside"] = _count(
        lambda: simulate(crunch, wall, outside, 0.5, DT_S)
    )
    out = {
        "what": __doc__.split("\n\n")[0],
        "dt_s": DT_S,
        "load_average_at_start": round(os.getloadavg()[0], 2),
        "cases": cases,
    }
    atomic_write_text(Path(args.out), json.dumps(out, indent=2) + "\n")
    for name, c in cases.items():
        print(
            f"{name:32s} "
            + (
                f"failed: {c['failed']}"
                if "failed" in c
                else f"{c['newton_iterations_per_step']:5.2f} iterations/step "
                f"{c['cpu_seconds']:.3f} s CPU"
            )
        )


if __name__ == "__main__":
    main()
