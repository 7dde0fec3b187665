"""Dynamic simulation of the whisker against a moving object.

The caller supplies a contact (:class:`PoleContact` or :class:`SurfaceContact`)
and the object's :class:`Trajectory` (position and velocity over time);
:func:`simulate` integrates the rod with the implicit generalised-alpha scheme
of :mod:`vibrissa.whisker._kernels` and returns the magnet's tilt, the contact
force and where along the whisker the contact is, at every internal step.
:meth:`SimulationResult.hall_volts` turns the tilt into sensor output.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from vibrissa._validate import finite, finite_array, in_range, non_negative, positive
from vibrissa.whisker._kernels import (
    BW,
    NO_CONTACT,
    PLANE,
    POLE,
    TR_BASE,
    Anchors,
    ContactSpec,
    Damping,
    NodeState,
    RodArrays,
    SolverSettings,
    add_internal_whisking,
    add_pole,
    first_possible_contact,
    interp_into,
    modal_advance,
    rcp_loop,
    run_dynamics,
    same_kernel_type,
)
from vibrissa.whisker.hall import HallSensor, calibrated_gain
from vibrissa.whisker.rod import (
    PRESLIDING_DISTANCE_M,
    RodModel,
    SimulationError,
    pole_contact_spec,
)
from vibrissa.whisker.surfaces import Surface

__all__ = [
    "BaseMotion",
    "ClosedLoopStepper",
    "PeriodOutput",
    "StepperKernelInputs",
    "rcp_loop",
    "same_kernel_type",
    "PoleContact",
    "SimulationResult",
    "SurfaceContact",
    "Trajectory",
    "free_vibration",
    "simulate",
]

DEFAULT_DT_S = 2.5e-4

#: Times (s) this close to a :class:`BaseMotion`'s end samples count as at them (far
#: below any step, far above the rounding of a running sum of steps).
TIME_TOL_S = 1e-9

_ENVELOPES: dict[tuple[int, float], tuple[Surface, np.ndarray]] = {}


def _tip_envelope(surface: Surface, tip_radius_m: float) -> np.ndarray:
    key = (id(surface), tip_radius_m)
    hit = _ENVELOPES.get(key)
    if hit is None or hit[0] is not surface:
        if len(_ENVELOPES) > 64:
            _ENVELOPES.clear()
        hit = (surface, surface.for_tip(tip_radius_m))
        _ENVELOPES[key] = hit
    return hit[1]


@dataclass(frozen=True)
class PoleContact:
    """A thin pole (or an object's corner) parallel to ``y``, moving in the x-z plane.

    Parameters
    ----------
    radius_mm
        Pole radius (mm).
    friction
        Coulomb friction coefficient between whisker and pole.
    stiffness_n_m
        Normal penalty stiffness of the contact (N/m).
    damping_n_s_m
        Normal contact damping, acting only while approaching (N s/m).
    presliding_distance_um
        Tangential elastic displacement before a stuck contact slips (um).
    """

    radius_mm: float = 0.5
    friction: float = 0.3
    stiffness_n_m: float = 2.0e4
    damping_n_s_m: float = 0.5
    presliding_distance_um: float = PRESLIDING_DISTANCE_M * 1e6

    def __post_init__(self) -> None:
        positive("radius_mm", self.radius_mm)
        positive("presliding_distance_um", self.presliding_distance_um)
        non_negative("friction", self.friction)
        positive("stiffness_n_m", self.stiffness_n_m)
        non_negative("damping_n_s_m", self.damping_n_s_m)


@dataclass(frozen=True)
class SurfaceContact:
    """A flat or textured plane that the whisker (chiefly its tip) touches.

    The plane contains the ``y`` axis direction; ``angle_deg`` is the angle between
    the plane and the whisker's rest axis (``z``) measured in the x-z plane: 0 deg is
    a surface parallel to the shaft, 90 deg a surface square to it. The outward
    normal points toward ``+x`` (objects come from ``-x``):
    ``n = (cos a, 0, -sin a)``, in-plane direction ``u = (sin a, 0, cos a)``.
    Negative angles (down to -90 deg) tilt the normal toward ``+z``: a plane that a
    whisker turned past it by its housing (:class:`BaseMotion`) meets with its tip,
    e.g. a wall ahead of a whisker resting sideways. The contact kernels use only the
    frame, so such a plane is the rotated image of one in [0, 90] deg
    (``tests/whisker/test_simulate_plane_angles.py``).

    Parameters
    ----------
    surface
        Height field (see :func:`vibrissa.whisker.surfaces.make_surface`).
    angle_deg
        Surface angle in [-90, 90] degrees (negative: see above).
    friction
        Coulomb coefficient; ``None`` takes the surface's.
    stiffness_n_m, damping_n_s_m
        Normal penalty stiffness and approach damping.
    presliding_distance_um
        Tangential elastic displacement before a stuck contact slips (um).
    side
        +1: the surface faces +x (objects come from -x); -1: the mirror image, facing
        -x (objects come from +x).
    """

    surface: Surface
    angle_deg: float = 45.0
    friction: float | None = None
    stiffness_n_m: float = 2.0e4
    damping_n_s_m: float = 0.5
    presliding_distance_um: float = PRESLIDING_DISTANCE_M * 1e6
    side: int = 1

    def __post_init__(self) -> None:
        in_range("angle_deg", self.angle_deg, -90.0, 90.0, "deg")
        if self.side not in (1, -1):
            raise ValueError(f"side must be +1 or -1, got {self.side!r}")
        positive("presliding_distance_um", self.presliding_distance_um)
        if self.friction is not None:
            non_negative("friction", self.friction)
        positive("stiffness_n_m", self.stiffness_n_m)
        non_negative("damping_n_s_m", self.damping_n_s_m)

    def surface_for(self, model: RodModel) -> np.ndarray:
        """The height field as seen by ``model``'s tip (cached per tip radius)."""
        return _tip_envelope(self.surface, float(model.radius[-1]))

    def frame(self) -> np.ndarray:
        """Rows: outward normal, in-plane u, in-plane w (= y)."""
        return _surface_frame(float(self.angle_deg), int(self.side)).copy()


@lru_cache(maxsize=64)
def _surface_frame(angle_deg: float, side: int) -> np.ndarray:
    # cached: a closed loop builds the contact every control period
    a = math.radians(angle_deg)
    n = np.array([side * math.cos(a), 0.0, -math.sin(a)])
    u = np.array([side * math.sin(a), 0.0, math.cos(a)])
    w = np.cross(n, u)
    return np.vstack([n, u, w])


def _interp(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """``np.interp(x, xp, fp)`` (finite ``fp``, increasing ``xp``), by the one-pass kernel."""
    flat = np.ascontiguousarray(x, dtype=float).reshape(-1)
    out = np.empty(flat.shape)
    interp_into(
        flat, np.ascontiguousarray(xp, dtype=float), np.ascontiguousarray(fp, dtype=float), out
    )
    return out.reshape(np.shape(x))


def _sample_times(time_s: np.ndarray) -> np.ndarray:
    """``time_s`` checked: finite, 1-D, at least two samples, strictly increasing."""
    t = finite_array("time_s", time_s)
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"time_s must be 1-D with at least 2 samples, got shape {t.shape}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be strictly increasing")
    return t


@dataclass(frozen=True)
class Trajectory:
    """Prescribed motion of the contact object.

    Parameters
    ----------
    time_s
        Strictly increasing sample times (s).
    position_mm
        Object reference point at those times, shape ``(n, 2)`` as (x, z) in mm: the
        pole's axis, or a point of the surface's base plane.
    velocity_mm_s
        Velocities, same shape (mm/s); if omitted, differentiated from positions.
    lateral_mm
        Optional motion across the whisker's bending plane, along ``y`` (mm), shape
        ``(n,)``: a surface slides sideways under the whisker (a turning mobile base);
        a pole slides along its own axis. ``None``: no lateral motion.
    lateral_velocity_mm_s
        Its velocity (mm/s), shape ``(n,)``; if omitted, differentiated.
    """

    time_s: np.ndarray
    position_mm: np.ndarray
    velocity_mm_s: np.ndarray | None = None
    lateral_mm: np.ndarray | None = None
    lateral_velocity_mm_s: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = _sample_times(self.time_s)
        p = finite_array("position_mm", self.position_mm)
        if p.shape != (t.size, 2):
            raise ValueError(f"position_mm must have shape ({t.size}, 2), got {p.shape}")
        if self.velocity_mm_s is None:
            v = np.gradient(p, t, axis=0)
        else:
            v = finite_array("velocity_mm_s", self.velocity_mm_s)
            if v.shape != p.shape:
                raise ValueError(f"velocity_mm_s must have shape {p.shape}, got {v.shape}")
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "position_mm", p)
        object.__setattr__(self, "velocity_mm_s", v)
        if self.lateral_mm is None:
            if self.lateral_velocity_mm_s is not None:
                raise ValueError("lateral_velocity_mm_s needs lateral_mm")
            return
        y = finite_array("lateral_mm", self.lateral_mm)
        if y.shape != t.shape:
            raise ValueError(f"lateral_mm must have shape {t.shape}, got {y.shape}")
        if self.lateral_velocity_mm_s is None:
            vy = np.gradient(y, t)
        else:
            vy = finite_array("lateral_velocity_mm_s", self.lateral_velocity_mm_s)
            if vy.shape != t.shape:
                raise ValueError(f"lateral_velocity_mm_s must have shape {t.shape}, got {vy.shape}")
        object.__setattr__(self, "lateral_mm", y)
        object.__setattr__(self, "lateral_velocity_mm_s", vy)

    @classmethod
    def linear(
        cls, start_mm: tuple[float, float], velocity_mm_s: tuple[float, float], duration_s: float
    ) -> Trajectory:
        """Constant-velocity motion from ``start_mm`` for ``duration_s``."""
        d = positive("duration_s", duration_s)
        p0 = np.asarray(start_mm, dtype=float)
        vel = np.asarray(velocity_mm_s, dtype=float)
        t = np.array([0.0, d])
        return cls(t, np.vstack([p0, p0 + vel * d]), np.vstack([vel, vel]))

    def sample(self, times_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (mm, mm/s) interpolated at ``times_s``."""
        # np.interp, bit for bit, in one pass over increasing times
        p = np.column_stack(
            [_interp(times_s, self.time_s, self.position_mm[:, i]) for i in range(2)]
        )
        v = np.column_stack(
            [_interp(times_s, self.time_s, self.velocity_mm_s[:, i]) for i in range(2)]
        )
        return p, v

    def sample_lateral(self, times_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lateral position and velocity (mm, mm/s) along ``y`` at ``times_s``.

        Zeros without lateral motion.
        """
        if self.lateral_mm is None:
            z = np.zeros(np.shape(times_s))
            return z, z.copy()
        return (
            _interp(times_s, self.time_s, self.lateral_mm),
            _interp(times_s, self.time_s, self.lateral_velocity_mm_s),
        )


@dataclass(frozen=True)
class BaseMotion:
    """Prescribed whisking: the follicle housing's angle over time.

    A motor turns the follicle housing about the ``y`` axis through the pivot (the
    whisker's node 0), carrying the follicle's rest direction and the Hall sensor
    with it (:func:`~vibrissa.whisker._kernels.add_internal_whisking`). Positive
    angles turn the whisker from ``z`` toward ``+x`` (protraction, toward an object
    on the ``+x`` side).

    Parameters
    ----------
    time_s
        Strictly increasing sample times (s), in absolute simulation time; times
        outside the range hold the end values (and a zero rate).
    angle_rad
        The housing's angle at those times (rad).
    rate_rad_s
        Its rate (rad/s); if omitted, differentiated from the angles.
    """

    time_s: np.ndarray
    angle_rad: np.ndarray
    rate_rad_s: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = _sample_times(self.time_s)
        a = finite_array("angle_rad", self.angle_rad)
        if a.shape != t.shape:
            raise ValueError(f"angle_rad must have shape {t.shape}, got {a.shape}")
        if np.any(np.abs(a) >= 0.5 * math.pi):
            raise ValueError("angle_rad must stay within (-pi/2, pi/2)")
        w = (
            np.gradient(a, t)
            if self.rate_rad_s is None
            else finite_array("rate_rad_s", self.rate_rad_s)
        )
        if w.shape != t.shape:
            raise ValueError(f"rate_rad_s must have shape {t.shape}, got {w.shape}")
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "angle_rad", a)
        object.__setattr__(self, "rate_rad_s", w)

    def sample(self, times_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Angles (rad) and rates (rad/s) interpolated at ``times_s``."""
        t = self.time_s
        # a step time a rounding error beyond an end sample is at it: a closed loop's
        # clock (a running sum of steps) overshoots its period's end by an ulp about
        # every other period, and must not read a zero rate there
        inside = (times_s >= t[0] - TIME_TOL_S) & (times_s <= t[-1] + TIME_TOL_S)
        rate = np.where(inside, np.interp(times_s, t, self.rate_rad_s), 0.0)
        return np.interp(times_s, t, self.angle_rad), rate


def _turned(x: np.ndarray, theta: float) -> np.ndarray:
    """Positions ``x`` turned by ``theta`` about ``y`` through node 0."""
    c, s = math.cos(theta), math.sin(theta)
    r = x - x[0]
    out = x.copy()
    out[:, 0] = x[0, 0] + c * r[:, 0] + s * r[:, 2]
    out[:, 2] = x[0, 2] - s * r[:, 0] + c * r[:, 2]
    return out


@dataclass
class SimulationResult:
    """Outputs of :func:`simulate` at every internal step.

    Attributes
    ----------
    time_s
        Step times (s), shape (n,).
    tan_xy
        Tangents of the magnet tilt toward x and y, shape (n, 2).
    contact_force_n
        Normal contact force (N), shape (n,).
    contact_arc_mm
        Arc length of the (closest) contact point from the base (mm) for a pole, nan
        for surfaces; shape (n,).
    slipping
        Whether the contact slipped during the step (pole) or how many nodes slipped
        (surface), shape (n,).
    contact_force_xz_n
        Contact force on the whisker in x and z (N), shape (n, 2).
    newton_iterations
        Newton iterations per step.
    model
        The rod model simulated.
    dt_s
        Internal time step (s).
    states_m
        Node positions every ``record_every`` steps if requested, else None;
        shape (n_records, n_nodes, 3).
    velocities_m_s
        Node velocities at the same records, else None.
    final_state
        The state at the last step, to continue with ``simulate(initial_state=...)``.
    stopped_early
        True if ``stop_when_tan_x_exceeds`` ended the run.
    base_angle_rad
        The follicle housing's whisk angle at every step (rad) when the run had a
        :class:`BaseMotion`, else None. ``tan_xy`` is then read in the housing's
        frame, as the Hall sensor turning with it reads it.
    """

    time_s: np.ndarray
    tan_xy: np.ndarray
    contact_force_n: np.ndarray
    contact_arc_mm: np.ndarray
    slipping: np.ndarray
    contact_force_xz_n: np.ndarray
    newton_iterations: np.ndarray
    model: RodModel
    dt_s: float
    states_m: np.ndarray | None = None
    velocities_m_s: np.ndarray | None = None
    final_velocity_m_s: np.ndarray | None = field(default=None, repr=False)
    final_state: DynamicState | None = field(default=None, repr=False)
    stopped_early: bool = False
    base_angle_rad: np.ndarray | None = None

    @property
    def follicle_angle_rad(self) -> np.ndarray:
        """Magnet tilt angles (rad), shape (n, 2)."""
        return np.arctan(self.tan_xy)

    @property
    def follicle_moment_nm(self) -> np.ndarray:
        """Restoring moment of the rubber follicle (N m) about the two axes, shape (n, 2)."""
        return self.model.kf * np.sin(self.follicle_angle_rad)

    def hall_volts(
        self,
        sensor: HallSensor | None = None,
        sample_rate_hz: float = 1000.0,
        rng: np.random.Generator | None = None,
    ) -> np.ndarray:
        """Sensor output sampled at the sensor's rate, shape (n_samples, 2).

        ``sensor`` defaults to a :class:`HallSensor` calibrated for this whisker at
        ``sample_rate_hz``.
        """
        if sensor is None:
            sensor = HallSensor(
                calibrated_gain(self.model.geometry, self.model.n_elements),
                sample_rate_hz=sample_rate_hz,
            )
        return sensor.read(self.tan_xy, 1.0 / self.dt_s, rng)


def _initial_acceleration(
    rod: RodArrays,
    damping: Damping,
    x: np.ndarray,
    v: np.ndarray,
    theta: float = 0.0,
    theta_dot: float = 0.0,
) -> np.ndarray:
    """Node accelerations (m/s^2) at positions ``x`` (m) and velocities ``v`` (m/s).

    The follicle housing is at angle ``theta`` (rad), turning at ``theta_dot`` (rad/s).
    The forces are divided by the row sums of the mass matrix (the node masses
    themselves for a lumped mass). For the consistent mass this is not ``M^-1 F``: the
    inverse of the tridiagonal matrix spreads a point force (a released tip load, a
    contact) over the whole rod in alternating signs, and the generalised-alpha
    scheme's first step then overshoots on those stiff components: released from a
    30 mm tip deflection the rod's energy rose by 0.40 % in the first 0.25 ms step
    (0.057 % with the lumped mass), while with the row sums it falls by 0.006 %
    (``benchmarks/rod_mass_dynamics.py``).
    The row sums keep each node's share of the force and the rod's total momentum
    rate; only the start of the first step differs.
    """
    n = x.shape[0]
    F = np.zeros((n, 3))
    S = np.zeros((3 * n, 2 * BW + 1))
    add_internal_whisking(x, v, rod, damping, F, S, 0.0, 0.0, False, float(theta), float(theta_dot))
    row_sums = rod.mass.copy()  # a lumped mass's couplings are zeros: its own masses
    row_sums[:-1] += rod.mass_off
    row_sums[1:] += rod.mass_off
    a = F / row_sums[:, None]
    a[~rod.free] = 0.0
    return a


@dataclass
class DynamicState:
    """Everything needed to continue a simulation exactly where it stopped.

    Attributes
    ----------
    positions_m, velocities_m_s, accelerations_m_s2
        Node states, each of shape (n_nodes, 3).
    pole_anchor
        Friction state of a pole contact (5,).
    plane_anchors
        Friction state of each node on a surface (n_nodes, 6).
    time_s
        Simulation time of this state (s).
    """

    positions_m: np.ndarray
    velocities_m_s: np.ndarray
    accelerations_m_s2: np.ndarray
    pole_anchor: np.ndarray
    plane_anchors: np.ndarray
    time_s: float = 0.0

    def copy(self) -> DynamicState:
        """Deep copy."""
        return DynamicState(
            self.positions_m.copy(),
            self.velocities_m_s.copy(),
            self.accelerations_m_s2.copy(),
            self.pole_anchor.copy(),
            self.plane_anchors.copy(),
            self.time_s,
        )


def _contact_spec(
    model: RodModel,
    contact: PoleContact | SurfaceContact | None,
    trajectory: Trajectory | None,
    times: np.ndarray,
) -> tuple[ContactSpec, np.ndarray]:
    """Pack the contact and the object's motion for the kernels.

    Returns the :class:`~vibrissa.whisker._kernels.ContactSpec`
    (:func:`_contact_kernel_spec`) and the object's state at ``times`` (s)
    (:func:`_object_motion`).
    """
    spec = _contact_kernel_spec(model, contact, trajectory)
    return spec, _object_motion(contact, trajectory, times)


def _contact_kernel_spec(
    model: RodModel,
    contact: PoleContact | SurfaceContact | None,
    trajectory: Trajectory | None,
) -> ContactSpec:
    """The contact's :class:`~vibrissa.whisker._kernels.ContactSpec` (no contact: none)."""
    if contact is None:
        return pole_contact_spec(np.zeros(5), NO_CONTACT)
    if trajectory is None:
        raise ValueError("a contact needs a trajectory")
    if isinstance(contact, PoleContact):
        return pole_contact_spec(
            np.array(
                [
                    contact.radius_mm * 1e-3,
                    contact.stiffness_n_m,
                    contact.damping_n_s_m,
                    contact.friction,
                    contact.presliding_distance_um * 1e-6,
                ]
            )
        )
    if isinstance(contact, SurfaceContact):
        mu = contact.surface.friction if contact.friction is None else contact.friction
        du = float(contact.surface.spacing_m)
        heights = contact.surface_for(model)
        return ContactSpec(
            kind=PLANE,
            params=np.array(
                [
                    0.0,
                    contact.stiffness_n_m,
                    contact.damping_n_s_m,
                    mu,
                    contact.presliding_distance_um * 1e-6,
                ]
            ),
            frame=contact.frame(),
            heights=heights,
            du=du,
            dw=du,
            first_node=2,
            h_max=float(heights.max()),
        )
    raise TypeError(f"unsupported contact type {type(contact).__name__}")


def _object_motion(
    contact: PoleContact | SurfaceContact | None,
    trajectory: Trajectory | None,
    times: np.ndarray,
) -> np.ndarray:
    """The object's state at ``times`` (s) for the kernels, shape ``(len(times), 6)``.

    For a pole x, z (m), vx, vz (m/s), y, vy (its motion along its own axis); for a
    surface the base point's x, y, z (m) and its velocity (m/s); zeros without a contact.
    """
    traj = np.zeros((times.size, 6))
    if contact is None or trajectory is None:
        return traj
    p, pv = trajectory.sample(times)
    y, vy = trajectory.sample_lateral(times)
    if isinstance(contact, PoleContact):
        traj[:, 0:2] = p * 1e-3
        traj[:, 2:4] = pv * 1e-3
        traj[:, 4] = y * 1e-3
        traj[:, 5] = vy * 1e-3
    else:
        traj[:, 0] = p[:, 0] * 1e-3
        traj[:, 1] = y * 1e-3
        traj[:, 2] = p[:, 1] * 1e-3
        traj[:, 3] = pv[:, 0] * 1e-3
        traj[:, 4] = vy * 1e-3
        traj[:, 5] = pv[:, 1] * 1e-3
    return traj


#: Consecutive contact-free steps before the hand-over to linear free flight is
#: tried, and the contact-free steps between later tries (when the whisker was not
#: yet linear enough).
FREE_STEPS_FIRST = 8
FREE_STEPS_RETRY = 40
#: Linear free flight is used only for stretches of at least this many steps.
MIN_LINEAR_STEPS = 16
#: Clearance (m) kept between an object and the bound of the free whisker's motion:
#: the nonlinear rod takes over before the object comes closer.
CONTACT_MARGIN_M = 0.5e-3


def _hybrid(
    model: RodModel,
    rod: RodArrays,
    damping: Damping,
    spec: ContactSpec,
    traj: np.ndarray,
    settings: SolverSettings,
    out: np.ndarray,
    states: np.ndarray,
    node: NodeState,
    anchors: Anchors,
) -> tuple[int, int]:
    """Integrate, alternating the nonlinear rod and exact linear free flight.

    Returns the steps done and the status code of :func:`run_dynamics`.
    """
    from vibrissa.whisker.modal import (
        ENERGY_TOL,
        LINEARITY_TOL,
        linear_modes,
    )

    lm = linear_modes(model)
    n_steps = traj.shape[0] - 1
    dt = settings.dt
    lam = lm.eigenvalues
    decay = lm.reduced(np.exp(lam * dt))
    h_max = spec.h_max if spec.kind == PLANE else 0.0
    status_arr = np.zeros(1, dtype=np.int64)
    k = 0
    free_steps = FREE_STEPS_FIRST
    x, v, a = node
    pivot = lm.x_rest[0]
    whisking = traj.shape[1] > TR_BASE
    no_load = np.zeros(0)
    gain0 = gain1 = np.zeros(decay.size, dtype=complex)
    load0 = load1 = no_load
    objects = traj
    if whisking:
        # in the turning housing's frame the free whisker is the same linear system,
        # driven by the housing's angular acceleration (see LinearModes.housing_load);
        # the rate, linear within each step, makes that acceleration constant in it
        theta = traj[:, TR_BASE]
        rate = traj[:, TR_BASE + 1]
        b = lm.reduced(lm.housing_load())
        lr = lm.reduced(lam)
        gain0 = b * (decay - 1.0) / lr
        gain1 = b * (decay - 1.0 - lr * dt) / (lr * lr * dt)
        accel = np.diff(rate) / dt
        load0 = np.ascontiguousarray(accel + damping.alpha * rate[:-1])
        load1 = np.ascontiguousarray(accel + damping.alpha * rate[1:])
        # rows where the housing turns too fast for the centrifugal load to be left out
        too_fast = rate**2 > LINEARITY_TOL * lm.omega[0] ** 2
        if spec.kind == POLE:  # the pole as seen from the housing
            objects = traj.copy()
            c, s_ = np.cos(theta), np.sin(theta)
            rx, rz = traj[:, 0] - pivot[0], traj[:, 1] - pivot[2]
            objects[:, 0] = pivot[0] + c * rx - s_ * rz
            objects[:, 1] = pivot[2] + s_ * rx + c * rz
    # row 0: the initial state (the nonlinear kernel writes it too, when it starts)
    xh0 = _to_housing(x, v, float(theta[0]), 0.0, pivot)[0] if whisking else x
    out[0, 0] = (xh0[1, 0] - xh0[0, 0]) / (xh0[1, 2] - xh0[0, 2])
    out[0, 1] = (xh0[1, 1] - xh0[0, 1]) / (xh0[1, 2] - xh0[0, 2])
    while k < n_steps:
        # --- linear free flight, if nothing can touch the whisker for a while
        xh, vh = _to_housing(x, v, float(theta[k]), float(rate[k]), pivot) if whisking else (x, v)
        # the cheap gates first: most tries after a release fail on nonlinearity
        linear = not (whisking and too_fast[k]) and lm.nonlinearity(xh) <= LINEARITY_TOL
        if linear:
            z, lost = lm.amplitudes(xh, vh)
            linear = lost <= ENERGY_TOL
        if linear:
            bound = np.einsum("ij,j->i", lm.node_bound, np.abs(z))
            zr = lm.reduced(z)
            k_end = k + first_possible_contact(
                spec.kind,
                spec.params,
                spec.frame,
                h_max,
                objects[k:],
                lm.x_rest,
                rod.radius,
                bound,
                CONTACT_MARGIN_M,
                spec.first_node,
            )
            if whisking:
                fast = np.flatnonzero(too_fast[k:])
                if fast.size:
                    k_end = min(k_end, k + int(fast[0]))
            k_end = min(max(k_end - 1, k), n_steps)
            if k_end - k >= MIN_LINEAR_STEPS or k_end == n_steps > k:
                row = out[k].copy()
                wanted = k_end - k
                n_done = modal_advance(
                    zr,
                    decay,
                    lm.magnet,
                    lm.x_rest[0],
                    lm.x_rest[1],
                    wanted,
                    settings.stop_tan,
                    out[k:],
                    gain0,
                    gain1,
                    load0[k:] if whisking else no_load,
                    load1[k:] if whisking else no_load,
                )
                out[k] = row
                k += n_done
                xl, vl = lm.state(lm.expanded(zr))
                th, thd = (float(theta[k]), float(rate[k])) if whisking else (0.0, 0.0)
                if whisking:
                    xl, vl = _to_world(xl, vl, th, thd, pivot)
                x[:, :] = xl
                v[:, :] = vl
                a[:, :] = _initial_acceleration(rod, damping, x, v, th, thd)
                _reset_contact_memory(spec, traj[k], rod, x, v, anchors)
                if n_done < wanted:  # the stop event fired
                    return k, 1
                if k >= n_steps:
                    return k, 0
                free_steps = FREE_STEPS_FIRST
        # --- the nonlinear rod until it has been free of contact for a while
        row = out[k].copy()
        done = run_dynamics(
            node,
            anchors,
            rod,
            damping,
            spec,
            traj[k:],
            settings._replace(stop_free=free_steps),
            out[k:],
            states,
            status_arr,
        )
        out[k] = row
        k += done
        status = int(status_arr[0])
        if status != 2:
            return k, status
        free_steps = FREE_STEPS_RETRY
    return k, 0


def _to_housing(
    x: np.ndarray, v: np.ndarray, theta: float, rate: float, pivot: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities (n, 3) as seen from a turned and turning follicle housing.

    The housing is turned by ``theta`` (rad) about ``y`` through ``pivot`` and turning at
    ``rate`` (rad/s).
    """
    c, s = math.cos(theta), math.sin(theta)
    r = x - pivot
    w = v - rate * np.column_stack([r[:, 2], np.zeros(len(r)), -r[:, 0]])
    xh, vh = x.copy(), w.copy()
    xh[:, 0] = pivot[0] + c * r[:, 0] - s * r[:, 2]
    xh[:, 2] = pivot[2] + s * r[:, 0] + c * r[:, 2]
    vh[:, 0] = c * w[:, 0] - s * w[:, 2]
    vh[:, 2] = s * w[:, 0] + c * w[:, 2]
    return xh, vh


def _to_world(
    xh: np.ndarray, vh: np.ndarray, theta: float, rate: float, pivot: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The inverse of :func:`_to_housing`."""
    c, s = math.cos(theta), math.sin(theta)
    r = xh - pivot
    x, v = xh.copy(), vh.copy()
    x[:, 0] = pivot[0] + c * r[:, 0] + s * r[:, 2]
    x[:, 2] = pivot[2] - s * r[:, 0] + c * r[:, 2]
    v[:, 0] = c * vh[:, 0] + s * vh[:, 2]
    v[:, 2] = -s * vh[:, 0] + c * vh[:, 2]
    rw = x - pivot
    v += rate * np.column_stack([rw[:, 2], np.zeros(len(rw)), -rw[:, 0]])
    return x, v


def _reset_contact_memory(
    spec: ContactSpec,
    tr: np.ndarray,
    rod: RodArrays,
    x: np.ndarray,
    v: np.ndarray,
    anchors: Anchors,
) -> None:
    """Friction and side memory for a whisker coming out of free flight.

    No stick anchor survives free flight; a pole's "side" memory is set to the side
    the shaft is on now, as :func:`~vibrissa.whisker._kernels.add_pole` would have
    remembered it out of contact.
    """
    anchors.pole[:] = 0.0
    anchors.plane[:, :] = 0.0
    if spec.kind != POLE:
        return
    n = x.shape[0]
    info = np.zeros(12)
    F = np.zeros((n, 3))
    S = np.zeros((3 * n, 2 * BW + 1))
    add_pole(x, v, rod, spec, tr, anchors.pole, F, S, 0.0, 0.0, False, info)
    anchors.pole[:] = 0.0
    if info[3] > 0.0:
        anchors.pole[4] = info[11]


def simulate(
    model: RodModel,
    contact: PoleContact | SurfaceContact | None,
    trajectory: Trajectory | None,
    duration_s: float,
    dt_s: float = DEFAULT_DT_S,
    initial_positions_m: np.ndarray | None = None,
    initial_velocities_m_s: np.ndarray | None = None,
    record_every: int = 0,
    rho_inf: float = 0.5,
    tol_m: float = 1e-8,
    max_iterations: int = 30,
    refactor_every: int = 16,
    max_halvings: int = 6,
    initial_state: DynamicState | None = None,
    stop_when_tan_x_exceeds: float | None = None,
    linear_free_flight: bool = True,
    max_stride: int = 8,
    stride_tol_m: float = 3e-7,
    base_motion: BaseMotion | None = None,
) -> SimulationResult:
    """Integrate the whisker's motion for ``duration_s`` seconds.

    Parameters
    ----------
    model
        The rod model.
    contact
        Contact object, or None for free motion.
    trajectory
        The object's motion (required with a contact), in absolute simulation time.
        Times outside the trajectory's range hold its end values.
    duration_s
        Simulated time (s).
    dt_s
        Internal time step (s).
    initial_positions_m, initial_velocities_m_s
        Initial state (default: at rest; ignored if ``initial_state`` is given).
    record_every
        Store node positions and velocities every that many steps (0: never).
    rho_inf
        Spectral radius of the generalised-alpha scheme at infinite frequency, [0, 1].
    tol_m
        Newton convergence tolerance on the position update (m).
    max_iterations
        Newton iterations allowed per step.
    refactor_every
        Refresh the factorised Newton matrix at least every that many steps
        (1 = full Newton; larger is faster, with the same converged result).
    max_halvings
        A step that fails to converge is retried in up to ``2**max_halvings``
        sub-steps before the simulation gives up.
    initial_state
        Continue from a :class:`DynamicState` (e.g. ``result.final_state``); the
        simulation then starts at ``initial_state.time_s``.
    stop_when_tan_x_exceeds
        Stop early after the first step at which |tan_x| of the magnet reaches this
        value (an event for closed-loop control); ``result.stopped_early`` tells.
    linear_free_flight
        Advance the whisker exactly in its linear modes while nothing can touch it
        and its deflection is small (:mod:`vibrissa.whisker.modal`), switching back
        to the nonlinear rod before any contact; False integrates every step with
        the nonlinear rod. Always off when ``record_every`` > 0. During linear
        free flight ``contact_arc_mm`` is nan and ``newton_iterations`` 0.
    max_stride
        While the contact state (touching or not, sticking or slipping) has not
        changed for a few steps, try steps of up to this many ``dt_s``; one is kept
        only if the contact state stays the same and its local error estimate is
        within ``stride_tol_m``; rows inside it are interpolated (cubic Hermite for
        the magnet, linear for forces). The length adapts from 2 ``dt_s`` up to this
        to the error estimate; out of contact no long step is taken while the object
        is within what whisker and object could close in it. 1 takes every step at
        ``dt_s``.
    stride_tol_m
        Largest local error estimate (m) of a long step.
    base_motion
        Whisking: the follicle housing's angle over time (:class:`BaseMotion`),
        or None for a housing at rest. A whisker starting at rest (no
        ``initial_state`` or ``initial_positions_m``) starts turned with the
        housing and moving with it. Linear free flight then runs in the housing's
        frame, driven by its angular acceleration, wherever its rate stays within
        ``sqrt(LINEARITY_TOL)`` times the first natural frequency (the centrifugal
        load it leaves out is of that order; :mod:`vibrissa.whisker.modal`); with a
        surface contact the nonlinear rod integrates throughout.

    Raises
    ------
    SimulationError
        If a step fails to converge or the state becomes non-finite.
    """
    T = positive("duration_s", duration_s)
    dt = positive("dt_s", dt_s)
    if dt > 1e-3:
        raise ValueError(f"dt_s must be at most 1 ms for this model, got {dt_s}")
    in_range("rho_inf", rho_inf, 0.0, 1.0)
    positive("tol_m", tol_m)
    positive("stride_tol_m", stride_tol_m)
    for name, value, low in (
        ("max_stride", max_stride, 1),
        ("max_iterations", max_iterations, 1),
        ("refactor_every", refactor_every, 1),
        ("max_halvings", max_halvings, 0),
    ):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise ValueError(f"{name} must be an integer of at least {low}, got {value!r}")
    stop = (
        0.0
        if stop_when_tan_x_exceeds is None
        else positive("stop_when_tan_x_exceeds", stop_when_tan_x_exceeds)
    )
    n_steps = int(round(T / dt))
    if n_steps < 1:
        raise ValueError(f"duration_s ({duration_s}) is shorter than one step ({dt_s})")
    n = model.n_nodes
    rod = model.rod_arrays()
    damping = Damping(*(float(c) for c in model.damping))
    if base_motion is not None and not isinstance(base_motion, BaseMotion):
        raise TypeError(f"base_motion must be a BaseMotion, got {type(base_motion).__name__}")
    t_start = float(initial_state.time_s) if initial_state is not None else 0.0
    th0, thd0 = (
        (0.0, 0.0)
        if base_motion is None
        else (float(u[0]) for u in base_motion.sample(np.array([t_start])))
    )
    if initial_state is not None:
        st = initial_state.copy()
        x, v, a = st.positions_m, st.velocities_m_s, st.accelerations_m_s2
        pole_anchor, plane_anchors = st.pole_anchor, st.plane_anchors
        t0 = float(st.time_s)
    elif initial_positions_m is None and initial_velocities_m_s is None:
        x, v, a = _rest_state(model, rod, damping, th0, thd0)
        pole_anchor = np.zeros(5)
        plane_anchors = np.zeros((n, 6))
        t0 = 0.0
    else:
        x = (
            (_turned(model.x_rest, th0) if th0 != 0.0 else model.x_rest.copy())
            if initial_positions_m is None
            else np.array(finite_array("initial_positions_m", initial_positions_m), dtype=float)
        )
        v = (
            np.zeros((n, 3))
            if initial_velocities_m_s is None
            else np.array(
                finite_array("initial_velocities_m_s", initial_velocities_m_s), dtype=float
            )
        )
        if x.shape != (n, 3) or v.shape != (n, 3):
            raise ValueError(f"initial state must have shape ({n}, 3)")
        a = _initial_acceleration(rod, damping, x, v, th0, thd0)
        pole_anchor = np.zeros(5)
        plane_anchors = np.zeros((n, 6))
        t0 = 0.0
    times = t0 + np.arange(n_steps + 1) * dt
    spec, traj = _contact_spec(model, contact, trajectory, times)
    if base_motion is not None:
        traj = np.column_stack([traj, *base_motion.sample(times)])
    settings = SolverSettings(
        dt=float(dt),
        rho_inf=float(rho_inf),
        tol=float(tol_m),
        max_iter=int(max_iterations),
        refactor_every=int(refactor_every),
        max_halvings=int(max_halvings),
        record_every=int(record_every),
        stop_tan=float(stop),
        stop_free=0,
        max_stride=int(max_stride),
        stride_tol=float(stride_tol_m),
    )
    out = np.zeros((n_steps + 1, 8))
    n_states = (n_steps // record_every + 1) if record_every > 0 else 1
    states = np.zeros((n_states, 2, n, 3))
    node_state = NodeState(x, v, a)
    anchors = Anchors(pole_anchor, plane_anchors)
    if linear_free_flight and record_every == 0 and (base_motion is None or spec.kind != PLANE):
        done, status = _hybrid(
            model, rod, damping, spec, traj, settings, out, states, node_state, anchors
        )
    else:
        status_arr = np.zeros(1, dtype=np.int64)
        done = run_dynamics(
            node_state, anchors, rod, damping, spec, traj, settings, out, states, status_arr
        )
        status = int(status_arr[0])
    stopped = status == 1
    if (
        status < 0
        or (done < n_steps and not stopped)
        or not np.all(np.isfinite(out[: done + 1, [0, 1, 2, 4, 5, 6, 7]]))
    ):
        raise SimulationError(
            f"simulation diverged or failed to converge at t = {t0 + done * dt:.5f} s "
            f"(step {done} of {n_steps}); try a smaller dt_s"
        )
    m = done + 1
    arc = out[:m, 3] * 1e3 if spec.kind == POLE else np.full(m, np.nan)
    n_rec = (done // record_every + 1) if record_every > 0 else 0
    return SimulationResult(
        time_s=times[:m],
        tan_xy=out[:m, 0:2].copy(),
        contact_force_n=out[:m, 2].copy(),
        contact_arc_mm=arc,
        slipping=out[:m, 4].copy(),
        contact_force_xz_n=out[:m, 5:7].copy(),
        newton_iterations=out[:m, 7].astype(np.int32),
        model=model,
        dt_s=dt,
        states_m=states[:n_rec, 0] if record_every > 0 else None,
        velocities_m_s=states[:n_rec, 1] if record_every > 0 else None,
        final_velocity_m_s=v,
        final_state=DynamicState(x, v, a, pole_anchor, plane_anchors, float(times[done])),
        stopped_early=bool(stopped),
        base_angle_rad=None if base_motion is None else traj[:m, TR_BASE].copy(),
    )


def _rest_state(
    model: RodModel, rod: RodArrays, damping: Damping, th0: float, thd0: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions, velocities and accelerations of a whisker at rest in its housing.

    The housing at angle ``th0`` (rad) turning at ``thd0`` (rad/s): the rest shape turned
    with it, moving with it.
    """
    x = _turned(model.x_rest, th0) if th0 != 0.0 else model.x_rest.copy()
    v = np.zeros((model.n_nodes, 3))
    if thd0 != 0.0:
        r = x - x[0]
        v = np.column_stack([thd0 * r[:, 2], np.zeros(model.n_nodes), -thd0 * r[:, 0]])
        v[~model.free] = 0.0
    return x, v, _initial_acceleration(rod, damping, x, v, th0, thd0)


def _is_still(trajectory: Trajectory) -> bool:
    """Whether the object stands still: one position, no velocity, across and along."""
    p, v = trajectory.position_mm, trajectory.velocity_mm_s
    still = bool(np.all(p == p[0]) and not np.any(v))
    if trajectory.lateral_mm is not None:
        y, vy = trajectory.lateral_mm, trajectory.lateral_velocity_mm_s
        still = still and bool(np.all(y == y[0]) and not np.any(vy))
    return still


class PeriodOutput(NamedTuple):
    """What :meth:`ClosedLoopStepper.advance` gives for one period, at every step."""

    time_s: np.ndarray
    tan_xy: np.ndarray
    contact_force_n: np.ndarray


class StepperKernelInputs(NamedTuple):
    """A :class:`ClosedLoopStepper`'s whisker as the compiled integrator reads it.

    ``state`` and ``anchors`` are the stepper's own arrays (advanced in place);
    ``object_row`` is the still object's state (6 values, zeros without an object).
    """

    state: NodeState
    anchors: Anchors
    rod: RodArrays
    damping: Damping
    contact: ContactSpec
    settings: SolverSettings
    object_row: np.ndarray


class ClosedLoopStepper:
    """One whisker advanced a control period at a time, for closed loops.

    A closed loop (the whisking robots' RCP control) simulates each whisker for one
    control period, reads its magnet and commands the next period. :func:`simulate`
    checks its inputs and builds the rod's arrays, the contact's kernel spec, the
    housing's motion and the solver settings on every call; the stepper builds what does
    not change once and keeps the whisker's state between periods. Each period is the
    nonlinear rod (no linear free flight), as the loops run it: the numbers are those of
    ``simulate(model, contact, trajectory, period, dt_s, initial_state=previous,
    base_motion=BaseMotion(base_time_s, base_angle_rad, base_rate_rad_s),
    linear_free_flight=False)``, bit for bit.

    Parameters
    ----------
    model, contact, trajectory, dt_s
        As in :func:`simulate`.
    rho_inf, tol_m, max_iterations, refactor_every, max_halvings, max_stride, stride_tol_m
        The solver's settings, as in :func:`simulate`.
    """

    def __init__(
        self,
        model: RodModel,
        contact: PoleContact | SurfaceContact | None,
        trajectory: Trajectory | None,
        dt_s: float = DEFAULT_DT_S,
        *,
        rho_inf: float = 0.5,
        tol_m: float = 1e-8,
        max_iterations: int = 30,
        refactor_every: int = 16,
        max_halvings: int = 6,
        max_stride: int = 8,
        stride_tol_m: float = 3e-7,
    ) -> None:
        dt = positive("dt_s", dt_s)
        if dt > 1e-3:
            raise ValueError(f"dt_s must be at most 1 ms for this model, got {dt_s}")
        in_range("rho_inf", rho_inf, 0.0, 1.0)
        for name, value, low in (
            ("max_stride", max_stride, 1),
            ("max_iterations", max_iterations, 1),
            ("refactor_every", refactor_every, 1),
            ("max_halvings", max_halvings, 0),
        ):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
                raise ValueError(f"{name} must be an integer of at least {low}, got {value!r}")
        self.model = model
        self.dt_s = dt
        self._contact = contact
        self._trajectory = trajectory
        self._rod = model.rod_arrays()
        self._damping = Damping(*(float(c) for c in model.damping))
        self._spec = _contact_kernel_spec(model, contact, trajectory)
        self._settings = SolverSettings(
            dt=float(dt),
            rho_inf=float(rho_inf),
            tol=float(positive("tol_m", tol_m)),
            max_iter=int(max_iterations),
            refactor_every=int(refactor_every),
            max_halvings=int(max_halvings),
            record_every=0,
            stop_tan=0.0,
            stop_free=0,
            max_stride=int(max_stride),
            stride_tol=float(positive("stride_tol_m", stride_tol_m)),
        )
        # a still object (the robots' poles and walls): its state is one row for all time
        self._still_object = (
            _object_motion(contact, trajectory, trajectory.time_s[:1])[0]
            if trajectory is not None and _is_still(trajectory)
            else None
        )
        self._node_state: NodeState | None = None
        self._anchors = Anchors(np.zeros(5), np.zeros((model.n_nodes, 6)))
        self._states = np.zeros((1, 2, model.n_nodes, 3))
        self._status = np.zeros(1, dtype=np.int64)
        #: The whisker's clock (s): the end of the last period.
        self.time_s = 0.0

    def advance(
        self,
        n_steps: int,
        base_time_s: np.ndarray,
        base_angle_rad: np.ndarray,
        base_rate_rad_s: np.ndarray,
    ) -> PeriodOutput:
        """Advance ``n_steps`` steps with the housing's motion given at ``base_time_s``.

        Parameters
        ----------
        n_steps : int
            Steps of ``dt_s`` (at least 1).
        base_time_s, base_angle_rad, base_rate_rad_s : ndarray of shape (k,)
            The housing's angle (rad) and rate (rad/s) at increasing times (s), read as
            :meth:`BaseMotion.sample` reads them (between samples linearly; outside them
            the end angle and zero rate).

        Returns
        -------
        PeriodOutput
            Times, magnet tangents and contact force at each step, the period's start
            included.

        Raises
        ------
        SimulationError
            If a step fails to converge or the state becomes non-finite.
        """
        if isinstance(n_steps, bool) or not isinstance(n_steps, (int, np.integer)) or n_steps < 1:
            raise ValueError(f"n_steps must be an integer of at least 1, got {n_steps!r}")
        tb = np.asarray(base_time_s, dtype=float)
        ab = np.asarray(base_angle_rad, dtype=float)
        wb = np.asarray(base_rate_rad_s, dtype=float)
        if tb.ndim != 1 or tb.size < 2 or ab.shape != tb.shape or wb.shape != tb.shape:
            raise ValueError(
                "base_time_s, base_angle_rad and base_rate_rad_s must be 1-D of one length "
                f"(at least 2), got {tb.shape}, {ab.shape}, {wb.shape}"
            )
        times = self.time_s + np.arange(n_steps + 1) * self.dt_s
        angle, rate = BaseMotion(tb, ab, wb).sample(times)
        return self._run(times, angle, rate)

    def advance_sampled(self, angle_rad: np.ndarray, rate_rad_s: np.ndarray) -> PeriodOutput:
        """Advance ``len(angle_rad) - 1`` steps, the housing's motion given at every step.

        The closed loops' hot path: ``angle_rad[k]`` and ``rate_rad_s[k]`` are the
        housing's angle (rad) and rate (rad/s) at step ``k`` of the period (``k = 0``: its
        start, the end of the last one), so nothing is interpolated. The numbers are
        those of :meth:`advance` given the same values at the step times.

        Raises
        ------
        ValueError
            If the two arrays are not 1-D of one length of at least 2.
        SimulationError
            If a step fails to converge or the state becomes non-finite.
        """
        angle = np.asarray(angle_rad, dtype=float)
        rate = np.asarray(rate_rad_s, dtype=float)
        if angle.ndim != 1 or angle.size < 2 or rate.shape != angle.shape:
            raise ValueError(
                "angle_rad and rate_rad_s must be 1-D of one length (at least 2), got "
                f"{angle.shape}, {rate.shape}"
            )
        times = self.time_s + np.arange(angle.size) * self.dt_s
        return self._run(times, angle, rate)

    def kernel_inputs(self, angle_rad: float, rate_rad_s: float) -> StepperKernelInputs:
        """What a compiled driver of several whiskers passes to the integrator.

        For loops that advance many whiskers a period at a time inside one compiled
        function (:func:`rcp_loop`, the whisking robots' RCP loop). The state is the stepper's own
        (created at rest in a housing at ``angle_rad`` turning at ``rate_rad_s`` if no
        period has run yet) and is advanced in place by whoever integrates it; a caller
        that goes on using the stepper moves its clock with :meth:`advance_clock`
        (``run_whisking`` does not: its steppers end with the loop).

        Raises
        ------
        ValueError
            If the object moves: a driver is given one object row for all time.
        """
        if self._trajectory is not None and self._still_object is None:
            raise ValueError("kernel_inputs needs a still object (or none)")
        if self._node_state is None:
            self._node_state = NodeState(
                *_rest_state(self.model, self._rod, self._damping, angle_rad, rate_rad_s)
            )
        row = self._still_object if self._still_object is not None else np.zeros(6)
        return StepperKernelInputs(
            self._node_state,
            self._anchors,
            self._rod,
            self._damping,
            self._spec,
            self._settings,
            np.ascontiguousarray(row, dtype=float),
        )

    def advance_clock(self, n_steps: int) -> None:
        """Move the clock by ``n_steps`` steps integrated outside :meth:`advance`."""
        self.time_s = float(self.time_s + n_steps * self.dt_s)

    def _run(self, times: np.ndarray, angle: np.ndarray, rate: np.ndarray) -> PeriodOutput:
        n_steps = times.size - 1
        traj = np.empty((n_steps + 1, 8))
        traj[:, :6] = (
            self._still_object
            if self._still_object is not None
            else _object_motion(self._contact, self._trajectory, times)
        )
        traj[:, TR_BASE] = angle
        traj[:, TR_BASE + 1] = rate
        if self._node_state is None:
            self._node_state = NodeState(
                *_rest_state(self.model, self._rod, self._damping, float(angle[0]), float(rate[0]))
            )
        out = np.zeros((n_steps + 1, 8))
        done = run_dynamics(
            self._node_state,
            self._anchors,
            self._rod,
            self._damping,
            self._spec,
            traj,
            self._settings,
            out,
            self._states,
            self._status,
        )
        m = done + 1
        # one sum is non-finite if any of its terms is (column 3, the contact's arc
        # length, is NaN out of contact and not checked)
        if (
            int(self._status[0]) < 0
            or done < n_steps
            or not math.isfinite(float(out[:m, :3].sum() + out[:m, 4:].sum()))
        ):
            raise SimulationError(
                f"simulation diverged or failed to converge at t = "
                f"{self.time_s + done * self.dt_s:.5f} s (step {done} of {n_steps}); try a "
                "smaller dt_s"
            )
        self.time_s = float(times[done])
        return PeriodOutput(times, out[:, 0:2], out[:, 2])

    @property
    def state(self) -> DynamicState | None:
        """The whisker's state now (a copy), or None before the first period."""
        if self._node_state is None:
            return None
        x, v, a = self._node_state
        return DynamicState(
            x.copy(),
            v.copy(),
            a.copy(),
            self._anchors.pole.copy(),
            self._anchors.plane.copy(),
            self.time_s,
        )


def free_vibration(
    model: RodModel,
    tip_deflection_mm: float = 10.0,
    duration_s: float = 1.0,
    dt_s: float = DEFAULT_DT_S,
    record_every: int = 0,
) -> SimulationResult:
    """Deflect the tip statically by ``tip_deflection_mm`` along x, release, and simulate."""
    d = finite("tip_deflection_mm", tip_deflection_mm)
    L = model.geometry.length_mm
    # find the tip force giving the requested deflection (small-deflection estimate, refined)
    probe = model.static_force(1e-4, L)
    force = 1e-4 * d / probe.deflection_mm
    for _ in range(3):
        res = model.static_force(force, L)
        force *= d / res.deflection_mm
    res = model.static_force(force, L)
    return simulate(
        model,
        None,
        None,
        duration_s,
        dt_s,
        initial_positions_m=res.positions_m,
        record_every=record_every,
    )
