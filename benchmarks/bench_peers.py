"""MuJoCo as a peer: the standard pole contact at equal accuracy, timed against ours.

Usage::

    .venv/bin/pip install -e '.[peers]'
    .venv/bin/python benchmarks/bench_peers.py [--json] [--out FILE] [--quick]
        [--repeats N] [--duration-s S]

The script builds the whisker and follicle of the standard scenario (the ``xy-robot``
preset, :data:`vibrissa.whisker.benchmark.STANDARD`) as a MuJoCo capsule chain, finds
the fewest links and the largest stable time step at which MuJoCo is as accurate as
required, then times the standard trial in both simulators on one core, interleaved
(ours, MuJoCo, ours, MuJoCo, ...), best of N each.

The MuJoCo whisker
    A follicle body turns about the pivot (``follicle_depth_mm`` below the base) on two
    hinges (x and y) with the follicle's rotational stiffness; its inertia about the
    pivot is ``follicle_inertia_kg_m2`` (a point mass at the base). The free shaft is
    ``N`` equal rigid links (capsules of the radius at their middle); each carries the
    mass, centre of mass and inertia of its truncated cone (density and taper). Link
    ``j`` hangs on two hinges at its lower end whose stiffness is the discretised
    bending stiffness ``EI(s_j) / l_j``, where ``l_j`` is the length the joint stands for
    (one link; half a link at the base, the clamped end of the shaft): the Hencky bar
    chain, which is also how our rod lumps bending at its nodes. Damping: each shaft
    hinge gets ``beta_shaft x k_j`` (our stiffness-proportional material damping), and
    the follicle hinges a damper set, on MuJoCo's own linearisation (its mass matrix,
    the joint stiffnesses and dampers), so that the first mode has our damping ratio.
    No gravity (our model has none).
The pole
    A capsule of the pole's radius along y, on a slide joint along x. Its body weighs
    one tonne, so the contact (tens of mN) cannot move it measurably; the script sets
    its velocity to the trajectory's (:func:`~vibrissa.whisker.benchmark.standard_trajectory`)
    wherever that changes (the mean velocity over a step that straddles a change), so
    it passes exactly through the trajectory's positions at every step. A mocap body
    would move exactly too, but it has no degrees of freedom, so MuJoCo's contacts see
    it at rest, which would get the friction direction and the contact damping wrong.
Contact
    ``condim 3``, friction 0.3, elliptic cones. ``solref = (2 dt, 1)``: the stiffest
    contact MuJoCo integrates stably at step ``dt`` (its documented lower bound on the
    time constant) with critical damping, as our penalty contact is stiff (20 kN/m: the
    pole presses under a micrometre into the whisker). The default time constant
    (20 ms) would let the pole sink millimetres into this light whisker and change the
    peak moment by percent. ``solimp`` is MuJoCo's default (0.9, 0.95, 0.001).
Equal accuracy
    The reference first mode comes from neither simulator: a Hermite finite-element
    solution of the tapered Euler-Bernoulli beam clamped to the rigid follicle, which
    turns on its spring about the pivot (:func:`reference_first_mode_hz`, converged to
    better than 1e-6). MuJoCo's first mode is measured by free ring-down (dampers off:
    the undamped frequency; released from the static shape under a tip force, sampled
    at 4 kHz, Hann-windowed FFT peak refined by parabolic interpolation). For each
    number of links (ascending) the time steps are tried from the largest down; a step
    is stable if the ring-down and the standard contact run give no NaN and no MuJoCo
    warning, the undamped ring-down's energy stays bounded (below 1.1 x its initial
    value), and the whisker's energy decays after the pole has left. The first
    (links, step) whose first mode is within 0.1 % of the reference and whose peak
    follicle moment in the standard contact is within 1 % of the peak-moment reference
    is the equal-accuracy configuration. The follicle moment is
    ``k_f x`` the follicle hinge's angle (MuJoCo's spring), sampled at 4 kHz.
The same tolerance for us
    Our rod is held to the same two tolerances (issue 32): for each element count
    (:data:`OUR_ELEMENTS`, ascending) at the standard step (0.25 ms, the largest that
    divides the 4 kHz output period), its first mode (the rod's linearisation; our
    implicit step's period error at 16 Hz is of order (w dt)^2 / 12 = 6e-5, i.e.
    0.006 %) against the beam reference and its peak follicle moment in the standard
    contact against the peak-moment reference; the fewest elements within both is the
    setting timed. The standard contact has no closed form, so the peak-moment
    reference is our rod converged
    (:data:`PEAK_REFERENCE`: 150 elements, 31.25 us steps, every step the nonlinear
    rod): between 100 and 150 elements it moves by 6e-5 relative, and between 31.25
    and 62.5 us steps by 3e-4, both well inside the 1 % tolerance (``physics_benchmark``
    at those settings, every step nonlinear, 2026-11-27). The JSON also
    states the default rod's errors (``vibrissa_default_*``), which may lie outside.
Timing
    Ours: :func:`~vibrissa.whisker.benchmark.physics_benchmark` (one timed standard trial
    per call, Hall output at 4 kHz); MuJoCo: the same scenario with ``mj_step``,
    reading the follicle angle at 4 kHz (at the step nearest each sample time). The
    process is pinned to one CPU, numba and BLAS to one thread; MuJoCo steps on one
    thread. Real-time factor = simulated seconds / wall seconds; ``ratio`` = ours /
    MuJoCo's.
The planar chain
    The standard contact stays in the x-z plane. A MuJoCo user who knows that can drop
    the hinges about x and simulate half the joints; our rod does not exploit the
    plane. So the accepted chain is also built with its y hinges only, checked in the
    standard contact, and timed third in each round: ``mujoco_planar_rtf`` and
    ``ratio_planar`` = ours / that (``mujoco_planar_peak_moment_error_pct`` is its peak
    moment against ours). It is not part of the search.

``--quick`` narrows the search for tests: it starts at the fewest links whose
linearised first mode is within the tolerance and at the largest step below the
linearised stability limit, rings down for 1 s instead of 2 s and times once.
Progress goes to stderr; ``--json`` prints the result as JSON on stdout, ``--out FILE``
writes it (atomically), e.g. ``benchmarks/results/peers.json``. Without mujoco the
script exits with status 2 saying how to install it.
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import json
import math
import os
import platform
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg
import scipy.optimize

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.whisker import RodModel, WhiskerGeometry, preset
from vibrissa.whisker.benchmark import STANDARD, physics_benchmark, standard_trajectory

INSTALL_HINT = "error: mujoco is not installed; install the peers extra: pip install -e '.[peers]'"

#: Required agreement of MuJoCo's first bending mode with the beam reference (%).
FIRST_MODE_TOLERANCE_PCT = 0.1
#: Required agreement of MuJoCo's peak follicle moment with ours (%).
MOMENT_TOLERANCE_PCT = 1.0
#: Links tried, ascending.
LINKS = tuple(range(4, 41))
#: Time steps tried, descending (s): the R10 series from 1 ms to 12.5 us.
TIME_STEPS_S = tuple(
    round(m * 10.0**e, 10)
    for e in (-4, -5)
    for m in (10.0, 8.0, 6.3, 5.0, 4.0, 3.15, 2.5, 2.0, 1.6, 1.25)
)
#: Mass of the pole's body (kg): heavy enough that the contact cannot move it.
POLE_MASS_KG = 1000.0
#: Tip deflection of the ring-down's initial shape (m): small, so the response is linear.
RING_DOWN_TIP_M = 1e-3
#: Hermite elements of the reference beam (converged to better than 1e-6 at 100).
REFERENCE_ELEMENTS = 100
#: Our rod's element counts tried, ascending.
OUR_ELEMENTS = (8, 10, 12, 14, 16, 20, 24, 28, 32, 36, 40, 48, 56, 64, 80, 100)
#: The converged rod whose peak follicle moment is the reference for both simulators.
PEAK_REFERENCE: dict[str, Any] = {"n_elements": 150, "dt_s": 31.25e-6, "speedups": False}
#: MuJoCo's warnings during a run (collected by :func:`one_core`).
WARNINGS: list[str] = []


# ---------------------------------------------------------------------- reference
def reference_frequencies_hz(
    geometry: WhiskerGeometry, n_elements: int = REFERENCE_ELEMENTS, n_modes: int = 3
) -> np.ndarray:
    """Bending frequencies (Hz) of the tapered Euler-Bernoulli whisker in its follicle.

    Independent of both simulators: cubic Hermite beam elements with the exact taper
    (EI and mass per length integrated by 6-point Gauss quadrature, exact for the
    conical shaft), clamped to the rigid follicle link, which turns about the pivot
    (``follicle_depth_mm`` below the base) against the follicle's rotational spring
    and inertia. The base's displacement and slope are ``d psi`` and ``psi``.

    Parameters
    ----------
    geometry
        The whisker.
    n_elements
        Beam elements along the shaft.
    n_modes
        How many of the lowest frequencies to return.

    Returns
    -------
    ndarray
        The lowest ``n_modes`` undamped natural frequencies (Hz), ascending.
    """
    L = geometry.length_m
    E = geometry.youngs_modulus_gpa * 1e9
    rho = geometry.density_kg_m3
    d = geometry.follicle_depth_mm * 1e-3
    h = L / n_elements
    xg, wg = np.polynomial.legendre.leggauss(6)
    t = (xg + 1.0) / 2.0
    N = np.stack(
        [1 - 3 * t**2 + 2 * t**3, h * (t - 2 * t**2 + t**3), 3 * t**2 - 2 * t**3, h * (t**3 - t**2)]
    )
    B = np.stack([12 * t - 6, h * (6 * t - 4), 6 - 12 * t, h * (6 * t - 2)]) / h**2
    n_dof = 2 * (n_elements + 1)
    K = np.zeros((n_dof, n_dof))
    M = np.zeros((n_dof, n_dof))
    for e in range(n_elements):
        r = geometry.radius_m(e * h + t * h)
        ei = wg * h / 2 * E * math.pi * r**4 / 4
        ra = wg * h / 2 * rho * math.pi * r**2
        K[2 * e : 2 * e + 4, 2 * e : 2 * e + 4] += (B * ei) @ B.T
        M[2 * e : 2 * e + 4, 2 * e : 2 * e + 4] += (N * ra) @ N.T
    # base (w, w') = (d psi, psi): the follicle angle psi replaces the base's two DOFs
    T = np.zeros((n_dof, n_dof - 1))
    T[0, 0], T[1, 0] = d, 1.0
    T[2:, 1:] = np.eye(n_dof - 2)
    K = T.T @ K @ T
    M = T.T @ M @ T
    K[0, 0] += geometry.follicle_stiffness_nm_per_rad
    M[0, 0] += geometry.follicle_inertia_kg_m2
    # the largest eigenvalues of M x = mu K x are accurate to machine precision, the
    # smallest of K x = w^2 M x are not (the matrix's condition number is ~1e10)
    n = n_dof - 1
    mu = scipy.linalg.eigh(M, K, eigvals_only=True, subset_by_index=[n - n_modes, n - 1])
    return np.sort(np.sqrt(1.0 / mu)) / (2 * math.pi)


def reference_first_mode_hz(geometry: WhiskerGeometry) -> float:
    """First bending frequency (Hz) of :func:`reference_frequencies_hz`."""
    return float(reference_frequencies_hz(geometry, n_modes=1)[0])


# ---------------------------------------------------------------------- the MuJoCo whisker
@dataclass(frozen=True)
class ChainDesign:
    """The capsule chain's numbers, in SI units (joint ``j`` at the foot of link ``j``)."""

    edges_m: np.ndarray  # link ends along the shaft, n_links + 1
    stiffness_nm: np.ndarray  # shaft hinges, n_links
    mass_kg: np.ndarray
    com_m: np.ndarray  # centre of mass of each link from its foot
    inertia_kg_m2: np.ndarray  # (n_links, 3): transverse, transverse, axial about the com
    radius_m: np.ndarray  # capsule radius (at the link's middle)


def chain_design(geometry: WhiskerGeometry, n_links: int) -> ChainDesign:
    """Links, joint stiffnesses, masses and inertias of the whisker as ``n_links`` links."""
    L = geometry.length_m
    E = geometry.youngs_modulus_gpa * 1e9
    rho = geometry.density_kg_m3
    edges = np.linspace(0.0, L, n_links + 1)
    # the length each joint stands for: half a link at the clamped base, one elsewhere
    span = np.full(n_links, L / n_links)
    span[0] = 0.5 * L / n_links
    stiffness = E * math.pi * geometry.radius_m(edges[:-1]) ** 4 / 4 / span
    xg, wg = np.polynomial.legendre.leggauss(8)
    mass, com, inertia = [], [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        s = a + (xg + 1) / 2 * (b - a)
        w = wg * (b - a) / 2
        r = geometry.radius_m(s)
        lam = rho * math.pi * r**2
        m = float(np.sum(w * lam))
        c = float(np.sum(w * lam * s)) / m
        it = float(np.sum(w * (lam * (s - c) ** 2 + rho * math.pi * r**4 / 4)))
        ia = float(np.sum(w * rho * math.pi * r**4 / 2))
        mass.append(m)
        com.append(c - a)
        inertia.append((it, it, ia))
    return ChainDesign(
        edges_m=edges,
        stiffness_nm=stiffness,
        mass_kg=np.array(mass),
        com_m=np.array(com),
        inertia_kg_m2=np.array(inertia),
        radius_m=geometry.radius_m(0.5 * (edges[:-1] + edges[1:])),
    )


def mjcf(
    geometry: WhiskerGeometry,
    n_links: int,
    dt_s: float,
    follicle_damping: float = 0.0,
    beta_shaft_s: float = 0.0,
    pole_radius_m: float = STANDARD["pole_radius_mm"] * 1e-3,
    pole_z_m: float = STANDARD["radial_distance_mm"] * 1e-3,
    friction: float = STANDARD["friction"],
    planar: bool = False,
) -> str:
    """MJCF text of the whisker as a capsule chain and the pole on its slide.

    Parameters
    ----------
    geometry
        The whisker.
    n_links
        Rigid links along the free shaft.
    dt_s
        MuJoCo's time step (s); the contact's time constant is twice that.
    follicle_damping
        Damping of each follicle hinge (N m s/rad).
    beta_shaft_s
        Stiffness-proportional damping of the shaft hinges (s).
    pole_radius_m, pole_z_m, friction
        The pole: radius, height along the rest axis, friction coefficient.
    planar
        Only the hinges about y (bending in the x-z plane, the standard contact's
        plane): the chain a user would build knowing the motion stays in that plane.
    """
    c = chain_design(geometry, n_links)
    d = geometry.follicle_depth_mm * 1e-3
    kf = geometry.follicle_stiffness_nm_per_rad
    m_fol = geometry.follicle_inertia_kg_m2 / d**2
    tiny = 1e-15  # a point mass still needs a positive-definite inertia
    out = [
        '<mujoco model="whisker">',
        f'  <option timestep="{dt_s!r}" gravity="0 0 0" integrator="Euler" cone="elliptic">',
        '    <flag energy="enable"/>',
        "  </option>",
        f'  <default><geom friction="{friction!r} 0 0" condim="3" solref="{2 * dt_s!r} 1"/>'
        "</default>",
        "  <worldbody>",
        f'    <body name="follicle" pos="0 0 {-d!r}">',
        f'      <joint name="follicle_y" type="hinge" axis="0 1 0" stiffness="{kf!r}" '
        f'damping="{follicle_damping!r}"/>',
        *(
            []
            if planar
            else [
                f'      <joint name="follicle_x" type="hinge" axis="1 0 0" stiffness="{kf!r}" '
                f'damping="{follicle_damping!r}"/>'
            ]
        ),
        f'      <inertial pos="0 0 {d!r}" mass="{m_fol!r}" diaginertia="{tiny} {tiny} {tiny}"/>',
    ]
    foot = -d
    for j in range(n_links):
        a, b = float(c.edges_m[j]), float(c.edges_m[j + 1])
        k = float(c.stiffness_nm[j])
        damp = beta_shaft_s * k
        it, _, ia = (float(v) for v in c.inertia_kg_m2[j])
        out += [
            f'{"  " * (j + 3)}<body name="link{j}" pos="0 0 {a - foot!r}">',
            f'{"  " * (j + 4)}<joint name="bend_y{j}" type="hinge" axis="0 1 0" '
            f'stiffness="{k!r}" damping="{damp!r}"/>',
            *(
                []
                if planar
                else [
                    f'{"  " * (j + 4)}<joint name="bend_x{j}" type="hinge" axis="1 0 0" '
                    f'stiffness="{k!r}" damping="{damp!r}"/>'
                ]
            ),
            f'{"  " * (j + 4)}<inertial pos="0 0 {float(c.com_m[j])!r}" '
            f'mass="{float(c.mass_kg[j])!r}" diaginertia="{it!r} {it!r} {ia!r}"/>',
            f'{"  " * (j + 4)}<geom name="shaft{j}" type="capsule" fromto="0 0 0 0 0 {b - a!r}" '
            f'size="{float(c.radius_m[j])!r}" contype="1" conaffinity="0"/>',
        ]
        foot = a
    out += ["  " * (j + 3 - i) + "</body>" for i in range(n_links + 1)]
    out += [
        f'    <body name="pole" pos="0 0 {pole_z_m!r}">',
        '      <joint name="pole_x" type="slide" axis="1 0 0"/>',
        f'      <geom name="pole" type="capsule" fromto="0 -0.05 0 0 0.05 0" '
        f'size="{pole_radius_m!r}" mass="{POLE_MASS_KG!r}" contype="0" conaffinity="1"/>',
        "    </body>",
        "  </worldbody>",
        "</mujoco>",
    ]
    return "\n".join(out) + "\n"


class MujocoWhisker:
    """The whisker as a MuJoCo capsule chain, with the pole, ready to run the scenario.

    Parameters
    ----------
    mujoco
        The imported ``mujoco`` module.
    geometry
        The whisker.
    n_links
        Rigid links along the free shaft.
    dt_s
        Time step (s).
    damping_ratio
        Damping ratio of the first mode that the follicle damper is set for (default
        the geometry's); ``beta_shaft_s`` is the shaft's stiffness-proportional damping.
    planar
        Hinges about y only (see :func:`mjcf`).
    """

    def __init__(
        self,
        mujoco: Any,
        geometry: WhiskerGeometry,
        n_links: int,
        dt_s: float,
        damping_ratio: float | None = None,
        beta_shaft_s: float = 0.0,
        planar: bool = False,
    ) -> None:
        self.mj = mujoco
        self.geometry = geometry
        self.n_links = int(n_links)
        self.dt_s = float(dt_s)
        self.design = chain_design(geometry, n_links)
        self.model = mujoco.MjModel.from_xml_string(
            mjcf(geometry, n_links, dt_s, beta_shaft_s=beta_shaft_s, planar=planar)
        )
        self.planar = bool(planar)
        self.data = mujoco.MjData(self.model)
        jnt = {self.model.joint(i).name: i for i in range(self.model.njnt)}
        self.qpos_follicle = int(self.model.jnt_qposadr[jnt["follicle_y"]])
        self.qpos_pole = int(self.model.jnt_qposadr[jnt["pole_x"]])
        self.dof_pole = int(self.model.jnt_dofadr[jnt["pole_x"]])
        self.dof_follicle = [
            int(self.model.jnt_dofadr[jnt[f"follicle_{a}"]]) for a in ("y" if planar else "yx")
        ]
        # one bending plane (x-z): the follicle's and the shaft's y hinges
        self.plane_dofs = np.array(
            [int(self.model.jnt_dofadr[jnt["follicle_y"]])]
            + [int(self.model.jnt_dofadr[jnt[f"bend_y{j}"]]) for j in range(n_links)]
        )
        target = geometry.damping_ratio if damping_ratio is None else damping_ratio
        self.follicle_damping = self._design_follicle_damper(target)
        for dof in self.dof_follicle:
            self.model.dof_damping[dof] = self.follicle_damping

    # ------------------------------------------------------------------ linearisation
    def plane_matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """MuJoCo's mass, stiffness and damping matrices at rest, one bending plane."""
        m, d = self.model, self.data
        self.mj.mj_resetData(m, d)
        self.mj.mj_forward(m, d)
        M = np.zeros((m.nv, m.nv))
        unit = np.zeros(m.nv)
        col = np.zeros(m.nv)
        for i in range(m.nv):
            unit[:] = 0.0
            unit[i] = 1.0
            self.mj.mj_mulM(m, d, col, unit)
            M[:, i] = col
        idx = self.plane_dofs
        K = np.diag(m.jnt_stiffness[m.dof_jntid[idx]])
        C = np.diag(m.dof_damping[idx])
        return M[np.ix_(idx, idx)], K, C

    def linear_frequencies_hz(self) -> np.ndarray:
        """Undamped frequencies (Hz) of MuJoCo's linearisation at rest, one plane."""
        M, K, _ = self.plane_matrices()
        w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
        return np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi)

    def _first_mode_damping(self, M: np.ndarray, K: np.ndarray, C: np.ndarray) -> float:
        n = M.shape[0]
        Minv = np.linalg.inv(M)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
        lam = np.linalg.eigvals(A)
        lam = lam[np.imag(lam) > 1e-9]
        first = lam[np.argmin(np.abs(lam))]
        return float(-first.real / abs(first))

    def _design_follicle_damper(self, target: float) -> float:
        """Follicle damping (N m s/rad) giving the first mode the damping ratio ``target``."""
        M, K, C0 = self.plane_matrices()

        def zeta(c: float) -> float:
            C = C0.copy()
            C[0, 0] = c
            return self._first_mode_damping(M, K, C) - target

        if zeta(0.0) >= 0.0:
            return 0.0
        kf = self.geometry.follicle_stiffness_nm_per_rad
        grid = kf * np.geomspace(1e-6, 1.0, 61)
        values = [zeta(c) for c in grid]
        for lo, hi, v in zip([0.0, *grid[:-1]], grid, values, strict=True):
            if v >= 0.0:
                return float(scipy.optimize.brentq(zeta, lo, hi, xtol=1e-16, rtol=1e-12))
        raise ValueError(
            f"the follicle damper cannot give the first mode a damping ratio of {target}"
        )

    def stability_limit_s(self) -> float:
        """Largest step of semi-implicit Euler for the undamped linearisation (2 / w_max)."""
        return 2.0 / (2 * math.pi * float(self.linear_frequencies_hz()[-1]))

    # ------------------------------------------------------------------ running
    def reset(self, pole_x_m: float = -0.1, pole_v_m_s: float = 0.0) -> None:
        """Whisker at rest, pole at ``pole_x_m`` moving at ``pole_v_m_s``."""
        self.mj.mj_resetData(self.model, self.data)
        self.data.qpos[self.qpos_pole] = pole_x_m
        self.data.qvel[self.dof_pole] = pole_v_m_s

    def tip_force_shape(self, tip_deflection_m: float) -> np.ndarray:
        """Hinge angles (rad) of the static shape under a tip force along +x (small angles).

        The moment of a tip force ``F`` about a hinge at ``s`` is ``F (L - s)``; each
        hinge turns by that moment over its stiffness. Returns the angles of the
        follicle hinge and of the shaft hinges (y axes) scaled to the given tip
        deflection.
        """
        g = self.geometry
        L = g.length_m
        d = g.follicle_depth_mm * 1e-3
        s = self.design.edges_m[:-1]
        q = np.concatenate(
            [[(L + d) / g.follicle_stiffness_nm_per_rad], (L - s) / self.design.stiffness_nm]
        )
        arm = np.concatenate([[L + d], L - s])
        return q * tip_deflection_m / float(np.dot(q, arm))

    def run(
        self,
        duration_s: float,
        sample_rate_hz: float,
        pole: tuple[np.ndarray, np.ndarray] | None = None,
        check_every: int = 0,
        uniform: bool = False,
    ) -> Run:
        """Integrate from the current state, reading the follicle angle at ``sample_rate_hz``.

        Parameters
        ----------
        duration_s
            Simulated time (s).
        sample_rate_hz
            Readout rate; each sample is the state at the step nearest its time. With
            ``uniform`` the readout is every ``max(1, round(1 / (rate dt)))`` steps
            instead (exactly uniform samples, for spectra).
        pole
            ``(t_s, x_m)``: the pole's trajectory, piecewise linear; its velocity is
            set to the trajectory's wherever that changes. ``None``: the pole stays.
        check_every
            Check for non-finite values and MuJoCo warnings every that many samples
            and record the whisker's energy there, and track the contact's deepest
            penetration at every sample (0: none of this; timed runs).

        Returns
        -------
        Run
            Sample times, follicle angles, energies at the checks, the deepest
            penetration and whether the run stayed stable.
        """
        m, d, mj = self.model, self.data, self.mj
        dt = self.dt_s
        n_steps = int(round(duration_s / dt))
        if uniform:
            every = max(1, int(round(1.0 / (sample_rate_hz * dt))))
            reads = np.arange(0, n_steps + 1, every)
        else:
            n_samples = int(math.floor(duration_s * sample_rate_hz + 1e-9)) + 1
            reads = np.unique(
                np.minimum(
                    np.rint(np.arange(n_samples) / (sample_rate_hz * dt)).astype(np.int64), n_steps
                )
            )
        changes = np.zeros(0, dtype=np.int64)
        vel = np.zeros(0)
        if pole is not None:
            x = np.interp(np.arange(n_steps + 1) * dt, *pole)
            v = np.diff(x) / dt
            changes = np.flatnonzero(np.abs(np.diff(v)) > 1e-12 * (1.0 + np.abs(v[1:]))) + 1
            changes = np.concatenate([[0], changes])
            vel = v[changes]
            d.qpos[self.qpos_pole] = x[0]
        stops = np.union1d(reads, changes)
        nsteps = np.diff(stops, prepend=0).tolist()
        is_read = np.isin(stops, reads).tolist()
        vel_at = {int(c): float(u) for c, u in zip(changes, vel, strict=True)}
        new_vel = [vel_at.get(int(s)) for s in stops]
        qpos, qvel = d.qpos, d.qvel
        i_fol, i_pole = self.qpos_follicle, self.dof_pole
        angles = np.empty(reads.size)
        energy: list[float] = []
        depth = 0.0
        step = mj.mj_step
        k = 0
        stable = True
        for nstep, read, new_v in zip(nsteps, is_read, new_vel, strict=True):
            if nstep:
                step(m, d, nstep)
            if read:
                angles[k] = qpos[i_fol]
                k += 1
                if check_every:
                    if d.ncon:
                        depth = max(depth, -float(np.min(d.contact.dist[: d.ncon])))
                    if k % check_every == 0:
                        if not self._healthy():
                            stable = False
                            break
                        energy.append(self.whisker_energy())
            if new_v is not None:
                qvel[i_pole] = new_v
        if check_every and stable and not self._healthy():
            stable = False
        return Run(reads[:k] * dt, angles[:k], np.array(energy), depth, stable)

    def _healthy(self) -> bool:
        d = self.data
        warned = sum(int(w.number) for w in d.warning)
        return warned == 0 and bool(np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel)))

    def whisker_energy(self) -> float:
        """Elastic plus kinetic energy of the whisker (J): MuJoCo's, less the pole's."""
        d = self.data
        pole_ke = 0.5 * POLE_MASS_KG * float(d.qvel[self.dof_pole]) ** 2
        return float(d.energy[0] + d.energy[1]) - pole_ke


@dataclass(frozen=True)
class Run:
    """Follicle angle samples of one MuJoCo run."""

    time_s: np.ndarray
    angle_rad: np.ndarray
    energy_j: np.ndarray  # at the checks
    penetration_m: float  # deepest contact penetration at the samples
    stable: bool


# ---------------------------------------------------------------------- ring-down
def peak_frequency_hz(time_s: np.ndarray, signal: np.ndarray) -> float:
    """Frequency (Hz) of the strongest spectral peak of a uniformly sampled signal.

    Hann window, zero-padded FFT (16x), parabolic interpolation of the log magnitude
    around the largest bin.
    """
    rate = 1.0 / float(time_s[1] - time_s[0])
    x = (signal - signal.mean()) * np.hanning(signal.size)
    n = 16 * 2 ** int(math.ceil(math.log2(signal.size)))
    mag = np.abs(np.fft.rfft(x, n))
    k = int(np.argmax(mag[1:-1])) + 1
    a, b, c = np.log(mag[k - 1 : k + 2])
    shift = 0.5 * (a - c) / (a - 2 * b + c)
    return (k + shift) * rate / n


def decay_damping_ratio(time_s: np.ndarray, signal: np.ndarray, frequency_hz: float) -> float:
    """Damping ratio of a decaying oscillation from the log of its successive peaks."""
    x = signal - signal[-signal.size // 4 :].mean()
    i = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]) & (x[1:-1] > 0)) + 1
    i = i[time_s[i] > 2.0 / frequency_hz]  # the higher modes have died away
    a, b, c = x[i - 1], x[i], x[i + 1]
    peak = b - 0.125 * (a - c) ** 2 / (a - 2 * b + c)
    keep = peak > 1e-3 * peak.max()
    sigma = -np.polyfit(time_s[i][keep], np.log(peak[keep]), 1)[0]
    wd = 2 * math.pi * frequency_hz
    return float(sigma / math.hypot(sigma, wd))


def ring_down(
    whisker: MujocoWhisker, duration_s: float, damped: bool = False
) -> tuple[float, float | None, bool]:
    """First mode (Hz) by free ring-down, the damping ratio if ``damped``, and stability.

    The whisker starts from the static shape under a tip force (1 mm at the tip) and
    is released; the follicle angle is read uniformly at about 4 kHz. Undamped (the
    dampers disabled), the run is stable if nothing is non-finite, MuJoCo warns of
    nothing and the energy stays bounded: never above 1.1 x its initial value.
    (Semi-implicit Euler does not conserve the energy exactly but keeps it within
    about ``w dt / 2`` of it, ~1-3 % here for the first mode, without drift; an
    unstable step grows it by orders of magnitude within a fraction of a second.)
    """
    mj = whisker.mj
    m = whisker.model
    saved = m.dof_damping.copy()
    if not damped:
        m.dof_damping[:] = 0.0
    try:
        whisker.reset()
        q = whisker.tip_force_shape(RING_DOWN_TIP_M)
        whisker.data.qpos[m.jnt_qposadr[m.dof_jntid[whisker.plane_dofs]]] = q
        mj.mj_forward(m, whisker.data)
        e0 = whisker.whisker_energy()
        run = whisker.run(duration_s, STANDARD["sample_rate_hz"], check_every=50, uniform=True)
    finally:
        m.dof_damping[:] = saved
    stable = run.stable and run.angle_rad.size > 100
    if stable and not damped:
        stable = bool(np.all(run.energy_j <= 1.1 * e0))
    if not stable:
        return float("nan"), None, False
    f = peak_frequency_hz(run.time_s, run.angle_rad)
    zeta = decay_damping_ratio(run.time_s, run.angle_rad, f) if damped else None
    return f, zeta, True


# ---------------------------------------------------------------------- the standard contact
def pole_path(duration_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The standard pole's x (m) over time (s), as our simulation drives it."""
    traj = standard_trajectory(RodModel(preset(STANDARD["preset"])), max(duration_s, 1e-3))
    return traj.time_s, traj.position_mm[:, 0] * 1e-3


def contact_run(
    whisker: MujocoWhisker,
    duration_s: float,
    path: tuple[np.ndarray, np.ndarray],
    check: bool = True,
) -> tuple[float, bool, float]:
    """The standard contact: peak follicle moment (N m), stability, deepest penetration (m).

    Stable: nothing non-finite, no MuJoCo warning, and once the pole has left the
    whisker's energy decays (it ends below its level at the pole's departure). The
    penetration is read at every sample (0 without ``check``).
    """
    whisker.reset()
    run = whisker.run(
        duration_s, STANDARD["sample_rate_hz"], pole=path, check_every=20 if check else 0
    )
    peak = whisker.geometry.follicle_stiffness_nm_per_rad * float(np.max(np.abs(run.angle_rad)))
    stable = run.stable and bool(np.all(np.isfinite(run.angle_rad)))
    if check and stable:
        sc = STANDARD
        left = sc["advance_s"] + sc["retract_distance_mm"] / sc["retract_speed_mm_s"] + 0.05
        checks = run.time_s[19::20][: run.energy_j.size]
        after = run.energy_j[checks >= left]
        if after.size > 2:
            stable = bool(after[-1] <= after[0] and np.all(after <= 1.01 * after[0]))
    return peak, stable, run.penetration_m


# ---------------------------------------------------------------------- search and timing
@dataclass(frozen=True)
class Setup:
    """What the search and the timing share."""

    mujoco: Any
    geometry: WhiskerGeometry
    beta_shaft_s: float
    duration_s: float
    path: tuple[np.ndarray, np.ndarray]
    reference_hz: float
    reference_peak_nm: float
    vibrissa_n_elements: int
    ring_down_s: float


def _pct(value: float, reference: float) -> float:
    return 100.0 * (value / reference - 1.0)


def search(setup: Setup, links: tuple[int, ...], steps: tuple[float, ...]) -> dict[str, Any]:
    """Fewest links, then largest stable step, meeting both accuracy criteria.

    For each number of links (ascending) the steps are tried from the largest: an
    unstable step moves on to the next smaller one; a first mode outside the tolerance
    moves on to the next number of links (the step changes the first mode by about
    ``(w1 dt)^2 / 24``, a few ppm); a peak moment outside its tolerance tries the next
    smaller step. Returns the accepted row and every row tried.
    """
    rows: list[dict[str, Any]] = []
    for n in links:
        for dt in steps:
            w = MujocoWhisker(setup.mujoco, setup.geometry, n, dt, beta_shaft_s=setup.beta_shaft_s)
            row: dict[str, Any] = {
                "links": n,
                "dt_s": dt,
                "linear_first_mode_hz": float(w.linear_frequencies_hz()[0]),
                "first_mode_hz": None,
                "first_mode_error_pct": None,
                "peak_follicle_moment_nm": None,
                "peak_moment_error_pct": None,
                "max_penetration_m": None,
                "stable": False,
                "accepted": False,
            }
            rows.append(row)
            f, _, stable = ring_down(w, setup.ring_down_s)
            if stable:
                row["first_mode_hz"] = f
                row["first_mode_error_pct"] = _pct(f, setup.reference_hz)
                peak, stable, depth = contact_run(w, setup.duration_s, setup.path)
                if stable:
                    row["peak_follicle_moment_nm"] = peak
                    row["peak_moment_error_pct"] = _pct(peak, setup.reference_peak_nm)
                    row["max_penetration_m"] = depth
            row["stable"] = stable
            _progress(row)
            if not stable:
                continue
            if abs(row["first_mode_error_pct"]) > FIRST_MODE_TOLERANCE_PCT:
                break
            if abs(row["peak_moment_error_pct"]) <= MOMENT_TOLERANCE_PCT:
                row["accepted"] = True
                return {"accepted": row, "rows": rows}
    return {"accepted": None, "rows": rows}


def reference_peak_moment_nm(duration_s: float) -> float:
    """Peak follicle moment (N m) of the standard contact on the converged rod.

    :data:`PEAK_REFERENCE`'s rod and step, every step the nonlinear rod: the reference
    both simulators' peak moments are held to.
    """
    out = physics_benchmark(
        duration_s=duration_s, repeats=1, measure_memory=False, **PEAK_REFERENCE
    )
    return float(out["peak_follicle_moment_nm"])


def our_search(
    geometry: WhiskerGeometry,
    duration_s: float,
    reference_hz: float,
    reference_peak_nm: float,
    elements: tuple[int, ...] = OUR_ELEMENTS,
) -> dict[str, Any]:
    """Fewest elements of our rod meeting both tolerances at the standard step.

    For each element count (ascending): the first mode of the rod's linearisation
    against ``reference_hz``; within the tolerance, the peak follicle moment of the
    standard contact (:func:`~vibrissa.whisker.benchmark.physics_benchmark`, as timed)
    against ``reference_peak_nm``. Returns the accepted row and every row tried.
    """
    rows: list[dict[str, Any]] = []
    for n in elements:
        f1 = float(RodModel(geometry, n).natural_frequencies_hz[0])
        row: dict[str, Any] = {
            "n_elements": n,
            "dt_s": STANDARD["dt_s"],
            "first_mode_hz": f1,
            "first_mode_error_pct": _pct(f1, reference_hz),
            "peak_follicle_moment_nm": None,
            "peak_moment_error_pct": None,
            "accepted": False,
        }
        rows.append(row)
        if abs(row["first_mode_error_pct"]) <= FIRST_MODE_TOLERANCE_PCT:
            out = physics_benchmark(
                duration_s=duration_s, n_elements=n, repeats=1, measure_memory=False
            )
            row["peak_follicle_moment_nm"] = float(out["peak_follicle_moment_nm"])
            row["peak_moment_error_pct"] = _pct(row["peak_follicle_moment_nm"], reference_peak_nm)
        print(f"  ours {n:3d} elements: {_accuracy(row)}", file=sys.stderr)
        if (
            row["peak_moment_error_pct"] is not None
            and abs(row["peak_moment_error_pct"]) <= MOMENT_TOLERANCE_PCT
        ):
            row["accepted"] = True
            return {"accepted": row, "rows": rows}
    return {"accepted": None, "rows": rows}


def _accuracy(row: dict[str, Any]) -> str:
    """A search row's first mode and peak moment with their errors, for progress lines."""
    what = f"first mode {row['first_mode_hz']:.4f} Hz ({row['first_mode_error_pct']:+.3f} %)"
    if row["peak_moment_error_pct"] is not None:
        what += (
            f", peak moment {row['peak_follicle_moment_nm'] * 1e3:.4f} mN m "
            f"({row['peak_moment_error_pct']:+.2f} %)"
        )
    return what


def _progress(row: dict[str, Any]) -> None:
    what = _accuracy(row) if row["stable"] else "unstable"
    print(f"  {row['links']:3d} links, dt {row['dt_s'] * 1e6:6.1f} us: {what}", file=sys.stderr)


def quick_candidates(setup: Setup) -> tuple[tuple[int, ...], tuple[float, ...]]:
    """Links and steps that MuJoCo's linearisation does not already rule out.

    The fewest links whose linearised first mode is within the tolerance, and the
    steps no larger than the linearised stability limit of semi-implicit Euler.
    """
    for n in LINKS:
        w = MujocoWhisker(setup.mujoco, setup.geometry, n, TIME_STEPS_S[-1])
        err = _pct(float(w.linear_frequencies_hz()[0]), setup.reference_hz)
        if abs(err) <= FIRST_MODE_TOLERANCE_PCT:
            limit = w.stability_limit_s()
            return (n, n + 1), tuple(dt for dt in TIME_STEPS_S if dt <= limit)
    return LINKS, TIME_STEPS_S


def time_interleaved(
    setup: Setup,
    whisker: MujocoWhisker,
    repeats: int,
    planar: MujocoWhisker | None = None,
) -> dict[str, Any]:
    """Wall times of the standard trial, ours and MuJoCo's in turn, ``repeats`` each.

    With ``planar`` (the same chain with hinges about y only) that is timed third in
    each round too.
    """
    ours: list[dict[str, Any]] = []
    theirs: list[float] = []
    flat: list[float] = []
    for r in range(repeats):
        ours.append(
            physics_benchmark(
                duration_s=setup.duration_s,
                n_elements=setup.vibrissa_n_elements,
                repeats=1,
                measure_memory=False,
            )
        )
        gc.collect()
        t0 = time.perf_counter()
        contact_run(whisker, setup.duration_s, setup.path, check=False)
        theirs.append(time.perf_counter() - t0)
        line = (
            f"  run {r + 1}/{repeats}: ours {ours[-1]['wall_seconds']:.4f} s, "
            f"MuJoCo {theirs[-1]:.4f} s"
        )
        if planar is not None:
            gc.collect()
            t0 = time.perf_counter()
            contact_run(planar, setup.duration_s, setup.path, check=False)
            flat.append(time.perf_counter() - t0)
            line += f", MuJoCo planar {flat[-1]:.4f} s"
        print(line, file=sys.stderr)
    best = min(ours, key=lambda o: o["wall_seconds"])
    steps_s = round(setup.duration_s / whisker.dt_s) * whisker.dt_s
    planar_keys = (
        {}
        if planar is None
        else {
            "mujoco_planar_wall_seconds_all": flat,
            "mujoco_planar_rtf": steps_s / min(flat),
        }
    )
    return {
        **planar_keys,
        "vibrissa_wall_seconds_all": [o["wall_seconds"] for o in ours],
        "mujoco_wall_seconds_all": theirs,
        "vibrissa_rtf": best["real_time_factor"],
        "vibrissa_simulated_s": best["duration_s"],
        "vibrissa_dt_s": best["dt_s"],
        "vibrissa_n_elements": best["n_elements"],
        "mujoco_rtf": steps_s / min(theirs),
    }


# ---------------------------------------------------------------------- command line
class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"error: {message}", file=sys.stderr)
        raise SystemExit(2)


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    """Parse and check every option (one-line error and exit 2 on a bad one)."""
    ap = _Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument(
        "--out",
        type=Path,
        default=None,
        help="also write the JSON to this file (e.g. benchmarks/results/peers.json)",
    )
    ap.add_argument(
        "--quick",
        action="store_true",
        help="narrow search from MuJoCo's linearisation, 1 s ring-down, one timing",
    )
    ap.add_argument(
        "--repeats",
        type=int,
        default=None,
        help="timed runs of each simulator, interleaved; the best counts "
        "(default 3, 1 with --quick)",
    )
    ap.add_argument(
        "--duration-s",
        type=float,
        default=STANDARD["duration_s"],
        help="simulated time of the standard trial, s (default 1.5; shorter "
        "truncates the scenario, for tests)",
    )
    args = ap.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)
    if args.repeats is None:
        args.repeats = 1 if args.quick else 3
    if not 1 <= args.repeats <= 20:
        ap.error(f"--repeats must lie in [1, 20], got {args.repeats}")
    if not (math.isfinite(args.duration_s) and 0.05 <= args.duration_s <= 60.0):
        ap.error(f"--duration-s must lie in [0.05, 60] s, got {args.duration_s}")
    if args.out is not None:
        out = args.out
        if out.is_dir():
            ap.error(f"--out {out} is a directory; give a file name")
        parent = next((p for p in [out.parent, *out.parent.parents] if p.exists()), Path("."))
        if not parent.is_dir() or not os.access(parent, os.W_OK):
            ap.error(f"--out {out}: cannot create a file under {parent}")
    return args


@contextlib.contextmanager
def one_core(mujoco: Any) -> Iterator[int | None]:
    """Run on one CPU (Linux), numba and BLAS on one thread, MuJoCo's warnings counted.

    Everything is restored on exit. Yields the CPU pinned to (None where the
    platform cannot pin). MuJoCo's warnings (an unstable candidate step warns) are
    collected in :data:`WARNINGS` instead of printed and logged to ``MUJOCO_LOG.TXT``.
    """
    import numba
    from threadpoolctl import threadpool_limits

    affinity = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    threads = numba.get_num_threads()
    handler = mujoco.get_mju_user_warning()
    cpu = None
    try:
        if affinity:
            cpu = min(affinity)
            os.sched_setaffinity(0, {cpu})
        numba.set_num_threads(1)
        mujoco.set_mju_user_warning(WARNINGS.append)
        with threadpool_limits(limits=1):
            yield cpu
    finally:
        mujoco.set_mju_user_warning(handler)
        numba.set_num_threads(threads)
        if affinity:
            os.sched_setaffinity(0, affinity)


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def run(args: argparse.Namespace, mujoco: Any) -> dict[str, Any]:
    """The search, the damping check and the interleaved timing; the result dict."""
    WARNINGS.clear()
    load_before = os.getloadavg()
    g = preset(STANDARD["preset"])
    T = float(args.duration_s)
    with one_core(mujoco) as cpu:
        print("our standard trial at the default rod (warm-up) ...", file=sys.stderr)
        default = physics_benchmark(duration_s=T, repeats=1, measure_memory=False)
        reference_hz = reference_first_mode_hz(g)
        print(
            f"peak-moment reference: {PEAK_REFERENCE['n_elements']} elements, "
            f"{PEAK_REFERENCE['dt_s'] * 1e6:g} us steps ...",
            file=sys.stderr,
        )
        reference_peak = reference_peak_moment_nm(T)
        print(
            f"reference first mode {reference_hz:.4f} Hz; reference peak follicle moment "
            f"{reference_peak * 1e3:.4f} mN m",
            file=sys.stderr,
        )
        t0 = time.perf_counter()
        mine = our_search(g, T, reference_hz, reference_peak)
        if mine["accepted"] is None:
            raise SystemExit("error: no element count of our rod met both accuracy criteria")
        our_model = RodModel(g, mine["accepted"]["n_elements"])
        alpha, beta_s, _ = our_model.damping
        if alpha != 0.0:
            raise SystemExit(
                f"error: {g.name} needs mass-proportional damping, which the "
                "MuJoCo chain does not model"
            )
        setup = Setup(
            mujoco=mujoco,
            geometry=g,
            beta_shaft_s=beta_s,
            duration_s=T,
            path=pole_path(T),
            reference_hz=reference_hz,
            reference_peak_nm=reference_peak,
            vibrissa_n_elements=our_model.n_elements,
            ring_down_s=1.0 if args.quick else 2.0,
        )
        links, steps = quick_candidates(setup) if args.quick else (LINKS, TIME_STEPS_S)
        print(
            f"searching {links[0]}-{links[-1]} links, steps {steps[0] * 1e6:g}-"
            f"{steps[-1] * 1e6:g} us ...",
            file=sys.stderr,
        )
        found = search(setup, links, steps)
        search_s = time.perf_counter() - t0
        best = found["accepted"]
        if best is None:
            raise SystemExit("error: no MuJoCo configuration met both accuracy criteria")
        whisker = MujocoWhisker(mujoco, g, best["links"], best["dt_s"], beta_shaft_s=beta_s)
        _, zeta, _ = ring_down(whisker, 2.0, damped=True)
        planar = MujocoWhisker(
            mujoco, g, best["links"], best["dt_s"], beta_shaft_s=beta_s, planar=True
        )
        planar_peak, planar_stable, _ = contact_run(planar, T, setup.path)
        if not planar_stable:
            raise SystemExit("error: the planar MuJoCo chain is unstable at the accepted step")
        print(f"timing {args.repeats}x interleaved ...", file=sys.stderr)
        timing = time_interleaved(setup, whisker, args.repeats, planar=planar)
    ours = mine["accepted"]
    default_f1 = float(RodModel(g, default["n_elements"]).natural_frequencies_hz[0])
    return {
        "vibrissa_rtf": timing["vibrissa_rtf"],
        "mujoco_rtf": timing["mujoco_rtf"],
        "ratio": timing["vibrissa_rtf"] / timing["mujoco_rtf"],
        "mujoco_links": best["links"],
        "mujoco_dt_s": best["dt_s"],
        "mujoco_first_mode_error_pct": best["first_mode_error_pct"],
        "reference_first_mode_hz": setup.reference_hz,
        "reference_peak_follicle_moment_nm": setup.reference_peak_nm,
        "peak_reference": dict(PEAK_REFERENCE),
        "mujoco_first_mode_hz": best["first_mode_hz"],
        "vibrissa_first_mode_hz": ours["first_mode_hz"],
        "vibrissa_first_mode_error_pct": ours["first_mode_error_pct"],
        "vibrissa_peak_follicle_moment_nm": ours["peak_follicle_moment_nm"],
        "vibrissa_peak_moment_error_pct": ours["peak_moment_error_pct"],
        "vibrissa_search": mine["rows"],
        "vibrissa_default_n_elements": default["n_elements"],
        "vibrissa_default_first_mode_error_pct": _pct(default_f1, setup.reference_hz),
        "vibrissa_default_peak_moment_error_pct": _pct(
            default["peak_follicle_moment_nm"], setup.reference_peak_nm
        ),
        "mujoco_peak_follicle_moment_nm": best["peak_follicle_moment_nm"],
        "mujoco_peak_moment_error_pct": best["peak_moment_error_pct"],
        "mujoco_max_penetration_m": best["max_penetration_m"],
        "damping_ratio": g.damping_ratio,
        "mujoco_first_mode_damping_ratio": zeta,
        "mujoco_follicle_damping_nm_s_per_rad": whisker.follicle_damping,
        "mujoco_planar_rtf": timing["mujoco_planar_rtf"],
        "ratio_planar": timing["vibrissa_rtf"] / timing["mujoco_planar_rtf"],
        "mujoco_planar_peak_follicle_moment_nm": planar_peak,
        "mujoco_planar_peak_moment_error_pct": _pct(planar_peak, setup.reference_peak_nm),
        "mujoco_planar_wall_seconds_all": timing["mujoco_planar_wall_seconds_all"],
        "mujoco_version": mujoco.__version__,
        "vibrissa_version": __version__,
        "vibrissa_n_elements": timing["vibrissa_n_elements"],
        "vibrissa_dt_s": timing["vibrissa_dt_s"],
        "vibrissa_wall_seconds_all": timing["vibrissa_wall_seconds_all"],
        "mujoco_wall_seconds_all": timing["mujoco_wall_seconds_all"],
        "repeats": args.repeats,
        "duration_s": T,
        "quick": bool(args.quick),
        "search": found["rows"],
        "search_seconds": search_s,
        "mujoco_warnings": len(WARNINGS),
        "criteria": {
            "first_mode_tolerance_pct": FIRST_MODE_TOLERANCE_PCT,
            "moment_tolerance_pct": MOMENT_TOLERANCE_PCT,
            "reference": "Hermite finite elements of the tapered Euler-Bernoulli beam "
            f"({REFERENCE_ELEMENTS} elements) on the follicle's spring and inertia",
            "peak_moment_reference": f"our rod converged: {PEAK_REFERENCE['n_elements']} "
            f"elements, {PEAK_REFERENCE['dt_s'] * 1e6:g} us steps, every step nonlinear",
            "applies_to": "both simulators, each at its cheapest accepted setting",
        },
        "mujoco_settings": {
            "integrator": "Euler (semi-implicit; joint damping implicit)",
            "cone": "elliptic",
            "condim": 3,
            "solref": [2 * best["dt_s"], 1.0],
            "solimp": "default (0.9, 0.95, 0.001, 0.5, 2)",
            "friction": STANDARD["friction"],
            "pole": f"capsule on a slide joint, {POLE_MASS_KG:g} kg, velocity set to the "
            "trajectory's",
            "threads": 1,
        },
        "scenario": dict(STANDARD, duration_s=T),
        "machine": {
            "python": platform.python_version(),
            "machine": platform.machine(),
            "cpu": _cpu_model(),
            "cpu_count": os.cpu_count(),
            "pinned_cpu": cpu,
            "load_average_before": list(load_before),
            "load_average_after": list(os.getloadavg()),
        },
        "command": " ".join(["python benchmarks/bench_peers.py", *args.argv]),
        "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }


def table(result: dict[str, Any]) -> str:
    """The result as readable text."""
    r = result
    lines = [
        "Our rod (elements at the standard step, first mode against the beam reference, "
        "peak follicle moment against the converged rod):",
        f"  {'elements':>8} {'first mode (Hz)':>16} {'error %':>8} {'peak (mN m)':>12} "
        f"{'error %':>8}  accepted",
    ]
    for row in r["vibrissa_search"]:
        p = row["peak_follicle_moment_nm"]
        lines.append(
            f"  {row['n_elements']:>8} {row['first_mode_hz']:>16.4f} "
            f"{row['first_mode_error_pct']:>+8.3f} "
            + (
                f"{p * 1e3:>12.4f} {row['peak_moment_error_pct']:>+8.2f}"
                if p
                else f"{'-':>12} {'-':>8}"
            )
            + f"  {'yes' if row['accepted'] else ''}"
        )
    lines += [
        "MuJoCo (links, step, first mode against the beam reference, peak follicle moment "
        "against the converged rod):",
        f"  {'links':>5} {'dt (us)':>8} {'first mode (Hz)':>16} {'error %':>8} "
        f"{'peak (mN m)':>12} {'error %':>8}  stable accepted",
    ]
    for row in r["search"]:
        f = row["first_mode_hz"]
        p = row["peak_follicle_moment_nm"]
        lines.append(
            f"  {row['links']:>5} {row['dt_s'] * 1e6:>8.1f} "
            + (f"{f:>16.4f} {row['first_mode_error_pct']:>+8.3f} " if f else f"{'-':>16} {'-':>8} ")
            + (
                f"{p * 1e3:>12.4f} {row['peak_moment_error_pct']:>+8.2f}"
                if p
                else f"{'-':>12} {'-':>8}"
            )
            + f"  {'yes' if row['stable'] else 'no':>6} {'yes' if row['accepted'] else '':>8}"
        )
    lines += [
        "",
        f"reference first mode (beam)     {r['reference_first_mode_hz']:.4f} Hz",
        f"ours: first mode                {r['vibrissa_first_mode_hz']:.4f} Hz "
        f"({r['vibrissa_first_mode_error_pct']:+.3f} %), {r['vibrissa_n_elements']} elements, "
        f"dt {r['vibrissa_dt_s'] * 1e6:g} us (the default rod, "
        f"{r['vibrissa_default_n_elements']} elements: first mode "
        f"{r['vibrissa_default_first_mode_error_pct']:+.3f} %, peak moment "
        f"{r['vibrissa_default_peak_moment_error_pct']:+.2f} %)",
        f"MuJoCo {r['mujoco_version']}: first mode     {r['mujoco_first_mode_hz']:.4f} Hz "
        f"({r['mujoco_first_mode_error_pct']:+.3f} %), {r['mujoco_links']} links, "
        f"dt {r['mujoco_dt_s'] * 1e6:g} us",
        f"peak follicle moment            reference "
        f"{r['reference_peak_follicle_moment_nm'] * 1e3:.4f} mN m; ours "
        f"{r['vibrissa_peak_follicle_moment_nm'] * 1e3:.4f} mN m "
        f"({r['vibrissa_peak_moment_error_pct']:+.2f} %), MuJoCo "
        f"{r['mujoco_peak_follicle_moment_nm'] * 1e3:.4f} mN m "
        f"({r['mujoco_peak_moment_error_pct']:+.2f} %)",
        f"MuJoCo's deepest penetration    {r['mujoco_max_penetration_m'] * 1e6:.1f} um",
        f"first-mode damping ratio        target {r['damping_ratio']:g}, MuJoCo ring-down "
        f"{r['mujoco_first_mode_damping_ratio']:.4f}",
        f"real-time factor (best of {r['repeats']})   ours {r['vibrissa_rtf']:.1f}, MuJoCo "
        f"{r['mujoco_rtf']:.1f}; ratio {r['ratio']:.2f}",
        f"MuJoCo planar (y hinges only)   peak follicle moment "
        f"{r['mujoco_planar_peak_follicle_moment_nm'] * 1e3:.4f} mN m "
        f"({r['mujoco_planar_peak_moment_error_pct']:+.2f} %), real-time factor "
        f"{r['mujoco_planar_rtf']:.1f}; ratio {r['ratio_planar']:.2f}",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    args = parse_args(argv)
    try:
        import mujoco
    except ModuleNotFoundError:
        print(INSTALL_HINT, file=sys.stderr)
        return 2
    except ImportError as exc:  # e.g. a 3.x install upgraded in place to 4.x
        print(
            f"error: mujoco is installed but cannot be imported: {' '.join(str(exc).split())}",
            file=sys.stderr,
        )
        return 2
    result = run(args, mujoco)
    text = json.dumps(result, indent=1) + "\n"
    if args.out is not None:
        atomic_write_text(args.out, text)
        print(f"wrote {args.out}", file=sys.stderr)
    print(text if args.json else table(result), end="" if args.json else "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
