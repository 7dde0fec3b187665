"""Whisking robots: the whisking pattern generator and its rapid-cessation-of-protraction control.

SCRATCHbot (thesis 3.2.4) and the BIOTACT G1 (3.4.2) turn each whisker's follicle
housing with a motor driven by a whisking pattern generator (WPG). Modelled here:

* **Oscillator**: per side, ``theta_osc(t) = retracted + A (1 - cos(2 pi f_w t + phase)) / 2``
  (deg): fully retracted at phase 0, fully protracted half a whisk later.
* **Rapid cessation of protraction** (eqs. 3.2-3.3): the contact signal of a side is
  ``pi(n) = max_w |H50(x_w)(n)|``, a causal third-order 50 Hz Butterworth low-pass of
  each whisker's ``x`` deflection run sample by sample, maximised over the side's
  whiskers; the gating variable ``z(n) = clip(max((1 - T/tau_z) z(n-1), sigma_z pi(n)), 0, 1)``
  (:func:`rcp_gating`). Protraction is suppressed by ``z`` without touching the
  oscillator's phase: the commanded angle is
  ``retracted + (1 - z)(theta_osc - retracted)``. ``x`` is the Hall sensor's ``x``
  output as a fraction of its calibrated half range (+/-1 at full scale: 5 % and
  95 % of the supply, 3.2.3) times :data:`CONTACT_SIGNAL_SCALE`: the thesis gives
  neither the signal's units nor its scale, so the factor was identified from figure
  3.9's two outcomes on this whisker in closed loop (``scripts/identify_rcp.py``;
  :func:`whisk_contacts` counts them).
* **Contact-induced asymmetry** (2.2.2, an option): a side's protraction amplitude is
  multiplied by ``1 + cia_gain * z_other``, the largest gating variable of the other
  sides (contact on one side protracts the other side further).
* **Motor**: the housing follows the commanded angle as a critically damped
  second-order servo of bandwidth ``motor_bandwidth_hz`` (the thesis does not give
  the actuators' dynamics; 20 Hz keeps a 6 Hz whisk within a few degrees of its
  command). The housing's angle and rate drive the rod model's follicle
  (:class:`vibrissa.whisker.simulate.BaseMotion`), so inertia and ringing in air come
  from the whisker's mechanics.
* **Closed loop**: with feedback (``sigma_z > 0`` or ``cia_gain > 0``) the simulation
  advances one control period at a time (``control_rate_hz``, default 1 kHz, the
  XY robot's and SCRATCHbot's Hall sampling rate in this thesis; the G1 ran its
  loop at 2 kHz, 3.4.1), carrying the whisker's state over
  (``simulate(..., initial_state=...)``); the deflection sampled at the end of a
  period sets the command of the next. Without feedback the whole run is one
  simulation per whisker.

Figure 3.9 was drawn from contact signals simulated in MATLAB with an obstruction
at a fixed protraction angle; :func:`obstacle_whisk` does the same.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.signal import butter, sosfilt_zi

from vibrissa._validate import finite, finite_array, non_negative, positive
from vibrissa.whisker.hall import calibrated_gain
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.simulate import (
    BaseMotion,
    ClosedLoopStepper,
    DynamicState,
    PoleContact,
    SurfaceContact,
    Trajectory,
    rcp_loop,
    same_kernel_type,
    simulate,
)

__all__ = [
    "ContactFilter",
    "RCPControl",
    "VaryingWhiskPattern",
    "WhiskPattern",
    "WhiskerSetup",
    "WhiskingResult",
    "FIGURE_3_9_SETTINGS",
    "Figure39Panel",
    "CONTACT_DIP_FRACTION",
    "CONTACT_SIGNAL_SCALE",
    "count_contacts",
    "check_pole_placement",
    "figure_3_9",
    "motor_follow",
    "obstacle_whisk",
    "pole_position_mm",
    "pole_whisker",
    "rcp_gating",
    "run_whisking",
    "whisk_contacts",
]

#: Full scale of the normalised deflection: the Hall output spans 5-95 % of its
#: supply (3.2.3), i.e. +/-0.45 V_DD about the rest output.
HALF_RANGE_FRACTION = 0.45

#: Scale of the contact signal of eq. 3.2: ``pi`` is this times the largest filtered
#: ``x`` deflection as a fraction of the Hall half range. Identified from figure 3.9's
#: outcomes by scripts/identify_rcp.py (docs/runs/identify_rcp.json): on the simulated
#: SCRATCHbot whisker whisking into a pole in closed loop, sigma_z 0.7 with tau_z T_w/4
#: must give one contact per whisk and sigma_z 2 with tau_z T_w/10 the biphasic whisk
#: (:func:`whisk_contacts`). Identified again after the closed loop stopped reading a
#: zero housing rate at the end of most control periods (issue 32): 2.75, was 3.0.
CONTACT_SIGNAL_SCALE = 2.75

#: :func:`whisk_contacts`' ``dip_deg`` as a fraction of the whisk amplitude: a withdrawal
#: of the housing by 5 % of the amplitude (0.6 deg of SCRATCHbot's 12 deg) separates two
#: contacts.
CONTACT_DIP_FRACTION = 0.05


def _gate_step(z_prev: float, pi_n: float, decay: float, sigma_z: float) -> float:
    """One step of eq. 3.3."""
    return min(max(max(decay * z_prev, sigma_z * pi_n), 0.0), 1.0)


def _check_gains(sigma_z: float, tau_z_s: float, dt_s: float) -> tuple[float, float, float]:
    s = non_negative("sigma_z", sigma_z)
    tau = positive("tau_z_s", tau_z_s)
    dt = positive("dt_s", dt_s)
    if dt > tau:
        raise ValueError(f"tau_z_s ({tau_z_s}) must be at least the step dt_s ({dt_s})")
    return s, tau, dt


def rcp_gating(
    contact: np.ndarray, dt_s: float, sigma_z: float, tau_z_s: float, z0: float = 0.0
) -> np.ndarray:
    """The gating variable of eq. 3.3, one value per sample of ``contact``.

    ``z(n) = clip(max((1 - dt_s/tau_z_s) z(n-1), sigma_z contact(n)), 0, 1)`` with
    ``z(-1) = z0``.

    Parameters
    ----------
    contact : array_like, shape (n,)
        The contact signal ``pi`` (eq. 3.2), one value per control step.
    dt_s : float
        The integration step ``T`` (s).
    sigma_z : float
        Gain, >= 0.
    tau_z_s : float
        Decay time constant (s), >= ``dt_s``.
    z0 : float
        The gating variable before the first sample, in [0, 1].

    Returns
    -------
    ndarray, shape (n,)
    """
    pi = finite_array("contact", contact)
    if pi.ndim != 1:
        raise ValueError(f"contact must be 1-D, got shape {pi.shape}")
    s, tau, dt = _check_gains(sigma_z, tau_z_s, dt_s)
    z = finite("z0", z0)
    if not 0.0 <= z <= 1.0:
        raise ValueError(f"z0 must lie in [0, 1], got {z0}")
    decay = 1.0 - dt / tau
    out = np.empty(pi.size)
    for n in range(pi.size):
        z = _gate_step(z, float(pi[n]), decay, s)
        out[n] = z
    return out


class ContactFilter:
    """The contact signal of one side, sample by sample (eq. 3.2).

    A causal Butterworth low-pass (third order, 50 Hz by default) of each whisker's
    ``x``, whose absolute values are maximised over the side's whiskers.
    """

    def __init__(
        self, n_whiskers: int, rate_hz: float, cutoff_hz: float = 50.0, order: int = 3
    ) -> None:
        rate = positive("control_rate_hz", rate_hz)
        fc = positive("filter cutoff_hz", cutoff_hz)
        if fc >= rate / 2:
            raise ValueError(
                f"filter cutoff ({cutoff_hz} Hz) must be below half the control rate ({rate_hz} Hz)"
            )
        self.sos = butter(int(order), fc, fs=rate, output="sos")
        self.state = np.zeros((int(n_whiskers), *sosfilt_zi(self.sos).shape))
        # one sample at a time in plain floats (sosfilt's transposed direct form II, the
        # same operations in the same order): the closed loop calls this every control
        # period, where sosfilt's per-call overhead cost more than the whisker's dynamics
        self._sections = [tuple(float(c) for c in sec[[0, 1, 2, 4, 5]]) for sec in self.sos]
        self._z = [[[0.0, 0.0] for _ in self._sections] for _ in range(int(n_whiskers))]

    def step(self, x: np.ndarray) -> float:
        """Feed one sample of every whisker's ``x``; return ``pi`` for this sample."""
        best = 0.0
        for w, xw in enumerate(np.atleast_1d(x)):
            y = float(xw)
            zs = self._z[w]
            for (b0, b1, b2, a1, a2), z in zip(self._sections, zs, strict=True):
                x_in = y
                y = b0 * x_in + z[0]
                z[0] = b1 * x_in - a1 * y + z[1]
                z[1] = b2 * x_in - a2 * y
            self.state[w] = zs
            best = max(best, abs(y))
        return best


@dataclass(frozen=True)
class WhiskPattern:
    """The whisking pattern generator's oscillator (angles in degrees).

    Parameters
    ----------
    frequency_hz
        Whisk frequency ``f_w`` (> 0).
    amplitude_deg
        Protraction from full retraction to full protraction (> 0).
    retracted_deg
        Housing angle at full retraction.
    phase_rad
        Oscillator phase at t = 0 (0: fully retracted).
    """

    frequency_hz: float
    amplitude_deg: float = 30.0
    retracted_deg: float = 0.0
    phase_rad: float = 0.0

    def __post_init__(self) -> None:
        positive("frequency_hz", self.frequency_hz)
        positive("amplitude_deg", self.amplitude_deg)
        finite("retracted_deg", self.retracted_deg)
        finite("phase_rad", self.phase_rad)
        if abs(self.retracted_deg) + self.amplitude_deg >= 80.0:
            raise ValueError(
                "retracted_deg and amplitude_deg must keep the housing within +/-80 deg"
            )

    @property
    def period_s(self) -> float:
        """Whisk period ``T_w`` (s)."""
        return 1.0 / self.frequency_hz

    def oscillator_deg(self, t_s: np.ndarray | float) -> np.ndarray:
        """The unmodulated angle at times ``t_s``."""
        ph = 2 * math.pi * self.frequency_hz * np.asarray(t_s, dtype=float) + self.phase_rad
        return self.retracted_deg + self.amplitude_deg * 0.5 * (1.0 - np.cos(ph))

    def command_deg(self, t_s: np.ndarray | float, z: float, gain: float = 1.0) -> np.ndarray:
        """The commanded angle with protraction suppressed by ``z``; the phase is untouched.

        The angle is also scaled by ``gain`` (contact-induced asymmetry).
        """
        osc = self.oscillator_deg(t_s)
        return self.retracted_deg + (1.0 - z) * gain * (osc - self.retracted_deg)


@dataclass(frozen=True)
class VaryingWhiskPattern(WhiskPattern):
    """A :class:`WhiskPattern` whose amplitude changes from whisk to whisk.

    Whisk ``k`` (from full retraction at phase ``2 pi k``) protracts by
    ``amplitudes_deg[k]``; the last one repeats. The angle stays continuous, since
    every whisk starts and ends at ``retracted_deg``. Empty: ``amplitude_deg``.
    """

    amplitudes_deg: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        super().__post_init__()
        for a in self.amplitudes_deg:
            positive("amplitudes_deg", a)
            if abs(self.retracted_deg) + a >= 80.0:
                raise ValueError(
                    "retracted_deg and amplitudes_deg must keep the housing within +/-80 deg"
                )

    def oscillator_deg(self, t_s: np.ndarray | float) -> np.ndarray:
        """The unmodulated angle at times ``t_s``."""
        ph = 2 * math.pi * self.frequency_hz * np.asarray(t_s, dtype=float) + self.phase_rad
        if not self.amplitudes_deg:
            amp: np.ndarray | float = self.amplitude_deg
        else:
            k = np.clip(np.floor(ph / (2 * math.pi)), 0, len(self.amplitudes_deg) - 1)
            amp = np.asarray(self.amplitudes_deg, dtype=float)[k.astype(int)]
        return self.retracted_deg + amp * 0.5 * (1.0 - np.cos(ph))


@dataclass(frozen=True)
class RCPControl:
    """Rapid cessation of protraction (eqs. 3.2-3.3) and contact-induced asymmetry.

    Parameters
    ----------
    sigma_z
        Gain on the contact signal (>= 0; 0: unmodulated whisking).
    tau_z_periods
        Decay time constant as a fraction of the whisk period (thesis: 1/4; the
        strong and fast setting of figure 3.9 b: 1/10).
    cia_gain
        Contact-induced asymmetry: the other sides' protraction grows by this
        fraction of this side's gating variable (>= 0; 0: off).
    cutoff_hz, order
        The contact filter (thesis: 50 Hz, third order).
    signal_scale
        The contact signal ``pi`` per unit of the filtered deflection (a fraction of
        the Hall half range); default :data:`CONTACT_SIGNAL_SCALE`, the identified one.
    """

    sigma_z: float = 0.0
    tau_z_periods: float = 0.25
    cia_gain: float = 0.0
    cutoff_hz: float = 50.0
    order: int = 3
    signal_scale: float = CONTACT_SIGNAL_SCALE

    def __post_init__(self) -> None:
        non_negative("sigma_z", self.sigma_z)
        positive("tau_z_periods", self.tau_z_periods)
        non_negative("cia_gain", self.cia_gain)
        positive("cutoff_hz", self.cutoff_hz)
        positive("signal_scale", self.signal_scale)

    @property
    def active(self) -> bool:
        """Whether any feedback acts."""
        return self.sigma_z > 0.0 or self.cia_gain > 0.0


@dataclass(frozen=True)
class WhiskerSetup:
    """One whisker of a whisking head.

    Parameters
    ----------
    model
        The rod model; its follicle housing is turned by the side's motor.
    contact, trajectory
        The object it may touch and the object's motion (None: whisking in air).
    side
        Index of the side (0, 1, ...) whose contact signal and pattern it shares.
    hall_gain_v
        Hall gain (V per unit tan); default: calibrated for the model's whisker.
    """

    model: RodModel
    contact: PoleContact | SurfaceContact | None = None
    trajectory: Trajectory | None = None
    side: int = 0
    hall_gain_v: float | None = None

    def gain(self) -> float:
        """The Hall gain (V per unit tan)."""
        if self.hall_gain_v is not None:
            return float(self.hall_gain_v)
        return calibrated_gain(self.model.geometry, self.model.n_elements)


@dataclass
class WhiskingResult:
    """A whisking run.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
        Simulation steps.
    tan_x : ndarray, shape (n_whiskers, n)
        Magnet tilt toward x in the housing's frame (what the Hall sensor reads).
    contact_force_n : ndarray, shape (n_whiskers, n)
    angle_deg : ndarray, shape (n_whiskers, n)
        The housing's angle.
    control_time_s : ndarray, shape (m,)
        Control samples.
    command_deg, contact_signal, gating : ndarray, shape (n_sides, m)
        Commanded angle, ``pi`` and ``z`` per side at the control samples.
    deflection : ndarray, shape (n_whiskers, m)
        Normalised ``x`` deflection at the control samples (+/-1 at full scale).
    """

    time_s: np.ndarray
    tan_x: np.ndarray
    contact_force_n: np.ndarray
    angle_deg: np.ndarray
    control_time_s: np.ndarray
    command_deg: np.ndarray
    contact_signal: np.ndarray
    gating: np.ndarray
    deflection: np.ndarray
    dt_s: float
    gains: list[float] = field(default_factory=list)
    #: Magnet tilt toward y (out of the whisking plane), shape (n_whiskers, n).
    tan_y: np.ndarray | None = None


def motor_follow(
    command_deg: np.ndarray,
    dt_s: float,
    bandwidth_hz: float,
    state: tuple[float, float] = (0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray]:
    """Angle (deg) and rate (deg/s) of a critically damped servo following ``command_deg``.

    ``theta'' = w^2 (command - theta) - 2 w theta'`` with ``w = 2 pi bandwidth_hz``;
    ``command_deg[k]`` is held over step k (of ``dt_s``) and each step is advanced
    exactly (the critically damped solution). ``state`` is the (angle,
    rate) before the first step. Returns arrays of ``len(command_deg) + 1`` values,
    the first being ``state``.
    """
    p11, p12, p21, p22 = _servo_matrix(dt_s, bandwidth_hz)
    n = len(command_deg)
    ang = np.empty(n + 1)
    rate = np.empty(n + 1)
    a, r = float(state[0]), float(state[1])
    ang[0], rate[0] = a, r
    for k in range(n):
        u = float(command_deg[k])
        a, r = u + p11 * (a - u) + p12 * r, p21 * (a - u) + p22 * r
        ang[k + 1], rate[k + 1] = a, r
    return ang, rate


def _servo_matrix(dt_s: float, bandwidth_hz: float) -> tuple[float, float, float, float]:
    """The servo's exact step over ``dt_s``: ``(angle, rate) <- P (angle - u, rate) + (u, 0)``."""
    w = 2 * math.pi * positive("motor bandwidth_hz", bandwidth_hz)
    dt = positive("dt_s", dt_s)
    # with e = angle - command (command held): e(t) = (e0 + (r0 + w e0) t) exp(-w t)
    E = math.exp(-w * dt)
    return (1.0 + w * dt) * E, dt * E, -w * w * dt * E, (1.0 - w * dt) * E


def pole_position_mm(
    radial_distance_mm: float,
    contact_angle_deg: float,
    pole_radius_mm: float,
    shaft_radius_mm: float,
) -> tuple[float, float]:
    """Centre (x, z) of a pole (parallel to ``y``) touching the straight whisker.

    The whisker's housing is turned by ``contact_angle_deg``; the pole touches it at
    ``radial_distance_mm`` from the base, on the whisker's protraction (+x) side.
    """
    a = math.radians(contact_angle_deg)
    off = pole_radius_mm + shaft_radius_mm
    return (
        radial_distance_mm * math.sin(a) + off * math.cos(a),
        radial_distance_mm * math.cos(a) - off * math.sin(a),
    )


def pole_whisker(
    model: RodModel,
    radial_distance_mm: float,
    contact_angle_deg: float,
    pole_radius_mm: float = 0.5,
    side: int = 0,
    hall_gain_v: float | None = None,
) -> WhiskerSetup:
    """A whisker facing a stationary vertical pole (:func:`pole_position_mm`)."""
    shaft = float(model.geometry.radius_m(radial_distance_mm * 1e-3)) * 1e3
    pos = pole_position_mm(radial_distance_mm, contact_angle_deg, pole_radius_mm, shaft)
    traj = Trajectory(np.array([0.0, 1e6]), np.array([pos, pos]))
    return WhiskerSetup(model, PoleContact(radius_mm=pole_radius_mm), traj, side, hall_gain_v)


def check_pole_placement(
    radial_distance_mm: float,
    contact_angle_deg: float,
    pattern: WhiskPattern,
    pole_radius_mm: float,
    length_mm: float,
) -> None:
    """Refuse a pole the whisk cannot meet properly, before any simulation.

    The pole must lie within the whisker's length and beyond its own radius from
    the base, outside the whisker's reach at rest (its contact angle beyond full
    retraction, ``pattern.retracted_deg``) and within reach of full protraction.

    Raises
    ------
    ValueError
        One line naming the parameter.
    """
    r = finite("radial_distance_mm", radial_distance_mm)
    c = finite("contact_angle_deg", contact_angle_deg)
    rp = positive("pole_radius_mm", pole_radius_mm)
    if not rp < r <= length_mm:
        raise ValueError(
            f"radial_distance_mm must lie in ({rp:g}, {length_mm:g}] mm (beyond "
            f"the pole's radius, within the whisker's length), got {r:g}"
        )
    if c <= pattern.retracted_deg:
        raise ValueError(
            f"contact_angle_deg ({c:g}) places the pole inside the whisker's reach at rest "
            f"(the whisker rests at the full retraction, {pattern.retracted_deg:g} deg); it "
            "must be greater"
        )
    top = pattern.retracted_deg + pattern.amplitude_deg
    if c >= top:
        raise ValueError(
            f"contact_angle_deg ({c:g}) is at or beyond full protraction "
            f"({top:g} deg): the whisker never reaches the pole"
        )


def _check_setups(whiskers: list[WhiskerSetup], n_sides: int) -> None:
    if not whiskers:
        raise ValueError("at least one whisker is needed")
    for w in whiskers:
        if not isinstance(w.side, int) or not 0 <= w.side < n_sides:
            raise ValueError(f"whisker side must lie in [0, {n_sides - 1}], got {w.side!r}")


def _compiled_inputs(
    steppers: list[ClosedLoopStepper], whiskers: list[WhiskerSetup], pats: list[WhiskPattern]
) -> tuple[Any, ...] | None:
    """The first arguments of :func:`~vibrissa.whisker.simulate.rcp_loop`, or None.

    None when the compiled loop cannot run these whiskers: an object that moves (the
    loop takes one object row for all time), or whiskers whose integrator inputs are of
    different kinds (a compiled tuple must hold one type).
    """
    try:
        # each whisker at rest in its housing at full retraction, as the loop starts it
        inputs = [
            st.kernel_inputs(float(np.radians(pats[w.side].retracted_deg)), 0.0)
            for st, w in zip(steppers, whiskers, strict=True)
        ]
    except ValueError:  # an object that moves
        return None
    bundles = tuple(tuple(getattr(k, f) for k in inputs) for f in ("state", "anchors", "rod"))
    rest = tuple(tuple(getattr(k, f) for k in inputs) for f in ("damping", "contact"))
    if not all(same_kernel_type(b) for b in (*bundles, *rest)):
        return None
    objects = np.array([k.object_row for k in inputs])
    side_of = np.array([w.side for w in whiskers], dtype=np.int64)
    return (*bundles, *rest, inputs[0].settings, objects, side_of)


def run_whisking(
    whiskers: list[WhiskerSetup],
    patterns: list[WhiskPattern] | WhiskPattern,
    control: RCPControl | None,
    duration_s: float,
    *,
    control_rate_hz: float = 1000.0,
    dt_s: float = 2.5e-4,
    motor_bandwidth_hz: float = 20.0,
) -> WhiskingResult:
    """Whisk the head's whiskers for ``duration_s`` under the WPG and its control.

    Parameters
    ----------
    whiskers
        The whiskers; each belongs to a side (``WhiskerSetup.side``).
    patterns
        One :class:`WhiskPattern` per side (or one for every side).
    control
        RCP and CIA (None: unmodulated).
    duration_s
        Simulated time (s); rounded to whole control periods.
    control_rate_hz
        Rate of the control loop (and of the recorded control samples).
    dt_s
        The rod's internal step; must divide the control period.
    motor_bandwidth_hz
        Bandwidth of the housing's servo.
    """
    ctrl = control if control is not None else RCPControl()
    pats = [patterns] if isinstance(patterns, WhiskPattern) else list(patterns)
    n_sides = max(len(pats), max((w.side for w in whiskers), default=0) + 1)
    if len(pats) == 1:
        pats = pats * n_sides
    if len(pats) != n_sides:
        raise ValueError(f"{len(pats)} patterns for {n_sides} sides")
    _check_setups(whiskers, n_sides)
    T = positive("duration_s", duration_s)
    rate = positive("control_rate_hz", control_rate_hz)
    dt = positive("dt_s", dt_s)
    spp = int(round(1.0 / (rate * dt)))
    if spp < 1 or abs(spp * dt * rate - 1.0) > 1e-9:
        raise ValueError(f"dt_s ({dt_s}) must divide the control period (1/{control_rate_hz} s)")
    n_ctrl = int(round(T * rate))
    if n_ctrl < 1:
        raise ValueError(f"duration_s ({duration_s}) is shorter than one control period")
    tc = 1.0 / rate
    n_w = len(whiskers)
    gains = [w.gain() for w in whiskers]
    full_tan = [HALF_RANGE_FRACTION * 5.0 / g for g in gains]
    filters = [
        ContactFilter(sum(w.side == s for w in whiskers), rate, ctrl.cutoff_hz, ctrl.order)
        for s in range(n_sides)
    ]
    taus = [ctrl.tau_z_periods * p.period_s for p in pats]
    decays = []
    for s in range(n_sides):
        _check_gains(ctrl.sigma_z, taus[s], tc)
        decays.append(1.0 - tc / taus[s])
    n_steps = n_ctrl * spp
    time_s = np.arange(n_steps + 1) * dt
    tan_x = np.zeros((n_w, n_steps + 1))
    tan_y = np.zeros((n_w, n_steps + 1))
    force = np.zeros((n_w, n_steps + 1))
    angle = np.zeros((n_w, n_steps + 1))
    ctime = np.arange(n_ctrl + 1) * tc
    command = np.zeros((n_sides, n_ctrl + 1))
    pis = np.zeros((n_sides, n_ctrl + 1))
    zs = np.zeros((n_sides, n_ctrl + 1))
    defl = np.zeros((n_w, n_ctrl + 1))
    motors = [(p.retracted_deg, 0.0) for p in pats]
    for s in range(n_sides):
        command[s, 0] = pats[s].command_deg(0.0, 0.0)
        angle[[i for i, w in enumerate(whiskers) if w.side == s], 0] = pats[s].retracted_deg

    def run(
        w: int, k0: int, k1: int, ang: np.ndarray, rt: np.ndarray, state: DynamicState | None
    ) -> DynamicState | None:
        wh = whiskers[w]
        bm = BaseMotion(time_s[k0 : k1 + 1], np.radians(ang), np.radians(rt))
        res = simulate(
            wh.model,
            wh.contact,
            wh.trajectory,
            (k1 - k0) * dt,
            dt,
            initial_state=state,
            base_motion=bm,
            linear_free_flight=False,
        )
        tan_x[w, k0 : k1 + 1] = res.tan_xy[:, 0]
        tan_y[w, k0 : k1 + 1] = res.tan_xy[:, 1]
        force[w, k0 : k1 + 1] = res.contact_force_n
        angle[w, k0 : k1 + 1] = ang
        return res.final_state

    if not ctrl.active:
        for s in range(n_sides):
            cmd = pats[s].command_deg(time_s[:-1], 0.0)
            ang, rt = motor_follow(cmd, dt, motor_bandwidth_hz, motors[s])
            command[s] = pats[s].command_deg(ctime, 0.0)
            for w in [i for i, wh in enumerate(whiskers) if wh.side == s]:
                run(w, 0, n_steps, ang, rt, None)
        for w in range(n_w):
            defl[w] = tan_x[w, ::spp] / full_tan[w]
        for s in range(n_sides):
            members = [i for i, wh in enumerate(whiskers) if wh.side == s]
            for n in range(n_ctrl + 1):
                pis[s, n] = ctrl.signal_scale * filters[s].step(defl[members, n])
        return WhiskingResult(
            time_s, tan_x, force, angle, ctime, command, pis, zs, defl, dt, gains, tan_y
        )

    steppers = [ClosedLoopStepper(w.model, w.contact, w.trajectory, dt) for w in whiskers]
    sides = [[i for i, wh in enumerate(whiskers) if wh.side == s] for s in range(n_sides)]
    compiled = _compiled_inputs(steppers, whiskers, pats)
    if compiled is not None:
        failure = np.zeros(3, dtype=np.int64)
        done = rcp_loop(
            *compiled,
            np.array([p.oscillator_deg(time_s) for p in pats]),
            np.array([p.oscillator_deg(ctime) for p in pats]),
            np.array([float(p.retracted_deg) for p in pats]),
            np.array(_servo_matrix(dt, motor_bandwidth_hz)),
            np.array([[float(a), float(r)] for a, r in motors]),
            np.ascontiguousarray(filters[0].sos[:, [0, 1, 2, 4, 5]]),
            np.zeros((n_w, filters[0].sos.shape[0], 2)),
            np.array(full_tan),
            np.array(decays),
            float(ctrl.sigma_z),
            float(ctrl.cia_gain),
            float(ctrl.signal_scale),
            spp,
            tan_x,
            tan_y,
            force,
            angle,
            command,
            pis,
            zs,
            defl,
            failure,
        )
        if done < n_ctrl:
            n, _, steps = (int(v) for v in failure)
            raise SimulationError(
                "simulation diverged or failed to converge at t = "
                f"{(n * spp + steps) * dt:.5f} s (step {steps} of {spp}); try a smaller dt_s"
            )
        return WhiskingResult(
            time_s, tan_x, force, angle, ctime, command, pis, zs, defl, dt, gains, tan_y
        )
    for n in range(n_ctrl):
        k0, k1 = n * spp, (n + 1) * spp
        for s in range(n_sides):
            others = [zs[o, n] for o in range(n_sides) if o != s]
            gain = 1.0 + ctrl.cia_gain * (max(others) if others else 0.0)
            cmd = pats[s].command_deg(time_s[k0:k1], zs[s, n], gain)
            ang, rt = motor_follow(cmd, dt, motor_bandwidth_hz, motors[s])
            motors[s] = (float(ang[-1]), float(rt[-1]))
            command[s, n + 1] = float(pats[s].command_deg(ctime[n + 1], zs[s, n], gain))
            ang_rad, rt_rad = np.radians(ang), np.radians(rt)
            for w in sides[s]:
                res = steppers[w].advance_sampled(ang_rad, rt_rad)
                tan_x[w, k0 : k1 + 1] = res.tan_xy[:, 0]
                tan_y[w, k0 : k1 + 1] = res.tan_xy[:, 1]
                force[w, k0 : k1 + 1] = res.contact_force_n
                angle[w, k0 : k1 + 1] = ang
        for w in range(n_w):
            defl[w, n + 1] = tan_x[w, k1] / full_tan[w]
        for s in range(n_sides):
            pis[s, n + 1] = ctrl.signal_scale * filters[s].step(defl[sides[s], n + 1])
            zs[s, n + 1] = _gate_step(zs[s, n], pis[s, n + 1], decays[s], ctrl.sigma_z)
    return WhiskingResult(
        time_s, tan_x, force, angle, ctime, command, pis, zs, defl, dt, gains, tan_y
    )


@dataclass
class ObstacleWhisk:
    """Figure 3.9's simulation (see :func:`obstacle_whisk`); arrays per side ``(2, n)``."""

    time_s: np.ndarray
    angle_deg: np.ndarray
    contact_signal: np.ndarray
    gating: np.ndarray
    obstacle_deg: tuple[float, float]


def obstacle_whisk(
    sigma_z: float,
    tau_z_periods: float,
    *,
    frequency_hz: float = 8.0,
    amplitude_deg: float = 80.0,
    retracted_deg: float = 40.0,
    obstacle_deg: tuple[float, float] = (100.0, 125.0),
    deflection_scale_deg: float = 20.0,
    n_whisks: float = 3.0,
    rate_hz: float = 1000.0,
) -> ObstacleWhisk:
    """Figure 3.9: two sides whisking against obstructions at fixed protraction angles.

    As in the thesis (3.4.2), the contact signal is simulated: a whisker commanded
    past the obstruction ``theta'`` of its side is held there and deflected by the
    excess, ``x = (theta - theta') / deflection_scale_deg`` (full scale at
    ``deflection_scale_deg`` past it), filtered and gated by eqs. 3.2-3.3. Side 0
    (left, obstruction at 100 deg) is reached, side 1 (right, 125 deg) is not with
    the default 40-130 deg whisk.

    Returns the commanded angles, contact signals and gating variables per side.
    """
    pattern = WhiskPattern(frequency_hz, 1.0, 0.0)  # validates the frequency
    positive("amplitude_deg", amplitude_deg)
    scale = positive("deflection_scale_deg", deflection_scale_deg)
    tau = positive("tau_z_periods", tau_z_periods) * pattern.period_s
    dt = 1.0 / positive("rate_hz", rate_hz)
    s, tau, dt = _check_gains(sigma_z, tau, dt)
    n = int(round(positive("n_whisks", n_whisks) * pattern.period_s / dt)) + 1
    t = np.arange(n) * dt
    osc = retracted_deg + amplitude_deg * 0.5 * (1.0 - np.cos(2 * math.pi * frequency_hz * t))
    ang = np.zeros((2, n))
    pis = np.zeros((2, n))
    zs = np.zeros((2, n))
    for side in range(2):
        filt = ContactFilter(1, rate_hz)
        z = 0.0
        for k in range(n):
            ang[side, k] = retracted_deg + (1.0 - z) * (osc[k] - retracted_deg)
            x = max(ang[side, k] - obstacle_deg[side], 0.0) / scale
            pis[side, k] = filt.step(np.array([x]))
            z = _gate_step(z, pis[side, k], 1.0 - dt / tau, s)
            zs[side, k] = z
    return ObstacleWhisk(t, ang, pis, zs, (float(obstacle_deg[0]), float(obstacle_deg[1])))


#: Figure 3.9's two panels (3.4.2): panel -> (sigma_z, tau_z as a fraction of T_w); (a)
#: stops each protraction at the first contact, (b) the biphasic whisk.
FIGURE_3_9_SETTINGS: dict[str, tuple[float, float]] = {"a": (0.7, 0.25), "b": (2.0, 0.1)}


@dataclass(frozen=True)
class Figure39Panel:
    """One panel of figure 3.9: the run of :func:`obstacle_whisk` and what it shows.

    Attributes
    ----------
    sigma_z, tau_z_periods : float
        The gain and time constant (fraction of the whisk period) of eq. 3.3.
    contacts_left, contacts_right : int
        Contact episodes per side over the run (:func:`count_contacts`, release 2 deg
        below the obstruction).
    whisks : int
        Whisks in the run.
    z_max : float
        Largest gating variable ``z`` (left side).
    z_at_next_whisk : float or None
        ``z`` at the left side's first contact of the second or a later whisk.
    run : ObstacleWhisk
        The simulated arrays.
    """

    sigma_z: float
    tau_z_periods: float
    contacts_left: int
    contacts_right: int
    whisks: int
    z_max: float
    z_at_next_whisk: float | None
    run: ObstacleWhisk

    def summary(self) -> dict[str, Any]:
        """The panel's numbers, JSON-ready (everything but the arrays)."""
        return {
            "sigma_z": self.sigma_z,
            "tau_z_periods": self.tau_z_periods,
            "contacts_left": self.contacts_left,
            "contacts_right": self.contacts_right,
            "whisks": self.whisks,
            "z_max": self.z_max,
            "z_at_next_whisk": self.z_at_next_whisk,
        }


def figure_3_9(
    settings: Mapping[str, tuple[float, float]] | None = None,
    *,
    frequency_hz: float = 8.0,
    n_whisks: int = 3,
) -> dict[str, Figure39Panel]:
    """Figure 3.9 (rapid cessation of protraction): :func:`obstacle_whisk` at each panel.

    It runs at each panel's ``(sigma_z, tau_z_periods)`` (default
    :data:`FIGURE_3_9_SETTINGS`), with its contacts counted.

    Returns
    -------
    dict of str to Figure39Panel
        Panel name -> the run and its numbers.
    """
    out = {}
    for key, (s, tau) in (FIGURE_3_9_SETTINGS if settings is None else settings).items():
        r = obstacle_whisk(s, tau, frequency_hz=frequency_hz, n_whisks=n_whisks)
        touching = r.angle_deg[0] > r.obstacle_deg[0]
        onsets = np.flatnonzero(touching[1:] & ~touching[:-1]) + 1
        later = onsets[r.time_s[onsets] >= 1.0 / frequency_hz]
        out[key] = Figure39Panel(
            sigma_z=s,
            tau_z_periods=tau,
            contacts_left=count_contacts(r.angle_deg[0] - r.obstacle_deg[0], 0.0, -2.0),
            contacts_right=count_contacts(r.angle_deg[1] - r.obstacle_deg[1], 0.0, -2.0),
            whisks=int(n_whisks),
            z_max=float(r.gating[0].max()),
            z_at_next_whisk=float(r.gating[0][later[0]]) if later.size else None,
            run=r,
        )
    return out


def count_contacts(signal: np.ndarray, threshold: float, release: float | None = None) -> int:
    """Contact episodes of ``signal``, found with hysteresis.

    Each starts when it rises above ``threshold`` and ends only once it falls below
    ``release`` (default ``threshold``).
    """
    lo = threshold if release is None else float(release)
    if lo > threshold:
        raise ValueError(f"release ({release}) must not exceed threshold ({threshold})")
    n = 0
    on = False
    for v in np.asarray(signal, dtype=float):
        if not on and v > threshold:
            on = True
            n += 1
        elif on and v < lo:
            on = False
    return n


def whisk_contacts(
    time_s: np.ndarray,
    angle_deg: np.ndarray,
    in_contact: np.ndarray,
    frequency_hz: float,
    dip_deg: float,
    phase_rad: float = 0.0,
) -> np.ndarray:
    """Contacts per whisk of a closed-loop run, as figure 3.9 counts them.

    Figure 3.9 (b): the whisker "quickly detached from the simulated obstacle ...
    and protraction begins again within a single whisk, leading to a biphasic whisk
    profile and two distinct contacts"; (a): protraction is suppressed during the
    contact and the whisker stays on the obstacle, one contact per whisk. On a
    physical whisker the tip may also bounce off the pole at impact while the
    housing keeps protracting; that is one contact. So two runs of contact are
    distinct contacts only if, between them, the housing withdrew (its angle fell at
    least ``dip_deg`` below its angle at the end of the first run) and protraction
    resumed (the angle rose again by at least ``dip_deg / 2`` from its lowest point
    before the second run began); otherwise they are one contact. A whisk with two
    or more contacts is biphasic. Each contact belongs to the whisk in which it
    starts; whisk ``k`` spans oscillator phases ``[2 pi k, 2 pi (k + 1))``.

    Parameters
    ----------
    time_s : array_like, shape (n,)
        Sample times (s), increasing.
    angle_deg : array_like, shape (n,)
        The housing's angle at those times.
    in_contact : array_like of bool, shape (n,)
        Whether the whisker touches the object (e.g. contact force > 0).
    frequency_hz : float
        The whisk frequency.
    dip_deg : float
        How far the housing must withdraw to separate two contacts (> 0).
    phase_rad : float
        The oscillator's phase at ``t = 0``.

    Returns
    -------
    ndarray of int, shape (n_whisks,)
        Contacts in each whole or partial whisk covered by ``time_s``.
    """
    t = finite_array("time_s", time_s)
    a = finite_array("angle_deg", angle_deg)
    on = np.asarray(in_contact, dtype=bool)
    if not (t.ndim == 1 and a.shape == t.shape and on.shape == t.shape and t.size > 0):
        raise ValueError("time_s, angle_deg and in_contact must be 1-D of the same length")
    f = positive("frequency_hz", frequency_hz)
    dip = positive("dip_deg", dip_deg)
    whisk = np.floor((2 * math.pi * f * t + finite("phase_rad", phase_rad)) / (2 * math.pi))
    whisk = (whisk - whisk[0]).astype(int)
    edges = np.diff(np.concatenate([[0], on.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    counts = np.zeros(int(whisk[-1]) + 1, dtype=int)
    for i, st in enumerate(starts):
        if i > 0:
            gap = a[ends[i - 1] - 1 : st + 1]
            low = int(np.argmin(gap))
            withdrew = gap[0] - gap[low] >= dip
            resumed = gap[low:].max() - gap[low] >= dip / 2
            if not (withdrew and resumed):
                continue
        counts[whisk[st]] += 1
    return counts
