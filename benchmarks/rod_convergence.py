"""Accuracy per unknown of the rod's discretisation options (issue 32, item 1).

Usage::

    .venv/bin/python benchmarks/rod_convergence.py [--out FILE] [--preset NAME]

For each option of the discrete rod (how the shaft's mass is put on the nodes, how
the bending stiffness is sampled, how the element lengths are graded) and each element
count it measures, on the linearisation about rest (one bending plane, the follicle's
spring and inertia included):

- the first three natural frequencies against an independent reference, cubic Hermite
  beam elements with the exact taper (``benchmarks/bench_peers.py``, 200 elements);
- the static deflection of the tip and the follicle's rotation under a small force at
  the tip, against the same Hermite beam's static solution.

The options:

``mass``
    ``lumped`` (the rod's mass until issue 32: each segment's truncated-cone mass split
    half and half onto its two nodes), ``centroid`` (split so that the two point masses keep the
    segment's centre of mass: the row sums of the consistent matrix) and
    ``consistent`` (the kinetic energy of the segment with its velocity interpolated
    linearly between the nodes, integrated exactly over the cone: a tridiagonal mass
    matrix, ``RodModel(mass="consistent")``, the default since issue 32; here integrated
    by Gauss quadrature, an independent check of the model's closed form).
``stiffness``
    ``node`` (today's: ``E I`` at the node over its dual length) or ``cell`` (``E I``
    averaged over the node's dual cell).
``grading``
    ``uniform`` or ``radius`` (element lengths proportional to the square root of the
    local radius, finer toward the thin tip).

The peak follicle moment of the standard contact needs the dynamics, which the rod
kernels run for ``node`` stiffness on ``uniform`` elements with each mass: for those,
each element count's standard contact
(:func:`~vibrissa.whisker.simulate.simulate` as ``vibrissa bench physics`` runs it) is
compared with the converged rod's (``bench_peers.reference_peak_moment_nm``: 150
elements, 31.25 us steps, every step nonlinear), and the fewest elements within both
tolerances (first mode 0.1 %, peak moment 1 %) are reported per option. ``centroid`` is
run by putting its node masses into the model (``RodModel.mass``).

Last, ``load_points`` measures what the element count costs in statics away from the
tip: the deflection at a small point load at several arc lengths of the model's rod
(clamped follicle, ``RodModel.static_force``) against Euler-Bernoulli beam theory with
the exact taper (``int_0^a (a - s)^2 / EI(s) ds``). Contacts between nodes near the
thick base are the coarse mesh's weak spot.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import functools
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_peers import (
    MOMENT_TOLERANCE_PCT,
    PEAK_REFERENCE,
    reference_frequencies_hz,
    reference_peak_moment_nm,
)

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.whisker import RodModel, WhiskerGeometry, preset
from vibrissa.whisker.benchmark import STANDARD, standard_trajectory
from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS
from vibrissa.whisker.simulate import PoleContact, simulate

DEFAULT_OUT = Path(__file__).resolve().parent / "results" / "rod_convergence.json"
#: Element counts tried for every option.
ELEMENTS = (8, 10, 12, 14, 16, 20, 24, 26, 28, 32, 36, 40)
#: Hermite elements of the reference (converged well below 1e-6 relative).
REFERENCE_ELEMENTS = 200
#: The tolerance issue 32 holds both simulators to, on the first mode (%).
FIRST_MODE_TOLERANCE_PCT = 0.1
#: The tip force of the static check (N): small, so the response is linear.
TIP_FORCE_N = 1e-4
OPTIONS: tuple[dict[str, str], ...] = (
    {"mass": "lumped", "stiffness": "node", "grading": "uniform"},
    {"mass": "lumped", "stiffness": "cell", "grading": "uniform"},
    {"mass": "lumped", "stiffness": "node", "grading": "radius"},
    {"mass": "centroid", "stiffness": "node", "grading": "uniform"},
    {"mass": "centroid", "stiffness": "node", "grading": "radius"},
    {"mass": "consistent", "stiffness": "node", "grading": "uniform"},
    {"mass": "consistent", "stiffness": "cell", "grading": "uniform"},
    {"mass": "consistent", "stiffness": "node", "grading": "radius"},
)


def nodes_m(g: WhiskerGeometry, n_elements: int, grading: str) -> np.ndarray:
    """Arc lengths (m) of the shaft's nodes, base to tip."""
    L = g.length_m
    if grading == "uniform":
        return np.linspace(0.0, L, n_elements + 1)
    s = np.linspace(0.0, L, 20001)
    w = g.radius_m(s) ** -0.5  # element length ~ sqrt(radius)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(s))])
    return np.interp(np.linspace(0.0, cum[-1], n_elements + 1), cum, s)


def plane_matrices(
    g: WhiskerGeometry, n_elements: int, mass: str, stiffness: str, grading: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stiffness and mass of the free lateral DOFs in one plane, and the nodes' arc lengths.

    The stiffness is the rod kernels' own tangent at rest (``RodModel.stiffness_matrix``)
    with the nodes, bending constants and masses of the option put in.
    """
    model = RodModel(g, n_elements)
    E = g.youngs_modulus_gpa * 1e9
    d = g.follicle_depth_mm * 1e-3
    L = g.length_m
    s = np.concatenate([[-d], nodes_m(g, n_elements, grading)])
    n = s.size
    h = np.diff(s)[1:]
    x = np.zeros((n, 3))
    x[:, 2] = s
    radius = g.radius_m(np.clip(s, 0.0, L))
    EA = model.EA.copy()
    mid = g.radius_m(0.5 * (np.clip(s[:-1], 0.0, L) + s[1:]))
    EA[1:] = E * math.pi * mid[1:] ** 2
    dual = np.zeros(n)
    dual[1] = 0.5 * h[0]
    dual[2 : n - 1] = 0.5 * (h[:-1] + h[1:])
    EI = E * math.pi * radius**4 / 4.0
    if stiffness == "cell":
        xg, wg = np.polynomial.legendre.leggauss(8)
        for i in range(1, n - 1):
            a = s[i] - (0.5 * h[i - 2] if i >= 2 else 0.0)
            b = s[i] + 0.5 * h[i - 1]
            r = g.radius_m(a + (xg + 1.0) / 2.0 * (b - a))
            EI[i] = float(np.sum(wg / 2.0 * E * math.pi * r**4 / 4.0))
    kb = np.zeros(n)
    kb[1 : n - 1] = EI[1 : n - 1] / (2.0 * dual[1 : n - 1])
    model.s_rest, model.x_rest, model.radius, model.L0 = s, x, radius, np.diff(s)
    model.EA, model.EI, model.kb = EA, EI, kb
    # the segments' mass matrices: velocity interpolated linearly, the cone integrated
    xg, wg = np.polynomial.legendre.leggauss(6)
    t = (xg + 1.0) / 2.0
    shape = np.stack([1.0 - t, t])
    M = np.zeros((n, n))
    for e in range(1, n - 1):
        rho_a = g.density_kg_m3 * math.pi * g.radius_m(s[e] + t * h[e - 1]) ** 2
        Me = (shape * (wg * h[e - 1] / 2.0 * rho_a)) @ shape.T
        if mass == "lumped":
            Me = np.diag(np.full(2, 0.5 * Me.sum()))
        elif mass == "centroid":
            Me = np.diag(Me.sum(axis=1))
        M[e : e + 2, e : e + 2] += Me
    M[1, 1] += g.follicle_inertia_kg_m2 / d**2
    K = model.stiffness_matrix()
    free = np.arange(1, n)
    K = K[np.ix_(3 * free, 3 * free)]
    return 0.5 * (K + K.T), M[np.ix_(free, free)], s


@functools.cache
def _reference(g: WhiskerGeometry) -> tuple[np.ndarray, float, float]:
    tip, rotation = hermite_static(g, REFERENCE_ELEMENTS, TIP_FORCE_N)
    return reference_frequencies_hz(g, REFERENCE_ELEMENTS, 3), tip, rotation


def hermite_static(g: WhiskerGeometry, n_elements: int, force_n: float) -> tuple[float, float]:
    """Tip deflection (m) and follicle rotation (rad) of the Hermite beam under a tip force."""
    L = g.length_m
    E = g.youngs_modulus_gpa * 1e9
    d = g.follicle_depth_mm * 1e-3
    h = L / n_elements
    xg, wg = np.polynomial.legendre.leggauss(6)
    t = (xg + 1.0) / 2.0
    B = np.stack([12 * t - 6, h * (6 * t - 4), 6 - 12 * t, h * (6 * t - 2)]) / h**2
    n_dof = 2 * (n_elements + 1)
    K = np.zeros((n_dof, n_dof))
    for e in range(n_elements):
        ei = wg * h / 2 * E * math.pi * g.radius_m(e * h + t * h) ** 4 / 4
        K[2 * e : 2 * e + 4, 2 * e : 2 * e + 4] += (B * ei) @ B.T
    T = np.zeros((n_dof, n_dof - 1))
    T[0, 0], T[1, 0] = d, 1.0
    T[2:, 1:] = np.eye(n_dof - 2)
    K = T.T @ K @ T
    K[0, 0] += g.follicle_stiffness_nm_per_rad
    f = np.zeros(n_dof - 1)
    f[-2] = force_n
    u = np.linalg.solve(K, f)
    return float(u[-2]), float(u[0])


def measure(g: WhiskerGeometry, option: dict[str, str], n_elements: int) -> dict[str, Any]:
    """One row: the option, the element count and its errors (%)."""
    K, M, s = plane_matrices(g, n_elements, **option)
    mu = scipy.linalg.eigh(M, K, eigvals_only=True)  # M x = mu K x: the large mu exactly
    f = np.sort(np.sqrt(1.0 / mu[-3:]))[:3] / (2 * math.pi)
    ref, tip_ref, rot_ref = _reference(g)
    load = np.zeros(K.shape[0])
    load[-1] = TIP_FORCE_N
    u = np.linalg.solve(K, load)
    rotation = u[0] / (s[1] - s[0])  # node 1 about the pivot, a follicle-depth away
    errors = 100.0 * (f / ref - 1.0)
    return {
        **option,
        "n_elements": n_elements,
        "unknowns": 3 * (s.size - 1),
        "mode_error_pct": [float(e) for e in errors],
        "tip_deflection_error_pct": float(100.0 * (u[-1] / tip_ref - 1.0)),
        "follicle_rotation_error_pct": float(100.0 * (rotation / rot_ref - 1.0)),
    }


#: The options the rod kernels can integrate (node stiffness on uniform elements).
DYNAMIC_OPTIONS: tuple[dict[str, str], ...] = (
    {"mass": "lumped", "stiffness": "node", "grading": "uniform"},
    {"mass": "centroid", "stiffness": "node", "grading": "uniform"},
    {"mass": "consistent", "stiffness": "node", "grading": "uniform"},
)
#: Arc lengths (mm) of the static load-point check, and the element counts it covers.
LOAD_POINTS_MM = (40.0, 60.0, 80.0, 100.0, 120.0, 140.0, 160.0)
LOAD_POINT_ELEMENTS = (8, 12, 16, 20, 28, 40)


def dynamic_model(g: WhiskerGeometry, n_elements: int, mass: str) -> RodModel:
    """The rod model with ``mass``'s node masses (``lumped`` and ``consistent``: the model's)."""
    if mass in ("lumped", "consistent"):
        return RodModel(g, n_elements, mass=mass)
    model = RodModel(g, n_elements, mass="lumped")
    if mass != "lumped":
        _, M, _ = plane_matrices(g, n_elements, mass, "node", "uniform")
        if np.count_nonzero(M - np.diag(np.diag(M))):
            raise ValueError(f"the rod kernels need a diagonal mass; {mass!r} is not")
        model.mass = model.mass.copy()
        model.mass[1:] = np.diag(M)
    return model


def peak_moment_nm(model: RodModel) -> float:
    """Peak follicle moment (N m) of the standard contact, as ``bench physics`` runs it."""
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    T = STANDARD["duration_s"]
    res = simulate(model, contact, standard_trajectory(model, T), T, STANDARD["dt_s"])
    return float(np.max(np.abs(res.follicle_moment_nm[:, 0])))


def add_peak_moments(g: WhiskerGeometry, rows: list[dict[str, Any]]) -> float:
    """Add ``peak_moment_error_pct`` to the rows of :data:`DYNAMIC_OPTIONS`; the reference."""
    ref = reference_peak_moment_nm(STANDARD["duration_s"])
    for r in rows:
        opt = {k: r[k] for k in ("mass", "stiffness", "grading")}
        r["peak_moment_error_pct"] = (
            float(100.0 * (peak_moment_nm(dynamic_model(g, r["n_elements"], r["mass"])) / ref - 1))
            if opt in DYNAMIC_OPTIONS
            else None
        )
    return ref


def load_point_errors(g: WhiskerGeometry, n_elements: int) -> list[float]:
    """Deflection error (%) at a small point load at each of :data:`LOAD_POINTS_MM`."""
    model = RodModel(g, n_elements, rigid_follicle=True)
    E = g.youngs_modulus_gpa * 1e9
    out = []
    for a_mm in LOAD_POINTS_MM:
        a = a_mm * 1e-3
        xg, wg = np.polynomial.legendre.leggauss(12)  # the integrand is smooth: exact enough
        s = (xg + 1.0) / 2.0 * a
        compliance = float(
            np.sum(wg * a / 2.0 * (a - s) ** 2 / (E * math.pi * g.radius_m(s) ** 4 / 4))
        )
        got = model.static_force(TIP_FORCE_N, a_mm).deflection_mm * 1e-3
        out.append(float(100.0 * (got / (TIP_FORCE_N * compliance) - 1.0)))
    return out


def run(name: str) -> dict[str, Any]:
    """Every option at every element count, and the fewest elements each needs."""
    g = preset(name)
    ref = _reference(g)[0]
    rows = [measure(g, opt, n) for opt in OPTIONS for n in ELEMENTS]
    peak_ref = add_peak_moments(g, rows)
    fewest = []
    for opt in OPTIONS:
        mine = [r for r in rows if all(r[k] == v for k, v in opt.items())]
        ok = [r for r in mine if abs(r["mode_error_pct"][0]) <= FIRST_MODE_TOLERANCE_PCT]
        both = [
            r
            for r in ok
            if r["peak_moment_error_pct"] is not None
            and abs(r["peak_moment_error_pct"]) <= MOMENT_TOLERANCE_PCT
        ]
        fewest.append(
            {
                **opt,
                "fewest_elements": min(r["n_elements"] for r in ok) if ok else None,
                "fewest_elements_both": (
                    min(r["n_elements"] for r in both)
                    if both
                    else (None if opt in DYNAMIC_OPTIONS else "not run")
                ),
            }
        )
    return {
        "preset": name,
        "reference": f"cubic Hermite beam, {REFERENCE_ELEMENTS} elements, exact taper",
        "reference_frequencies_hz": [float(v) for v in ref],
        "first_mode_tolerance_pct": FIRST_MODE_TOLERANCE_PCT,
        "default_n_elements": DEFAULT_N_ELEMENTS,
        "default_mass": RodModel(g).mass_kind,
        "tip_force_n": TIP_FORCE_N,
        "moment_tolerance_pct": MOMENT_TOLERANCE_PCT,
        "reference_peak_follicle_moment_nm": peak_ref,
        "peak_reference": dict(PEAK_REFERENCE),
        "rows": rows,
        "fewest_elements_within_tolerance": fewest,
        "load_points": {
            "at_mm": list(LOAD_POINTS_MM),
            "rows": [
                {"n_elements": n, "deflection_error_pct": load_point_errors(g, n)}
                for n in LOAD_POINT_ELEMENTS
            ],
        },
    }


def table(result: dict[str, Any]) -> str:
    """The fewest elements per option, and each option's errors at those counts."""
    out = [
        f"{result['preset']}: fewest elements with |first-mode error| <= "
        f"{result['first_mode_tolerance_pct']} %",
        f"{'mass':<11} {'stiffness':<9} {'grading':<8} {'n':>4} {'mode 1 %':>9} "
        f"{'mode 2 %':>9} {'mode 3 %':>9} {'tip %':>8} {'follicle %':>10} {'peak M %':>9} "
        f"{'n (both)':>9}",
    ]
    for best in result["fewest_elements_within_tolerance"]:
        n = best["fewest_elements"]
        if n is None:
            out.append(f"{best['mass']:<11} {best['stiffness']:<9} {best['grading']:<8} none")
            continue
        (r,) = [
            r
            for r in result["rows"]
            if r["n_elements"] == n
            and all(r[k] == best[k] for k in ("mass", "stiffness", "grading"))
        ]
        m = r["mode_error_pct"]
        p = r["peak_moment_error_pct"]
        out.append(
            f"{r['mass']:<11} {r['stiffness']:<9} {r['grading']:<8} {n:>4} {m[0]:>+9.3f} "
            f"{m[1]:>+9.3f} {m[2]:>+9.3f} {r['tip_deflection_error_pct']:>+8.3f} "
            f"{r['follicle_rotation_error_pct']:>+10.3f} "
            + (f"{p:>+9.2f} " if p is not None else f"{'-':>9} ")
            + f"{best['fewest_elements_both']!s:>9}"
        )
    lp = result["load_points"]
    out.append("")
    out.append(
        "deflection error (%) at a point load at (mm): " + " ".join(f"{a:>7g}" for a in lp["at_mm"])
    )
    for r in lp["rows"]:
        out.append(
            f"{r['n_elements']:>4} elements{'':<36}"
            + " ".join(f"{e:>+7.2f}" for e in r["deflection_error_pct"])
        )
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    """Measure, print the table and write the JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="JSON file to write")
    parser.add_argument("--preset", default="xy-robot", help="whisker preset (default xy-robot)")
    args = parser.parse_args(argv)
    try:
        preset(args.preset)
    except ValueError as exc:
        parser.error(str(exc))
    result = run(args.preset)
    result["meta"] = {
        "command": " ".join(["python benchmarks/rod_convergence.py", *sys.argv[1:]]),
        "vibrissa_version": __version__,
        "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    print(table(result))
    atomic_write_text(args.out, json.dumps(result, indent=1) + "\n")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
