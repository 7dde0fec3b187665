"""A whisker on a Roomba, dragged over the floor (thesis 6.2).

"A SCRATCHbot whisker was fixed to a Roomba vacuum cleaner robot" (6.1) and data
were recorded while it turned clockwise or anticlockwise for 16 s, or ran its
'spot' cleaning behaviour, "which varied from run to run" (6.2). The thesis gives no
speeds or mounting; the choices here (:class:`Roomba`) are stated with their reasons.

**Kinematics.** Robot frame: ``X`` forward, ``Y`` left, ``Z`` up, turning centre at
the origin. The whisker's base sits on the right-hand rim at ``(0, -r)`` and the
whisker points backward and down at ``tilt_deg`` to the floor, its bending plane the
vertical X-Z plane ("angle as far back as possible", the CrunchBot lesson of 6.5.6.1).
With forward speed ``v`` and yaw rate ``omega`` (anticlockwise positive, seen from
above) the floor under the nominal tip ``(-L cos(tilt), -r)`` moves, relative to the
robot, at ``(-v - omega r, omega L cos(tilt))``. In the whisker's frame
(:class:`~vibrissa.whisker.simulate.SurfaceContact`, floor angle = tilt) that is a
slide along the floor's in-plane axis ``u`` (pointing from the base toward the tip)
at ``v + omega r`` and a slide across the bending plane, along ``y``, at
``omega L cos(tilt)``. Turning anticlockwise the floor runs from base to tip (the
whisker trails, as when driving forward); clockwise it runs from tip to base (the tip
leads and is pushed into the floor). The floor translates under the tip without
rotating: over one window (0.4 s) the robot turns by ~20 deg, and the floors are
statistically isotropic apart from the carpets' lattice. A whisker turned by
``mount_yaw_deg`` = psi from straight backward toward the right sees the slide
``(v + omega r) cos(psi)`` along ``u`` and ``(v + omega r) sin(psi) + omega L cos(tilt)``
across (:func:`floor_slide`); at psi = 90 deg (pointing outward) the two turning
directions are mirror images.

**Catches.** With the tip leading, the floor's friction on the tip pushes along the
whisker toward its base. Quasi-statically, a tip meeting an obstacle flank of slope
``alpha`` can only ride up it if ``alpha + atan(mu) < 90 deg - theta``, ``theta`` the
tip's angle to the floor: at 30 deg and mu = 0.6 every flank steeper than ~29 deg
holds it. Under a 1 mm tip, a quarter of the rough carpet's rigid loop relief
(``whisker.floors``) is steeper than that along the whisker (up to ~60 deg), against
~5 % of smooth carpet (mu 0.7), ~2 % of tarmac and none of vinyl. The tip then stays
caught while the floor drags the whisker, until the whisker bends or twists off the
loop; trailing, the same friction pulls the tip over the flank. The limit is
quasi-static, but the catches are not speed-independent: with the wheels at 300 mm/s
instead of 100 the simulated clockwise rough-carpet trials catch ~30x less often
(presumably the tip no longer settles into the gaps before the loops; not measured),
so whether the tip catches depends on a speed the thesis does not give (numbers:
``scripts/roomba_catches.py``, ``docs/runs/roomba_catches.json``).
:class:`FloorTrial` counts the catches (stuck for at least :data:`CATCH_MIN_S` on a
sliding floor), the time at a sensor rail and the contact force;
``scripts/roomba_catches.py`` measures them per direction and floor.

Everything the sensor records comes from the rod and its contact with the floor's
height field; the robot contributes only the prescribed slide of the floor.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from vibrissa._validate import in_range, positive
from vibrissa.whisker.floors import FloorSpec
from vibrissa.whisker.hall import HallSensor, steps_per_sample
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import SurfaceContact, Trajectory, simulate
from vibrissa.whisker.surfaces import Surface

__all__ = [
    "CATCH_MIN_S",
    "CONDITIONS",
    "SETTLE_S",
    "FloorTrial",
    "Roomba",
    "base_motion",
    "floor_slide",
    "run_floor_trial",
    "tip_path",
]

#: The movement conditions of 6.2, in the thesis' order of tables.
CONDITIONS = ("clockwise", "anticlockwise", "spot")


@dataclass(frozen=True)
class Roomba:
    """The mobile base and how the whisker is mounted on it.

    Parameters
    ----------
    wheel_base_mm : float
        Distance between the drive wheels (mm); 235 mm for the Roomba 400-600
        series (iRobot Roomba Open Interface specification).
    spin_wheel_speed_mm_s : float
        Wheel speed when spinning in place (mm/s). The Open Interface accepts up to
        500 mm/s; the thesis gives none. 100 mm/s: yaw rate 0.85 rad/s, one turn in
        7.4 s, about two turns per 16 s trial.
    acceleration_mm_s2 : float
        Wheel acceleration at start (mm/s^2).
    start_delay_s : tuple of float
        The robot starts moving after a delay drawn uniformly from this range (s):
        the recording runs from the command, and "there is no guarantee that the
        robot will be moving" (6.2.1). The packets of that stationary start are what
        the variance threshold removes.
    mount_radius_mm : float
        Distance of the whisker's base from the turning centre (mm): on the rim of
        the 340 mm body, a little inside it.
    tilt_deg : float
        Angle between the undeflected whisker and the floor (deg).
    mount_yaw_deg : float
        Direction the whisker points in seen from above, from straight backward (0)
        toward the robot's right, i.e. outward from the right-hand rim (90) (deg).
        0: turning anticlockwise the whisker trails and clockwise its tip leads; 90:
        both turning directions slide the floor straight across the whisker's
        bending plane, mirror images of each other.
    preload_mm : float
        How far the floor would cut into the undeflected whisker's tip, along the
        floor's normal (mm): the whisker is set to press on the floor.
    spot_speed_mm_s : tuple of float
        Forward speed of the spot spiral, drawn per trial (mm/s).
    spot_pitch_mm : tuple of float
        Distance between turns of the spot spiral, drawn per trial (mm).
    spot_start_radius_mm : tuple of float
        Radius of curvature at the start of the spiral, drawn per trial (mm).
    """

    wheel_base_mm: float = 235.0
    spin_wheel_speed_mm_s: float = 100.0
    acceleration_mm_s2: float = 500.0
    start_delay_s: tuple[float, float] = (0.2, 1.2)
    mount_radius_mm: float = 150.0
    tilt_deg: float = 30.0
    mount_yaw_deg: float = 0.0
    preload_mm: float = 15.0
    spot_speed_mm_s: tuple[float, float] = (100.0, 200.0)
    spot_pitch_mm: tuple[float, float] = (60.0, 150.0)
    spot_start_radius_mm: tuple[float, float] = (60.0, 200.0)

    def __post_init__(self) -> None:
        for name in (
            "wheel_base_mm",
            "spin_wheel_speed_mm_s",
            "acceleration_mm_s2",
            "mount_radius_mm",
            "preload_mm",
        ):
            positive(name, getattr(self, name))
        in_range("tilt_deg", self.tilt_deg, 1.0, 89.0, "deg")
        in_range("mount_yaw_deg", self.mount_yaw_deg, -90.0, 90.0, "deg")
        for name in ("start_delay_s", "spot_speed_mm_s", "spot_pitch_mm", "spot_start_radius_mm"):
            lo, hi = getattr(self, name)
            if not (0.0 <= lo <= hi and math.isfinite(hi)):
                raise ValueError(
                    f"{name} must be a range (low, high) with 0 <= low <= high, got {(lo, hi)!r}"
                )
        for name in ("spot_speed_mm_s", "spot_pitch_mm", "spot_start_radius_mm"):
            positive(f"{name} low end", getattr(self, name)[0])

    def to_dict(self) -> dict:
        """Every parameter as plain values."""
        return asdict(self)


def base_motion(
    roomba: Roomba, condition: str, duration_s: float, rng: np.random.Generator, dt_s: float = 1e-3
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward speed and yaw rate of the base over a trial.

    Parameters
    ----------
    roomba : Roomba
    condition : {"clockwise", "anticlockwise", "spot"}
        Spin in place either way, or the spot spiral (its speed, pitch, starting
        radius and turning direction drawn from ``rng``).
    duration_s : float
        Trial length (s).
    rng : numpy.random.Generator
        The trial's random stream (start delay; the spot spiral).
    dt_s : float
        Sample spacing of the returned profiles (s).

    Returns
    -------
    (time_s, forward_mm_s, yaw_rad_s) : three arrays of the same length
    """
    if condition not in CONDITIONS:
        raise ValueError(f"unknown condition {condition!r}; choose one of {', '.join(CONDITIONS)}")
    T = positive("duration_s", duration_s)
    t = np.arange(0.0, T + dt_s, dt_s)
    delay = rng.uniform(*roomba.start_delay_s)
    if condition == "spot":
        v = rng.uniform(*roomba.spot_speed_mm_s)
        pitch = rng.uniform(*roomba.spot_pitch_mm)
        r0 = rng.uniform(*roomba.spot_start_radius_mm)
        turn = rng.choice([-1.0, 1.0])
    else:
        v = roomba.spin_wheel_speed_mm_s
    ramp = np.clip((t - delay) * roomba.acceleration_mm_s2 / v, 0.0, 1.0)
    if condition == "spot":
        forward = v * ramp
        path = np.concatenate([[0.0], np.cumsum(0.5 * (forward[1:] + forward[:-1]) * dt_s)])
        # Archimedean spiral: the radius grows by one pitch per turn
        radius = np.sqrt(r0**2 + pitch * path / math.pi)
        yaw = turn * forward / radius
    else:
        forward = np.zeros_like(t)
        wheel = roomba.spin_wheel_speed_mm_s * ramp
        yaw = (1.0 if condition == "anticlockwise" else -1.0) * 2.0 * wheel / roomba.wheel_base_mm
    return t, forward, yaw


def floor_slide(
    roomba: Roomba,
    length_mm: float,
    time_s: np.ndarray,
    forward_mm_s: np.ndarray,
    yaw_rad_s: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The floor's slide under the tip in the whisker's frame (see the module doc).

    With the whisker pointing ``mount_yaw_deg`` = psi from straight backward toward the
    right and reaching ``R = L cos(tilt)`` over the floor, the floor under the nominal
    tip slides along the whisker at ``(v + omega r) cos(psi)`` and across it at
    ``(v + omega r) sin(psi) + omega R``.

    Returns
    -------
    (along_u_mm_s, across_y_mm_s)
        Velocity of the floor along its in-plane axis ``u`` (positive: from the base
        toward the tip) and along the whisker's ``y`` (mm/s).
    """
    reach = length_mm * math.cos(math.radians(roomba.tilt_deg))
    psi = math.radians(roomba.mount_yaw_deg)
    rim = forward_mm_s + yaw_rad_s * roomba.mount_radius_mm
    along = rim * math.cos(psi)
    across = rim * math.sin(psi) + yaw_rad_s * reach
    return along, across


@dataclass
class FloorTrial:
    """One recorded floor trial.

    Attributes
    ----------
    signal_v : ndarray
        Sensor output, shape (2, n_samples).
    time_s : ndarray
        Sample times of the recording (s), shape (n_samples,).
    slide_speed_mm_s : ndarray
        Speed of the floor under the tip at each sample (mm/s).
    contact_fraction : float
        Fraction of the recording with the whisker touching the floor.
    moving_fraction : float
        Fraction of the recording with the base moving.
    saturated : bool
        Whether the sensor output reached either rail.
    rail_fraction : float
        Fraction of the samples (either channel) at a rail.
    catches : int
        Times the tip caught in the floor: stuck (no contact node slipping) while the
        floor slides under it, for at least :data:`CATCH_MIN_S`.
    catch_fraction : float
        Fraction of the recording the tip spent caught.
    contact_force_n : float
        Median normal contact force while the base moves and the whisker touches (N).
    """

    signal_v: np.ndarray
    time_s: np.ndarray
    slide_speed_mm_s: np.ndarray
    contact_fraction: float
    moving_fraction: float
    saturated: bool
    rail_fraction: float = 0.0
    catches: int = 0
    catch_fraction: float = 0.0
    contact_force_n: float = 0.0


#: Seconds to press the floor onto the whisker and let it settle before recording.
SETTLE_S = 0.6

#: Shortest stick of the tip on a sliding floor counted as a catch (s): at the spin
#: speed the floor slides ~6 mm in 50 ms, more than one carpet loop pitch, so the tip
#: is held by one loop instead of ticking over it (ordinary stick-slip on the loops
#: lasts a few ms, 6.5.6.1: catches "can last several hundred milliseconds or more").
CATCH_MIN_S = 0.05


def _runs(mask: np.ndarray) -> np.ndarray:
    """Lengths (in samples) of the runs of True in a boolean array."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)


def run_floor_trial(
    roomba: Roomba,
    model: RodModel,
    sensor: HallSensor,
    floor: Surface,
    spec: FloorSpec,
    condition: str,
    duration_s: float,
    rng: np.random.Generator,
    dt_s: float = 2.5e-4,
) -> FloorTrial:
    """Simulate one trial: the whisker pressed on the floor while the base moves.

    Parameters
    ----------
    roomba : Roomba
    model : RodModel
        The whisker.
    sensor : HallSensor
        The sensor, with the recording rate.
    floor : Surface
        The floor's height field.
    spec : FloorSpec
        The floor's recipe (its contact stiffness).
    condition : {"clockwise", "anticlockwise", "spot"}
    duration_s : float
        Recorded seconds (the thesis: 16).
    rng : numpy.random.Generator
        The trial's stream: start delay, spot spiral, place on the floor, sensor noise.
    dt_s : float
        Internal time step (s); must divide the sample period.
    """
    step = steps_per_sample(dt_s, sensor.sample_rate_hz)
    T = positive("duration_s", duration_s)
    contact = SurfaceContact(floor, angle_deg=roomba.tilt_deg, stiffness_n_m=spec.stiffness_n_m)
    n, u, _ = contact.frame()
    g = model.geometry
    t_rec, forward, yaw = base_motion(roomba, condition, T, rng)
    along_rec, across_rec = floor_slide(roomba, g.length_mm, t_rec, forward, yaw)
    # settle: the floor comes up along its normal from a 2 mm gap to the preload
    t_set = np.linspace(0.0, SETTLE_S, 121)
    press = np.clip(t_set / (0.5 * SETTLE_S), 0.0, 1.0)
    t = np.concatenate([t_set, SETTLE_S + t_rec[1:]])
    along = np.concatenate([np.zeros(t_set.size), along_rec[1:]])
    across = np.concatenate([np.zeros(t_set.size), across_rec[1:]])
    normal = np.concatenate([press, np.ones(t_rec.size - 1)])
    s_u = np.concatenate([[0.0], np.cumsum(0.5 * (along[1:] + along[:-1]) * np.diff(t))])
    s_y = np.concatenate([[0.0], np.cumsum(0.5 * (across[1:] + across[:-1]) * np.diff(t))])
    tip = np.array([0.0, 0.0, g.length_mm])
    gap = 2.0 + g.tip_radius_mm
    start = rng.uniform(0.0, 1e3 * floor.spacing_m * np.array(floor.heights_m.shape))
    origin = (tip - n * gap)[None, :] + n[None, :] * ((gap + roomba.preload_mm) * normal)[:, None]
    origin = origin + u[None, :] * (s_u + start[0])[:, None]
    speed_n = (gap + roomba.preload_mm) / (0.5 * SETTLE_S) * (t < 0.5 * SETTLE_S)
    vel = n[None, :] * speed_n[:, None] + u[None, :] * along[:, None]
    traj = Trajectory(
        t,
        origin[:, [0, 2]],
        vel[:, [0, 2]],
        lateral_mm=s_y + start[1],
        lateral_velocity_mm_s=across,
    )
    res = simulate(model, contact, traj, SETTLE_S + T, dt_s)
    k0 = int(round(SETTLE_S / dt_s))
    tan = res.tan_xy[k0:]
    volts = sensor.read(tan, 1.0 / dt_s, rng)
    n_samples = int(round(T * sensor.sample_rate_hz))
    volts = volts[:n_samples]
    time = np.arange(n_samples) / sensor.sample_rate_hz
    speed = np.hypot(np.interp(time, t_rec, along_rec), np.interp(time, t_rec, across_rec))
    force = res.contact_force_n[k0:][: n_samples * step]
    touching = force > 0
    t_step = np.arange(force.size) * dt_s
    sliding = np.interp(t_step, time, speed) > 1e-6
    stuck = _runs(touching & (res.slipping[k0:][: force.size] == 0) & sliding) * dt_s
    at_rail = (volts <= sensor.v_min) | (volts >= sensor.v_max)
    pressed = force[touching & sliding]
    return FloorTrial(
        signal_v=np.ascontiguousarray(volts.T),
        time_s=time,
        slide_speed_mm_s=speed,
        contact_fraction=float(np.mean(touching)),
        moving_fraction=float(np.mean(speed > 1e-6)),
        saturated=bool(np.any(at_rail)),
        rail_fraction=float(np.mean(np.any(at_rail, axis=1))),
        catches=int(np.sum(stuck >= CATCH_MIN_S - 0.5 * dt_s)),
        catch_fraction=float(np.sum(stuck[stuck >= CATCH_MIN_S - 0.5 * dt_s]) / T),
        contact_force_n=float(np.median(pressed)) if pressed.size else 0.0,
    )


def tip_path(
    roomba: Roomba,
    length_mm: float,
    time_s: np.ndarray,
    forward_mm_s: np.ndarray,
    yaw_rad_s: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Where the undeflected tip passes over the floor (mm, floor frame).

    The robot starts at the origin heading along +x.

    Returns
    -------
    (x_mm, y_mm) : arrays like ``time_s``
    """
    dt = np.diff(time_s)
    heading = np.concatenate([[0.0], np.cumsum(0.5 * (yaw_rad_s[1:] + yaw_rad_s[:-1]) * dt)])
    vx, vy = forward_mm_s * np.cos(heading), forward_mm_s * np.sin(heading)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (vx[1:] + vx[:-1]) * dt)])
    y = np.concatenate([[0.0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * dt)])
    reach = length_mm * math.cos(math.radians(roomba.tilt_deg))
    psi = math.radians(roomba.mount_yaw_deg)
    # the tip at (-reach cos psi, -r - reach sin psi) in the robot frame, turned by the heading
    tx, ty = -reach * math.cos(psi), -roomba.mount_radius_mm - reach * math.sin(psi)
    return (
        x + tx * np.cos(heading) - ty * np.sin(heading),
        y + tx * np.sin(heading) + ty * np.cos(heading),
    )
