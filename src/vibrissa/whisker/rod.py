"""The discrete elastic rod model of a whisker in its follicle, and its statics.

:class:`RodModel` turns a :class:`~vibrissa.whisker.geometry.WhiskerGeometry` into
the arrays the numba kernels work on (node positions, masses, bending and axial
stiffnesses, Rayleigh damping coefficients), computes natural frequencies from
the linearisation about rest, and solves static equilibria: a fixed-direction
point force (:meth:`RodModel.static_force`) and a pole pushed sideways through a
point (:meth:`RodModel.push`). Dynamics live in :mod:`vibrissa.whisker.simulate`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg
import scipy.optimize

from vibrissa._validate import finite, in_range, non_negative, positive
from vibrissa.whisker._kernels import (
    BW,
    NO_CONTACT,
    POLE,
    Anchors,
    ContactSpec,
    Damping,
    RodArrays,
    add_internal,
    commit_anchors,
    solve_static,
)
from vibrissa.whisker.geometry import WhiskerGeometry

__all__ = ["PushResult", "RodModel", "StaticResult", "DEFAULT_N_ELEMENTS"]

#: Elements along the free shaft. Chosen by the convergence study in docs/physics.md:
#: the first three natural frequencies are within 2 % of the converged values.
DEFAULT_N_ELEMENTS = 28

_AXIAL_FOLLICLE_FACTOR = 10.0

#: How the shaft's mass can be put on the nodes (see :class:`RodModel`).
MASS_KINDS = ("lumped", "consistent")

#: Presliding distance of the elasto-plastic friction model (m): the tangential
#: elastic displacement at which a stuck contact starts to slip. A few micrometres,
#: the order of contact asperity deformation; small against the grains of the
#: thesis' sandpapers (26-201 um) so texture stick-slip is resolved.
PRESLIDING_DISTANCE_M = 2.0e-6  # the in-follicle shaft is 10x stiffer axially than the base


class SimulationError(RuntimeError):
    """Raised when a solver fails to converge or produces non-finite values."""


@dataclass(frozen=True)
class StaticResult:
    """Static equilibrium under a fixed-direction point force.

    Attributes
    ----------
    base_moment_nm
        Magnitude of the bending moment at the whisker base (N m).
    deflection_mm
        Sideways (x) displacement of the loaded material point (mm).
    axial_shortening_mm
        Displacement of the loaded point toward the base along the rest axis (mm).
    base_angle_deg
        Rotation of the follicle (magnet) about the pivot (deg); 0 for a rigid follicle.
    tan_x, tan_y
        Tangents of the magnet's two tilt angles (what the Hall sensor reads).
    positions_m
        Node positions at equilibrium, shape (n_nodes, 3).
    """

    base_moment_nm: float
    deflection_mm: float
    axial_shortening_mm: float
    base_angle_deg: float
    tan_x: float
    tan_y: float
    positions_m: np.ndarray


@dataclass(frozen=True)
class PushResult:
    """Quasi-static equilibrium of a whisker pushed sideways by a thin pole.

    Attributes
    ----------
    base_moment_nm
        Magnitude of the bending moment at the whisker base (N m).
    base_force_n
        Magnitude of the contact force, equal to the force at the base (N).
    contact_arc_length_mm
        Arc length from the base at which the pole touches the whisker (mm).
    slipped_off
        True if the whisker slid off the pole's end (past the tip).
    tan_x, tan_y
        Tangents of the magnet's tilt angles.
    normal_force_n, friction_force_n
        Components of the contact force normal and tangential to the whisker (N).
    positions_m
        Node positions at equilibrium, shape (n_nodes, 3).
    contact_y_mm, pole_y_mm
        Displacement along the pole's axis (y) of the whisker's contact point and of
        the pole (equal while the contact sticks).
    """

    base_moment_nm: float
    base_force_n: float
    contact_arc_length_mm: float
    slipped_off: bool
    tan_x: float
    tan_y: float
    normal_force_n: float
    friction_force_n: float
    positions_m: np.ndarray
    contact_y_mm: float = 0.0
    pole_y_mm: float = 0.0


class RodModel:
    """A whisker discretised as a chain of nodes with bending and stretching springs.

    Parameters
    ----------
    geometry
        Whisker geometry and material.
    n_elements
        Number of elements along the free shaft (>= 4).
    rigid_follicle
        If True the base is clamped (the follicle does not rotate).
    mass
        How the shaft's mass is put on the nodes: ``"consistent"`` (the default: the
        kinetic energy of each segment with its velocity interpolated linearly between
        its nodes, integrated exactly over the truncated cone, a tridiagonal mass
        matrix) or ``"lumped"`` (each segment's mass split half and half onto its two
        nodes, the rod's mass until issue 32). The xy-robot whisker's first mode comes
        within 0.1 % of the beam reference at 8 consistent elements, 40 lumped ones.
        The follicle's inertia is lumped on the base node in both.
        ``benchmarks/rod_convergence.py`` measures what each costs in elements.

    Notes
    -----
    Node 0 is the follicle pivot, node 1 the base of the free shaft (the origin),
    node ``n_elements + 1`` the tip. See :mod:`vibrissa.whisker._kernels` for the
    energies and ``docs/physics.md`` for the validation against beam theory.
    """

    def __init__(
        self,
        geometry: WhiskerGeometry | None = None,
        n_elements: int = DEFAULT_N_ELEMENTS,
        rigid_follicle: bool = False,
        mass: str = "consistent",
    ) -> None:
        self.geometry = geometry if geometry is not None else WhiskerGeometry(name="xy-robot")
        if isinstance(n_elements, bool) or not isinstance(n_elements, int | np.integer):
            raise TypeError(f"n_elements must be an integer, got {n_elements!r}")
        if n_elements < 4 or n_elements > 400:
            raise ValueError(f"n_elements must lie in [4, 400], got {n_elements}")
        self.n_elements = int(n_elements)
        if mass not in MASS_KINDS:
            raise ValueError(f"mass must be one of {MASS_KINDS}, got {mass!r}")
        self.rigid_follicle = bool(rigid_follicle)
        self.mass_kind = mass
        self._build()

    # ------------------------------------------------------------------ building
    def _build(self) -> None:
        g = self.geometry
        ne = self.n_elements
        n = ne + 2
        L = g.length_m
        h = L / ne
        d = g.follicle_depth_mm * 1e-3
        E = g.youngs_modulus_gpa * 1e9
        s = np.empty(n)
        s[0] = -d
        s[1:] = np.arange(ne + 1) * h
        x = np.zeros((n, 3))
        x[:, 2] = s
        radius = g.radius_m(np.clip(s, 0.0, L))
        L0 = np.diff(s)
        r_mid = g.radius_m(0.5 * (np.clip(s[:-1], 0, L) + s[1:]))
        EA = E * math.pi * r_mid**2
        EA[0] = _AXIAL_FOLLICLE_FACTOR * E * math.pi * radius[1] ** 2
        EI = E * math.pi * radius**4 / 4.0
        kb = np.zeros(n)
        kb[1] = EI[1] / (2.0 * (0.5 * h))  # clamped end: half Voronoi length
        kb[2 : n - 1] = EI[2 : n - 1] / (2.0 * h)
        mass, mass_off = _segment_masses(
            radius[1:-1], radius[2:], h, g.density_kg_m3, self.mass_kind
        )
        m_fol = g.follicle_inertia_kg_m2 / d**2
        mass[0] = m_fol
        mass[1] += m_fol
        free = np.ones(n, dtype=np.bool_)
        free[0] = False
        if self.rigid_follicle:
            free[1] = False
        self.n_nodes = n
        self.element_length_m = h
        self.s_rest = s
        self.x_rest = x
        self.radius = radius
        self.L0 = L0
        self.EA = EA
        self.EI = EI
        self.kb = kb
        self.kf = g.follicle_stiffness_nm_per_rad
        self.axis = np.array([0.0, 0.0, 1.0])
        self.mass = mass
        self.mass_off = mass_off
        self.free = free

    def rod_arrays(self) -> RodArrays:
        """The model's arrays bundled for the numba kernels.

        Returns
        -------
        RodArrays
            Node mask ``free``, bending constants ``kb`` (N m), follicle stiffness
            ``kf`` (N m/rad) and rest ``axis``, edge rest lengths ``L0`` (m) and axial
            rigidities ``EA`` (N), the mass matrix's diagonal ``mass`` and the
            couplings ``mass_off`` of consecutive nodes (kg), radii (m) and rest arc lengths
            ``s_rest`` (m). The arrays are the model's own (not copies), read when
            this is called: rebuild the bundle after replacing an attribute.
        """
        return RodArrays(
            free=self.free,
            kb=self.kb,
            kf=float(self.kf),
            axis=self.axis,
            L0=self.L0,
            EA=self.EA,
            mass=self.mass,
            mass_off=self.mass_off,
            radius=self.radius,
            s_rest=self.s_rest,
        )

    # ------------------------------------------------------------------ linearisation
    def stiffness_matrix(self, x: np.ndarray | None = None) -> np.ndarray:
        """Dense tangent stiffness matrix (3n x 3n) at positions ``x`` (default: rest)."""
        return _dense_stiffness(self.rod_arrays(), self.x_rest if x is None else x)

    def node_mass_matrix(self) -> np.ndarray:
        """The mass matrix over the nodes (n x n, kg), the same in each direction.

        Tridiagonal for the consistent mass, diagonal for the lumped one; the
        kinetic energy of node velocities ``v`` (n, 3) is ``1/2 sum_c v[:, c] M v[:, c]``.
        """
        off = self.mass_off
        return np.diag(self.mass) + np.diag(off, 1) + np.diag(off, -1)

    def _plane_modes(self) -> tuple[np.ndarray, np.ndarray]:
        K = self.stiffness_matrix()
        idx = np.array([3 * i for i in range(self.n_nodes) if self.free[i]])
        Kx = K[np.ix_(idx, idx)]
        nodes = idx // 3
        Mx = self.node_mass_matrix()[np.ix_(nodes, nodes)]
        w2, vecs = scipy.linalg.eigh(0.5 * (Kx + Kx.T), Mx)
        return np.sqrt(np.clip(w2, 0.0, None)), vecs

    @cached_property
    def natural_frequencies_hz(self) -> np.ndarray:
        """Bending natural frequencies (Hz) in one plane, from the linearisation at rest."""
        w, _ = self._plane_modes()
        return w / (2 * math.pi)

    def pinned_frequencies_hz(self, at_mm: float, n_modes: int = 3) -> np.ndarray:
        """Bending frequencies (Hz) of the whisker with its point ``at_mm`` pinned.

        The linearised whisker (one bending plane, follicle spring included) with
        the lateral displacement of the material point ``at_mm`` held at zero, as by
        an object pressed against it: a pole at that radial distance, or a surface
        under the tip (``at_mm`` = the length). The constraint is imposed exactly, by
        projecting onto its null space.
        """
        K = self.stiffness_matrix()
        nodes = np.array([i for i in range(self.n_nodes) if self.free[i]])
        idx = 3 * nodes
        Kx = K[np.ix_(idx, idx)]
        Kx = 0.5 * (Kx + Kx.T)
        M = self.node_mass_matrix()[np.ix_(nodes, nodes)]
        j, u = self.locate(at_mm)
        c = np.zeros(nodes.size)
        where = {int(n): k for k, n in enumerate(nodes)}
        if j in where:
            c[where[j]] += 1.0 - u
        c[where[j + 1]] += u
        Z = scipy.linalg.null_space(c[None, :])
        w2 = scipy.linalg.eigh(Z.T @ Kx @ Z, Z.T @ M @ Z, eigvals_only=True)
        return np.sqrt(np.clip(w2[:n_modes], 0.0, None)) / (2 * math.pi)

    def _plane_matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Shaft stiffness, follicle stiffness and mass in one bending plane (free DOFs)."""
        rod = self.rod_arrays()
        K = _dense_stiffness(rod, self.x_rest)
        Kf = _dense_stiffness(rod._replace(kb=np.zeros_like(rod.kb)), self.x_rest)
        idx = np.array([3 * i for i in range(self.n_nodes) if self.free[i]])
        Kx = K[np.ix_(idx, idx)]
        Kfx = Kf[np.ix_(idx, idx)]
        nodes = idx // 3
        return Kx - Kfx, Kfx, self.node_mass_matrix()[np.ix_(nodes, nodes)]

    def modal_damping(
        self, alpha: float, beta_shaft: float, beta_follicle: float, n_modes: int = 3
    ) -> tuple[np.ndarray, np.ndarray]:
        """Damping ratios and damped frequencies (Hz) of the first modes in one plane."""
        Ks, Kf, M = self._plane_matrices()
        n = M.shape[0]
        K = Ks + Kf
        C = beta_shaft * Ks + beta_follicle * Kf + alpha * M
        Minv = np.linalg.inv(M)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
        lam = np.linalg.eigvals(A)
        lam = lam[np.imag(lam) > 1e-9]
        lam = lam[np.argsort(np.abs(lam))][:n_modes]
        return -lam.real / np.abs(lam), np.abs(lam.imag) / (2 * math.pi)

    @cached_property
    def damping(self) -> tuple[float, float, float]:
        """Damping coefficients (alpha 1/s, beta_shaft s, beta_follicle s).

        The shaft gets stiffness-proportional material damping with damping ratio
        ``material_damping_ratio`` at 100 Hz. The follicle's rubber damper (damping
        moment ``k_f beta_follicle dpsi/dt``) is then set, by root finding on the
        damped eigenvalues of the linearised whisker, so that the first mode has
        ``damping_ratio``. If the follicle cannot provide that much (a stiff follicle
        barely moves in the first mode; always the case for a rigid follicle), the
        follicle damper is set at its most effective value and mass-proportional
        damping (air drag, alpha) makes up the rest.
        """
        g = self.geometry
        beta_s = 2.0 * g.material_damping_ratio / (2 * math.pi * 100.0)
        target = g.damping_ratio
        w1 = 2 * math.pi * self.natural_frequencies_hz[0]

        def z1(bf: float, alpha: float = 0.0) -> float:
            zetas = self.modal_damping(alpha, beta_s, bf, 1)[0]
            return float(zetas[0]) if zetas.size else 1.0  # no oscillation: overdamped

        base = z1(0.0)
        if base >= 1.0:
            raise ValueError(
                f"the whisker's first bending mode ({w1 / (2 * math.pi):.4g} Hz) is "
                "overdamped by the shaft's own material damping (material_damping_ratio "
                f"{g.material_damping_ratio:g} at 100 Hz, growing with frequency), so it "
                "cannot ring: use a lower youngs_modulus_gpa, a higher density_kg_m3 or a "
                "longer, thinner whisker"
            )
        if target <= base:
            return 0.0, beta_s, 0.0
        best_bf = 0.0
        if not self.rigid_follicle:
            grid = np.geomspace(1e-5, 1.0, 41)
            zs = np.array([z1(b) for b in grid])
            k = int(np.argmax(zs))
            if zs[k] >= target:
                lo = grid[k - 1] if k > 0 else 0.0
                for j in range(k + 1):
                    if zs[j] >= target:
                        lo = grid[j - 1] if j > 0 else 0.0
                        hi = grid[j]
                        break
                bf = float(scipy.optimize.brentq(lambda b: z1(b) - target, lo, hi, xtol=1e-12))
                return 0.0, beta_s, bf
            best_bf = float(grid[k])
        # make up the rest with mass-proportional damping
        hi = 2.0 * target * w1 * 4
        alpha = float(scipy.optimize.brentq(lambda a: z1(best_bf, a) - target, 0.0, hi, xtol=1e-10))
        return alpha, beta_s, best_bf

    # ------------------------------------------------------------------ helpers
    def locate(self, at_mm: float) -> tuple[int, float]:
        """Segment index ``j`` and fraction ``u`` of the material point ``at_mm`` from the base."""
        a = finite("at_mm", at_mm)
        if not 0.0 < a <= self.geometry.length_mm:
            raise ValueError(
                f"at_mm must lie in (0, {self.geometry.length_mm}] mm (the whisker's length), "
                f"got {at_mm}"
            )
        pos = a * 1e-3 / self.element_length_m
        j = min(int(pos), self.n_elements - 1)
        u = pos - j
        return j + 1, u

    def base_moment(self, x: np.ndarray, forces: np.ndarray) -> np.ndarray:
        """Moment vector (N m) about the base of external ``forces`` (n, 3) at positions ``x``."""
        r = x - x[1]
        return np.cross(r[2:], forces[2:]).sum(axis=0) + np.cross(r[1], forces[1])

    def tan_angles(self, x: np.ndarray) -> tuple[float, float]:
        """Tangents of the magnet's tilt toward x and y at positions ``x``."""
        e0 = x[1] - x[0]
        return float(e0[0] / e0[2]), float(e0[1] / e0[2])

    def _static(
        self,
        x: np.ndarray,
        f_app: np.ndarray,
        contact: ContactSpec | None = None,
        tr: np.ndarray | None = None,
        anchors: Anchors | None = None,
        tol: float = 1e-11,
        max_iter: int = 60,
    ) -> tuple[int, np.ndarray]:
        """Newton solve of the static equilibrium from ``x`` (updated in place).

        ``contact`` defaults to none; ``tr`` is the contact object's state and
        ``anchors`` its friction state (a pole's first touch writes its anchor).
        Returns the iterations used (-1: no convergence) and the contact's ``info``.
        """
        info = np.zeros(12)
        contact = pole_contact_spec(np.zeros(5), NO_CONTACT) if contact is None else contact
        tr = np.zeros(6) if tr is None else tr
        if anchors is None:
            anchors = Anchors(np.zeros(5), np.zeros((self.n_nodes, 6)))
        it = solve_static(x, f_app, self.rod_arrays(), contact, tr, anchors, tol, max_iter, info)
        return it, info

    # ------------------------------------------------------------------ statics
    def static_force(
        self,
        force_n: float,
        at_mm: float,
        direction: tuple[float, float] = (1, 0),
    ) -> StaticResult:
        """Equilibrium under a fixed-direction point force perpendicular to the rest axis.

        Parameters
        ----------
        force_n
            Force magnitude (N); may be large (geometrically nonlinear solution).
        at_mm
            Material point where it acts, arc length from the base (mm).
        direction
            Direction of the force in the x-y plane (normalised).
        """
        F = finite("force_n", force_n)
        j, u = self.locate(at_mm)
        dvec = np.array([direction[0], direction[1], 0.0], dtype=float)
        if not np.all(np.isfinite(dvec)) or np.linalg.norm(dvec) == 0:
            raise ValueError(f"direction must be a non-zero finite 2-vector, got {direction}")
        dvec /= np.linalg.norm(dvec)
        x = self.x_rest.copy()
        # load stepping with adaptive increments
        done = 0.0
        step = 1.0
        while done < 1.0:
            frac = min(1.0, done + step)
            f_app = np.zeros((self.n_nodes, 3))
            f_app[j] = (1 - u) * F * frac * dvec
            f_app[j + 1] = u * F * frac * dvec
            trial = x.copy()
            it, _ = self._static(trial, f_app)
            if it < 0:
                step *= 0.5
                if step < 1e-4:
                    raise SimulationError(
                        f"static solve did not converge beyond {done * F:.4g} N of "
                        f"force_n={force_n} at at_mm={at_mm}"
                    )
                continue
            x = trial
            done = frac
            step = min(1.0, step * 1.5)
        _check_finite(x)
        f_app = np.zeros((self.n_nodes, 3))
        f_app[j] = (1 - u) * F * dvec
        f_app[j + 1] = u * F * dvec
        M = self.base_moment(x, f_app)
        p = (1 - u) * x[j] + u * x[j + 1]
        p0 = (1 - u) * self.x_rest[j] + u * self.x_rest[j + 1]
        tx, ty = self.tan_angles(x)
        return StaticResult(
            base_moment_nm=float(np.linalg.norm(M)),
            deflection_mm=float(np.dot(p - p0, dvec) * 1e3),
            axial_shortening_mm=float((p0[2] - p[2]) * 1e3),
            base_angle_deg=float(np.degrees(np.arctan(math.hypot(tx, ty)))),
            tan_x=tx,
            tan_y=ty,
            positions_m=x,
        )

    def push(
        self,
        at_mm: float,
        displacement_mm: float,
        friction: float = 0.0,
        pole_radius_mm: float = 0.5,
        n_increments: int | None = None,
        contact_stiffness_n_m: float = 2e4,
        direction_deg: float = 0.0,
    ) -> PushResult:
        """Quasi-static push of a thin pole (parallel to y) through the whisker.

        The pole first touches the undeformed whisker at ``at_mm`` from the base on
        its -x side and is moved ``displacement_mm`` along +x in small increments;
        friction anchors are carried from one increment to the next, so the result
        follows the loading path (stick until the friction cone is exceeded, then slip).

        Parameters
        ----------
        at_mm
            Radial distance of first contact (mm), in (0, length].
        displacement_mm
            Sideways displacement of the pole (mm), >= 0.
        friction
            Coulomb friction coefficient, >= 0.
        pole_radius_mm
            Radius of the pole (mm).
        n_increments
            Load increments (default: one per 0.25 mm, at least 20).
        contact_stiffness_n_m
            Penalty stiffness of the contact (N/m).
        direction_deg
            Direction of the pole's motion, measured from +x (perpendicular to the
            shaft) toward +y (along the pole's own axis), in [-80, 80] degrees. The
            y component is resisted by friction alone: since the whisker bends equally
            easily in x and y, the contact sticks (the whisker follows the pole in y)
            while tan(direction) < friction, and slides along the pole once the
            friction cone is exceeded.
        """
        j, u = self.locate(at_mm)
        a_m = at_mm * 1e-3
        D = non_negative("displacement_mm", displacement_mm) * 1e-3
        mu = non_negative("friction", friction)
        rp = positive("pole_radius_mm", pole_radius_mm) * 1e-3
        if rp >= a_m:
            # the pole's edge would reach below the base, into the follicle and the face,
            # which the model does not contain; its one contact point is then meaningless
            raise ValueError(
                f"pole_radius_mm ({pole_radius_mm:g}) must be smaller than at_mm "
                f"({at_mm:g}): a larger pole reaches past the whisker's base"
            )
        kn = positive("contact_stiffness_n_m", contact_stiffness_n_m)
        beta = math.radians(in_range("direction_deg", direction_deg, -80.0, 80.0, "deg"))
        ux, uy = math.cos(beta), math.sin(beta)
        if n_increments is None:
            n_increments = max(20, int(math.ceil(D / 0.25e-3)))
        a = at_mm * 1e-3
        r_here = float(self.geometry.radius_m(a))
        px0 = -(rp + r_here)
        contact = pole_contact_spec(np.array([rp, kn, 0.0, mu, PRESLIDING_DISTANCE_M]))
        anchor = np.zeros(5)
        x = self.x_rest.copy()
        info = np.zeros(12)
        released = False
        s_converged = a
        for k in range(1, n_increments + 1):
            tr = np.array(
                [px0 + ux * D * k / n_increments, a, 0.0, 0.0, uy * D * k / n_increments, 0.0]
            )
            trial = x.copy()
            sub = 1
            while True:
                ok = True
                xs = x.copy()
                anc = Anchors(anchor.copy(), np.zeros((self.n_nodes, 6)))
                prev = D * (k - 1) / n_increments
                for m in range(1, sub + 1):
                    dk = prev + (D / n_increments) * m / sub
                    tr[0] = px0 + ux * dk
                    tr[4] = uy * dk
                    it, info = self._static(
                        xs, np.zeros((self.n_nodes, 3)), contact, tr.copy(), anc
                    )
                    if it < 0:
                        ok = False
                        break
                    commit_anchors(POLE, info, anc)
                if ok:
                    trial, anchor = xs, anc.pole
                    break
                sub *= 2
                if sub > 64:
                    if info[1] >= self.geometry.length_m * (1 - 1e-6):
                        # the tip is at the pole and equilibrium is lost: the whisker
                        # slips off the pole's end and springs back (it lands beyond
                        # the pole, which the remaining increments then never touch); with
                        # no load its equilibrium is the rest shape, where Newton starts
                        xs = self.x_rest.copy()
                        it, info = self._static(xs, np.zeros((self.n_nodes, 3)))
                        if it < 0:
                            raise SimulationError("whisker failed to spring back after slip-off")
                        info[1] = self.geometry.length_m
                        info[3] = 1.0
                        info[0] = info[7] = info[8] = info[10] = 0.0
                        anchor = np.zeros(5)
                        released = True
                        trial = xs
                        break
                    # the usual reason: the pole reaches the shaft elsewhere (it is too
                    # large for one contact point); say so when the last converged shape
                    # lies within two increments of it away from the contact
                    self._check_single_contact(
                        x,
                        px0 + ux * prev,
                        a,
                        rp,
                        s_converged,
                        pole_radius_mm,
                        prev,
                        clearance_m=2 * D / n_increments,
                    )
                    raise SimulationError(
                        f"push did not converge at displacement {D * k / n_increments * 1e3:.2f} mm"
                    )
            x = trial
            if released:
                break
            s_converged = info[1]
            self._check_single_contact(
                x, tr[0], a, rp, s_converged, pole_radius_mm, D * k / n_increments
            )
        _check_finite(x)
        fvec = np.array([info[7], info[10], info[8]])
        s_c = info[1]
        jj, uu = self._segment_of(s_c)
        q = (1 - uu) * x[jj] + uu * x[jj + 1]
        M = float(np.linalg.norm(np.cross(q - x[1], fvec)))
        fn = info[0]
        force = float(np.linalg.norm(fvec))
        in_contact = info[3] < 0.0
        slipped = released or ((not in_contact) and s_c >= self.geometry.length_m * (1 - 1e-9))
        tx, ty = self.tan_angles(x)
        return PushResult(
            base_moment_nm=M,
            base_force_n=float(force),
            contact_arc_length_mm=float(s_c * 1e3),
            slipped_off=bool(slipped),
            tan_x=tx,
            tan_y=ty,
            normal_force_n=float(fn),
            friction_force_n=float(math.sqrt(max(force**2 - fn**2, 0.0))),
            positions_m=x,
            contact_y_mm=float(q[1] * 1e3),
            pole_y_mm=float(tr[4] * 1e3),
        )

    def _check_single_contact(
        self,
        x: np.ndarray,
        pole_x_m: float,
        pole_z_m: float,
        pole_radius_m: float,
        contact_s_m: float,
        pole_radius_mm: float,
        displacement_m: float,
        clearance_m: float = 0.0,
    ) -> None:
        """Refuse a push whose pole touches the whisker away from the modelled contact.

        The model resolves one contact point per object. A pole whose radius is large
        for the push (a near-flat wall) reaches the shaft away from that point, or the
        base itself: the whisker would wrap around it, which one contact point cannot
        represent, and the result (for instance a base moment of zero with the pole
        pressing on the base) would be wrong. Every node outside the contact's own
        element must stay at least ``clearance_m`` from the pole's surface (0 for a
        converged state; two load increments when explaining a failed one: the next
        increments bring those nodes into the pole).
        """
        near = np.abs(self.s_rest - contact_s_m) < self.element_length_m
        # the follicle's anchor node (inside the body) is never a contact point
        far = ~near | (self.s_rest < 0.0)
        gap = np.hypot(x[:, 0] - pole_x_m, x[:, 2] - pole_z_m) - pole_radius_m - self.radius
        hit = far & (gap < clearance_m)
        if np.any(hit & (self.s_rest <= 0.0)):
            raise ValueError(
                f"pole_radius_mm={pole_radius_mm:g}: after {displacement_m * 1e3:.3g} mm of "
                "the push the pole reaches the whisker's base (the follicle); a pole this "
                "large is a wall, which the model's one contact point per object cannot "
                "represent, so use a smaller pole radius or displacement"
            )
        if np.any(hit):
            s_hit = np.clip(self.s_rest[hit], 0.0, None) * 1e3
            where = (
                f"{s_hit[0]:.3g} mm"
                if s_hit.size == 1
                else f"{s_hit.min():.3g}-{s_hit.max():.3g} mm"
            )
            raise ValueError(
                f"pole_radius_mm={pole_radius_mm:g}: after {displacement_m * 1e3:.3g} mm of "
                f"the push the pole also reaches the whisker {where} from the base, besides "
                f"the contact at {contact_s_m * 1e3:.3g} mm (it would wrap around a pole this "
                "large); the model resolves one contact point per object, so use a smaller "
                "pole radius or displacement"
            )

    def _segment_of(self, s_m: float) -> tuple[int, float]:
        pos = min(max(s_m / self.element_length_m, 0.0), self.n_elements)
        j = min(int(pos), self.n_elements - 1)
        return j + 1, pos - j

    # ------------------------------------------------------------------ energy
    def elastic_energy(self, x: np.ndarray) -> float:
        """Elastic energy (J) of positions ``x`` (stretching, bending and follicle)."""
        e = np.diff(x, axis=0)
        ln = np.linalg.norm(e, axis=1)
        E = float(np.sum(self.EA / (2 * self.L0) * (ln - self.L0) ** 2))
        t = e / ln[:, None]
        E += 0.5 * self.kf * float(np.sum((t[0] - self.axis) ** 2))
        d = t[1:] - t[:-1]
        E += float(np.sum(self.kb[1:-1] * np.sum(d * d, axis=1)))
        return E

    def kinetic_energy(self, v: np.ndarray) -> float:
        """Kinetic energy (J) of node velocities ``v`` (with the model's mass matrix)."""
        w = np.where(self.free[:, None], v, 0.0)
        Mw = self.mass[:, None] * w
        Mw[:-1] += self.mass_off[:, None] * w[1:]
        Mw[1:] += self.mass_off[:, None] * w[:-1]
        return float(0.5 * np.sum(w * Mw))


def _segment_masses(
    r_a: np.ndarray, r_b: np.ndarray, h: float, density: float, kind: str
) -> tuple[np.ndarray, np.ndarray]:
    """The shaft's node mass matrix: diagonal (n,) and consecutive-node couplings (n - 1,).

    Segment ``e`` (``e = 1 .. n - 2``) runs from node ``e`` (radius ``r_a[e - 1]``) to
    node ``e + 1`` (radius ``r_b[e - 1]``) with length ``h`` (m); the radius varies
    linearly along it (a truncated cone of ``density`` kg/m^3). With the velocity
    interpolated linearly between the nodes the segment's kinetic energy is
    ``1/2 [v_a v_b] M_e [v_a v_b]^T`` with, integrated exactly,

    ``M_e = rho pi h [[ra^2/5 + ra rb/10 + rb^2/30, ra^2/20 + ra rb/15 + rb^2/20],
    [..., ra^2/30 + ra rb/10 + rb^2/5]]``

    (``kind="consistent"``); ``"lumped"`` puts half the segment's mass on each node
    and couples nothing. Node 0 (the pivot) and edge 0 (the follicle) get nothing.
    """
    c = density * math.pi * h
    aa, ab, bb = r_a * r_a, r_a * r_b, r_b * r_b
    n = r_a.size + 2
    mass = np.zeros(n)
    off = np.zeros(n - 1)
    if kind == "consistent":
        mass[1:-1] += c * (aa / 5.0 + ab / 10.0 + bb / 30.0)
        mass[2:] += c * (aa / 30.0 + ab / 10.0 + bb / 5.0)
        off[1:] = c * (aa / 20.0 + ab / 15.0 + bb / 20.0)
    else:
        seg = c / 3.0 * (aa + ab + bb)
        mass[1:-1] += 0.5 * seg
        mass[2:] += 0.5 * seg
    return mass, off


def _check_finite(x: np.ndarray) -> None:
    if not np.all(np.isfinite(x)):
        raise SimulationError("the solver produced non-finite positions (diverged)")


def _dense_stiffness(rod: RodArrays, x: np.ndarray) -> np.ndarray:
    """Dense tangent stiffness matrix (3n x 3n, N/m) of ``rod`` at positions ``x`` (m)."""
    xx = np.array(x, dtype=float, order="C")
    n = xx.shape[0]
    F = np.zeros((n, 3))
    S = np.zeros((3 * n, 2 * BW + 1))
    add_internal(xx, np.zeros_like(xx), rod, Damping(0.0, 0.0, 0.0), F, S, 0.0, 1.0, True)
    K = np.zeros((3 * n, 3 * n))
    for r in range(3 * n):
        for off in range(-BW, BW + 1):
            c = r + off
            if 0 <= c < 3 * n:
                K[r, c] = S[r, BW + off]
    return K


def pole_contact_spec(params: np.ndarray, kind: int = POLE) -> ContactSpec:
    """A :class:`~vibrissa.whisker._kernels.ContactSpec` for a pole (or for no contact).

    Parameters
    ----------
    params : ndarray, shape (5,)
        Pole radius (m), normal penalty stiffness (N/m), approach damping (N s/m),
        Coulomb friction coefficient and presliding distance (m).
    kind : int
        The contact kind: ``POLE`` (default) or ``NO_CONTACT``.

    Returns
    -------
    ContactSpec
        With the plane-only fields set to neutral placeholders.
    """
    return ContactSpec(
        kind=int(kind),
        params=np.ascontiguousarray(params, dtype=float),
        frame=np.eye(3),
        heights=np.zeros((1, 1)),
        du=1.0,
        dw=1.0,
        first_node=2,
    )
