"""The XY positioning robot and its minimal-impingement (MI) control loop.

Thesis 3.3: a Yamaha PXYX Cartesian robot (350 x 650 mm range, up to 720 mm/s,
repeatability +/-0.01 mm) carries an object into a whisker fixed to the table.
MI control (3.3.2): "move an object into the whisker at a given speed until a
deflection threshold is crossed, at which point the robot retracts the object as
fast as possible (720 mm/s). Temporal latency for the loop is ~300 ms from initial
contact due to the controller duty cycle."

Modelled here:

* **Motion** (:mod:`vibrissa.robots.stage_motion`): constant approach speed; on the
  controller's command one point-to-point move brakes, reverses at up to the
  retraction speed and stops at the retract target, with a finite acceleration
  (``acceleration_mm_s2``, 10 m/s^2, about 1 g, assumed: typical of ball-screw
  Cartesian robots; the thesis gives only the speeds) and optionally a jerk limit
  (``jerk_mm_s3``, none by default). The target lies ``retract_clearance_mm``
  behind where the object first touches the resting whisker: 3 mm, **identified**
  (``scripts/identify_stage.py``, ``docs/runs/identify_stage.json``) as the nearest
  point from which the approach can start at rest and reach 216 mm/s, among the
  settings meeting the most of ``vibrissa identify``'s observables. Where the move
  ends decides how fast the object leaves the whisker as it springs back through
  its rest position, and with it the ringing after release (3.3: MI "keeps whisker
  ringing after contact to a minimum"); a target 10 mm further back releases it at
  full speed and every trial rings. Positioning error: Gaussian with sigma =
  repeatability / 2 on the object's starting position, or a trial's
  :class:`~vibrissa.robots.xy_variability.TrialPerturbation`.
* **Loop latency**: the controller polls the sensor once per duty cycle and the
  command takes effect after a fixed pipeline delay. The threshold crossing is
  therefore seen at a uniformly distributed phase of the duty cycle: latency from
  the crossing = ``latency_s - duty_cycle_s / 2 + U(0, duty_cycle_s)``. The thesis
  counts the loop's latency "from initial contact" (~300 ms, 3.3.2); the threshold
  is crossed some 6-106 ms after first contact (5-95 % over a 6 x 6 grid, sooner
  for close, fast contacts; ``vibrissa identify``, ``mi_latency_ms``), so the
  pipeline delay, 272 ms, is identified as the value that makes the median time
  from first contact to retraction 300 ms over the chapter-4 grid
  (``scripts/identify_parameters.py``). The duty cycle, 15.625 ms, is the default
  timer resolution of Windows (64 Hz system clock), the granularity of a MATLAB
  polling loop of the time; the thesis gives no spread. Each trial records its
  ``contact_onset_s``, ``threshold_time_s``, ``retract_start_s`` and
  ``contact_end_s`` (see :class:`TrialResult`).
* **Recording**: the Hall sensor is sampled at the protocol's rate; each trial is
  aligned to its peak deflection and cut to a window around it (+/-325 ms in
  chapter 4, +/-750 ms in chapter 5). The whisker rests before contact, so any part
  of the window before the simulation starts is the sensor's resting output.
* **Directions**: trials in -x are simulated with the motion mirrored and then
  converted (x channel reflected about 2.5 V) "so all data samples were
  equivalent" (4.2).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from vibrissa._validate import in_range, non_negative, positive
from vibrissa.robots.stage_motion import mi_axis_motion
from vibrissa.robots.xy_variability import TrialPerturbation
from vibrissa.whisker.geometry import WhiskerGeometry
from vibrissa.whisker.hall import HallSensor, steps_per_sample
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import (
    PoleContact,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import Surface, make_surface

__all__ = [
    "LatencyModel",
    "PoleStimulus",
    "SurfaceStimulus",
    "TrialResult",
    "XYStage",
    "run_trial",
]


@dataclass(frozen=True)
class LatencyModel:
    """Controller loop latency from the threshold crossing (s).

    Mean plus a uniform jitter over one duty cycle (s). Defaults: see the module docstring.
    """

    latency_s: float = 0.272
    duty_cycle_s: float = 0.015625

    def __post_init__(self) -> None:
        positive("latency_s", self.latency_s)
        non_negative("duty_cycle_s", self.duty_cycle_s)
        if self.duty_cycle_s / 2 > self.latency_s:
            raise ValueError("duty_cycle_s must not exceed twice latency_s")

    def sample(self, rng: np.random.Generator) -> float:
        """One latency draw (s)."""
        return self.latency_s - self.duty_cycle_s / 2 + rng.uniform(0.0, self.duty_cycle_s)


@dataclass(frozen=True)
class XYStage:
    """The XY positioning robot with its MI controller (thesis 3.3)."""

    range_x_mm: float = 350.0
    range_y_mm: float = 650.0
    max_speed_mm_s: float = 720.0
    retract_speed_mm_s: float = 720.0
    acceleration_mm_s2: float = 10_000.0
    jerk_mm_s3: float = float("inf")
    repeatability_mm: float = 0.01
    latency: LatencyModel = field(default_factory=LatencyModel)
    threshold_v: float = 0.05
    approach_gap_mm: float = 1.0
    retract_clearance_mm: float = 3.0
    max_travel_mm: float = 80.0

    def __post_init__(self) -> None:
        positive("max_speed_mm_s", self.max_speed_mm_s)
        in_range("retract_speed_mm_s", self.retract_speed_mm_s, 1e-9, self.max_speed_mm_s)
        positive("acceleration_mm_s2", self.acceleration_mm_s2)
        if not self.jerk_mm_s3 > 0:
            raise ValueError(f"jerk_mm_s3 must be > 0 (inf for none), got {self.jerk_mm_s3!r}")
        non_negative("repeatability_mm", self.repeatability_mm)
        positive("threshold_v", self.threshold_v)
        positive("approach_gap_mm", self.approach_gap_mm)
        non_negative("retract_clearance_mm", self.retract_clearance_mm)
        positive("max_travel_mm", self.max_travel_mm)

    def check_speed(self, speed_mm_s: float) -> float:
        """Validate an approach speed against the robot's limit."""
        return in_range("speed_mm_s", speed_mm_s, 1e-6, self.max_speed_mm_s, "mm/s")

    def to_dict(self) -> dict:
        """Plain dict of the parameters."""
        d = asdict(self)
        d["name"] = "xy-stage (Yamaha PXYX + RCX222, simulated)"
        return d


@dataclass(frozen=True)
class PoleStimulus:
    """A thin vertical pole (a corner) meeting the shaft at ``radial_distance_mm``."""

    radial_distance_mm: float
    radius_mm: float = 0.5
    friction: float = 0.3


@dataclass(frozen=True)
class SurfaceStimulus:
    """The angled textured corner of thesis 5.2, meeting the whisker tip."""

    texture: str
    angle_deg: float
    surface_seed: int = 0


@dataclass
class TrialResult:
    """One recorded trial.

    Event times are in seconds on the recording's own time axis: 0 is the peak
    deflection (the sample ``peak_index`` of ``signal_v``), earlier events are
    negative. An event that did not happen is ``nan``.

    Attributes
    ----------
    signal_v
        Sensor output aligned to peak deflection, shape (n_channels=2, n_samples).
    peak_index
        Index of the peak in ``signal_v``.
    contact_onset_s
        First instant the object touched the whisker.
    threshold_time_s
        The instant the sensor output first crossed the MI threshold (``nan`` if it
        never did, e.g. the whisker slipped off first).
    retract_start_s
        The instant the controller's retract command took effect (the stage starts
        braking). Without a threshold crossing the stage stops at the end of its
        travel (``max_travel_mm``) and this is that instant.
    contact_end_s
        End of the MI contact: the last touch of the last contact episode that
        began while the stage was advancing (a bounce at impact is part of the
        contact; the object meeting the whisker again on its way back, after the
        whisker slipped past it, is not).
    latency_s
        The controller's loop latency drawn for this trial, from the threshold
        crossing to the command taking effect.
    contact_duration_s
        Total time the object was in contact with the whisker.
    slipped_off
        True if the MI contact ended while the stage was still advancing: the
        whisker slipped past the object before the retraction (thesis 4.2).
    saturated
        True if the sensor clipped at its range inside the recorded window.
    peak_deflection_v
        Peak |V_x - 2.5| (V).
    """

    signal_v: np.ndarray
    peak_index: int
    contact_onset_s: float
    threshold_time_s: float
    retract_start_s: float
    contact_end_s: float
    latency_s: float
    contact_duration_s: float
    slipped_off: bool
    saturated: bool
    peak_deflection_v: float

    @property
    def mi_latency_s(self) -> float:
        """Loop latency as the thesis counts it: first contact to retraction (3.3.2)."""
        return self.retract_start_s - self.contact_onset_s


#: Breaks in contact shorter than this (s) belong to one contact: the whisker may
#: chatter on the object for a few steps without leaving it.
_CONTACT_GAP_S = 0.005


def _mi_contact(
    time: np.ndarray, touching: np.ndarray, gap_s: float, advancing_until_s: float
) -> tuple[float, float]:
    """Start and end (s) of the MI contact (nan, nan if the object never touched).

    Touches separated by less than ``gap_s`` form one episode. The MI contact runs
    from the first touch to the end of the last episode that began while the stage
    was still advancing (before ``advancing_until_s``): the whisker may bounce off
    the object at impact and be caught again, which is one contact; an episode that
    begins after the stage turned back (the object meeting the whisker from behind
    after it slipped past) is not.
    """
    idx = np.flatnonzero(touching)
    if idx.size == 0:
        return float("nan"), float("nan")
    t = time[idx]
    breaks = np.flatnonzero(np.diff(t) > gap_s)
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks, [idx.size - 1]])
    kept = np.flatnonzero(t[starts] < advancing_until_s)
    last = ends[kept[-1]] if kept.size else ends[0]
    return float(t[0]), float(t[last])


def _hall_input(
    tan: np.ndarray, sensor: HallSensor, perturbation: TrialPerturbation | None
) -> np.ndarray:
    """The magnet's tangents as the Hall IC of this trial reads them (offset and gain)."""
    if perturbation is None:
        return tan
    offset = np.asarray(perturbation.sensor_offset_v, dtype=float) / sensor.gain_v
    return tan * perturbation.sensor_gain + offset


def run_trial(
    stage: XYStage,
    model: RodModel,
    sensor: HallSensor,
    stimulus: PoleStimulus | SurfaceStimulus,
    speed_mm_s: float,
    direction: int,
    window_s: tuple[float, float],
    rng: np.random.Generator,
    dt_s: float = 2.5e-4,
    surface: Surface | None = None,
    perturbation: TrialPerturbation | None = None,
) -> TrialResult:
    """Simulate one MI contact and record it as the thesis did.

    Parameters
    ----------
    stage
        The robot.
    model
        The whisker (possibly drifted) to simulate.
    sensor
        The Hall sensor (calibrated on the nominal whisker) with the protocol's rate.
    stimulus
        Pole at a radial distance, or textured surface at an angle.
    speed_mm_s
        Approach speed.
    direction
        +1 (object moves +x) or -1 (mirrored; converted back on recording).
    window_s
        Seconds kept before and after the peak.
    rng
        Random generator of this trial (latency, positioning error, noise).
    dt_s
        Internal time step (s); must divide the sensor's sample period
        (:func:`~vibrissa.whisker.hall.steps_per_sample`).
    surface
        Height field for a surface stimulus (default: built from the texture).
    perturbation
        This trial's physical variability (:mod:`vibrissa.robots.xy_variability`):
        its position error replaces the default placement draw (Gaussian, sigma =
        repeatability / 2), the whisker's residual rest angle (creep) moves the contact
        by ``r tan(angle)`` along the motion, and the Hall offset and gain act on the
        sensor's input. Its ``modulus_factor`` is the caller's to apply to ``model``.
        ``None``: the default placement draw only.
    """
    v = stage.check_speed(speed_mm_s)
    step = steps_per_sample(dt_s, sensor.sample_rate_hz)
    if direction not in (1, -1):
        raise ValueError(f"direction must be +1 or -1, got {direction!r}")
    g: WhiskerGeometry = model.geometry
    latency = stage.latency.sample(rng)
    if perturbation is None:
        jitter = rng.normal(0.0, stage.repeatability_mm / 2, 2)
    else:
        jitter = np.asarray(perturbation.position_offset_mm, dtype=float).copy()
    sgn = float(direction)
    acc = stage.acceleration_mm_s2
    vr = stage.retract_speed_mm_s
    if isinstance(stimulus, PoleStimulus):
        r = in_range("radial_distance_mm", stimulus.radial_distance_mm, 1e-6, g.length_mm, "mm")
        contact: PoleContact | SurfaceContact = PoleContact(
            radius_mm=stimulus.radius_mm, friction=stimulus.friction
        )
        clearance = stimulus.radius_mm + float(g.radius_m(r * 1e-3)) * 1e3
        x_start = -(clearance + stage.approach_gap_mm) + jitter[0]
        z_ref = r + jitter[1]
        r_contact = r
    elif isinstance(stimulus, SurfaceStimulus):
        in_range("angle_deg", stimulus.angle_deg, 1e-6, 90.0 - 1e-6, "deg")
        surf = (
            surface
            if surface is not None
            else make_surface(stimulus.texture, stimulus.surface_seed)
        )
        # geometry worked out for +x; a -x trial meets the mirror-image surface
        n, u, _ = SurfaceContact(surf, angle_deg=stimulus.angle_deg).frame()
        contact = SurfaceContact(surf, angle_deg=stimulus.angle_deg, side=direction)
        # the plane starts approach_gap_mm (along x) short of touching the tip, at a
        # random place on the sheet so that each trial meets different grains
        tip = np.array([0.0, 0.0, g.length_m])
        gap_normal = (stage.approach_gap_mm + g.tip_radius_mm) * 1e-3 * n[0]
        origin = tip - n * gap_normal
        origin += u * rng.uniform(0, 8e-3)
        x_start = origin[0] * 1e3 + jitter[0]
        z_ref = origin[2] * 1e3 + jitter[1]
        r_contact = g.length_mm
    else:
        raise TypeError(f"unsupported stimulus {type(stimulus).__name__}")
    if perturbation is not None:
        # a rest shape tilted towards the motion (+x here) meets the object later
        tilt = sgn * float(perturbation.rest_angle_rad[0])
        x_start -= r_contact * np.tan(tilt)

    # the retract move ends retract_clearance_mm behind the object's first touch of the
    # resting whisker (x_start is approach_gap_mm short of it)
    x_end = x_start + stage.approach_gap_mm - stage.retract_clearance_mm

    def traj_for(t_rev: float, t_end: float) -> Trajectory:
        dt_traj = min(1e-3, 4 * dt_s)
        t = np.arange(0.0, t_end + dt_traj, dt_traj)
        x, vx = mi_axis_motion(t, v, t_rev, vr, acc, stage.jerk_mm_s3, x_start, x_end)
        pos = np.column_stack([sgn * x, np.full(t.size, z_ref)])
        vel = np.column_stack([sgn * vx, np.zeros(t.size)])
        return Trajectory(t, pos, vel)

    # phase 1: advance until the controller sees the threshold
    t_max = stage.max_travel_mm / v
    tan_thr = stage.threshold_v / sensor.gain_v
    approach = traj_for(1e9, t_max)
    first = simulate(model, contact, approach, t_max, dt_s, stop_when_tan_x_exceeds=tan_thr)
    if first.stopped_early:
        t_c = float(first.time_s[-1])
        t_rev = t_c + latency
    else:
        t_c = float("nan")
        t_rev = t_max
    # phase 2: keep advancing for the latency, then brake and retract
    t_peak_guess = t_rev + v / acc
    t_end = t_peak_guess + window_s[1] + 0.05
    traj = traj_for(t_rev, t_end + 1.0)
    parts = [first]
    state = first.final_state
    while True:
        remaining = t_end - state.time_s
        if remaining > dt_s / 2:
            nxt = simulate(model, contact, traj, remaining, dt_s, initial_state=state)
            parts.append(nxt)
            state = nxt.final_state
        tan = np.concatenate([parts[0].tan_xy] + [p.tan_xy[1:] for p in parts[1:]])
        force = np.concatenate(
            [parts[0].contact_force_n] + [p.contact_force_n[1:] for p in parts[1:]]
        )
        tan = tan * np.array([sgn, 1.0])  # convert -x trials: equivalent to +x
        volts = sensor.read(_hall_input(tan, sensor, perturbation), 1.0 / dt_s, rng)
        dev = np.abs(volts[:, 0] - sensor.offset_v)
        k_peak = int(np.argmax(dev))
        n_before = int(round(window_s[0] * sensor.sample_rate_hz))
        n_after = int(round(window_s[1] * sensor.sample_rate_hz))
        if k_peak + n_after < volts.shape[0] or t_end > t_max + 10.0:
            break
        t_end += window_s[1]
    time = np.concatenate([parts[0].time_s] + [p.time_s[1:] for p in parts[1:]])
    t_peak = float(time[k_peak * step])  # sample k of the sensor is internal step k * step
    rest_tan = _hall_input(np.zeros((max(n_before, 1) * step, 2)), sensor, perturbation)
    rest = sensor.read(rest_tan, 1.0 / dt_s, rng)
    padded = np.concatenate([rest[: max(0, n_before - k_peak)], volts], axis=0)
    k_peak += max(0, n_before - k_peak)
    seg = padded[k_peak - n_before : k_peak + n_after + 1]
    in_contact = force > 0
    duration = float(np.count_nonzero(in_contact) * dt_s)
    # the stage advances until it has braked to a stop after t_rev
    t_stop = t_rev + v / acc + (acc / stage.jerk_mm_s3) / 2
    t_on, t_off = _mi_contact(time, in_contact, _CONTACT_GAP_S, t_stop)
    slipped = bool(np.isfinite(t_off) and t_off < t_stop)
    saturated = bool(np.any(seg <= sensor.v_min) or np.any(seg >= sensor.v_max))
    return TrialResult(
        signal_v=np.ascontiguousarray(seg.T),
        peak_index=n_before,
        contact_onset_s=t_on - t_peak,
        threshold_time_s=t_c - t_peak,
        retract_start_s=t_rev - t_peak,
        contact_end_s=t_off - t_peak,
        latency_s=latency,
        contact_duration_s=duration,
        slipped_off=slipped,
        saturated=saturated,
        peak_deflection_v=float(dev.max()),
    )
