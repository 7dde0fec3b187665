"""Energy of a released rod under generalised-alpha with a consistent mass (issue 32, item 1).

Usage::

    .venv/bin/python benchmarks/consistent_mass_energy.py [--out FILE]

The consistent (tridiagonal) mass reaches a first mode within 0.1 % of the beam
reference at 8 elements (``benchmarks/rod_convergence.py``), but a trial of it in the
dynamics kernels gained 0.40 % energy after release from a static deflection, where
``tests/whisker/test_simulate.py::test_free_vibration_is_passive`` allows 0.1 %. This
script separates the integrator from the bookkeeping on the linearisation about rest
(one bending plane, :func:`rod_convergence.plane_matrices`): the rod is deflected
statically by a tip force to 30 mm, released, and advanced by the kernels' scheme
(generalised-alpha, ``rho_inf`` 0.5, the default step) with the consistent mass ``M``,
for three ways of starting and measuring:

- ``consistent``: initial acceleration ``M^-1 (-K x0)``, energy ``v.M v/2 + x.K x/2``;
- ``lumped start``: initial acceleration from the lumped masses (``F / mass``, as
  ``simulate`` computed it before the consistent mass), energy as above;
- ``lumped energy``: consistent start, kinetic energy measured with the lumped masses
  (as ``RodModel.kinetic_energy`` did before the consistent mass).

This is the linear, undamped rod. On the nonlinear rod with its damping the exact
consistent start does overshoot (``benchmarks/rod_mass_dynamics.py``), which is why
``simulate`` starts from the forces over the mass matrix's row sums.

Each row gives the energy after the first step and the largest over 400 steps, relative
to the initial (potential) energy.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from rod_convergence import plane_matrices

from vibrissa._atomic import atomic_write_text
from vibrissa.whisker.geometry import WhiskerGeometry
from vibrissa.whisker.simulate import DEFAULT_DT_S

RHO_INF = 0.5
TIP_DEFLECTION_M = 30e-3
STEPS = 400


def released(n_elements: int, start: str, measure: str) -> dict[str, Any]:
    """Energy history (relative) of the released rod with the consistent mass."""
    g = WhiskerGeometry(name="xy-robot")
    K, M, _ = plane_matrices(g, n_elements, "consistent", "node", "uniform")
    _, ML, _ = plane_matrices(g, n_elements, "lumped", "node", "uniform")
    am = (2 * RHO_INF - 1) / (RHO_INF + 1)
    af = RHO_INF / (RHO_INF + 1)
    gam = 0.5 - am + af
    beta = 0.25 * (1 - am + af) ** 2
    h = DEFAULT_DT_S
    f = np.zeros(len(K))
    f[-1] = 1.0
    x = np.linalg.solve(K, f)
    x *= TIP_DEFLECTION_M / x[-1]
    v = np.zeros_like(x)
    a = np.linalg.solve(M if start == "consistent" else ML, -K @ x)
    Mk = M if measure == "consistent" else ML
    e0 = 0.5 * x @ K @ x
    A = (1 - am) / (beta * h * h) * M + (1 - af) * K
    rel = []
    for _ in range(STEPS):
        xb = x + h * v + h * h * (0.5 - beta) * a
        vb = v + h * (1 - gam) * a
        # M ((1 - am) a1 + am a) + K ((1 - af) x1 + af x) = 0, a1 = (x1 - xb) / (beta h^2)
        rhs = M @ ((1 - am) / (beta * h * h) * xb - am * a) - af * (K @ x)
        x1 = np.linalg.solve(A, rhs)
        a = (x1 - xb) / (beta * h * h)
        v = vb + gam * h * a
        x = x1
        rel.append((0.5 * v @ Mk @ v + 0.5 * x @ K @ x) / e0 - 1.0)
    return {
        "n_elements": n_elements,
        "first_step_pct": 100 * rel[0],
        "max_pct": 100 * max(rel),
        "last_pct": 100 * rel[-1],
    }


CASES = {
    "consistent": ("consistent", "consistent"),
    "lumped start": ("lumped", "consistent"),
    "lumped energy": ("consistent", "lumped"),
}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="also write the rows as JSON")
    args = ap.parse_args(argv)
    rows = []
    for case, (start, measure) in CASES.items():
        for ne in (8, 12, 28):
            rows.append({"case": case, **released(ne, start, measure)})
            r = rows[-1]
            print(
                f"{case:14s} {ne:3d} elements: first step {r['first_step_pct']:+.3f} %, "
                f"max {r['max_pct']:+.3f} %, after {STEPS} steps {r['last_pct']:+.3f} %"
            )
    if args.out is not None:
        meta = {"rho_inf": RHO_INF, "dt_s": DEFAULT_DT_S, "steps": STEPS}
        atomic_write_text(args.out, json.dumps({"settings": meta, "rows": rows}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
