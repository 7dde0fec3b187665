"""Offline training of CrunchBot's real-time classifiers on the simulated robot (6.5).

The data are collected as in the thesis, on the same body and whiskers the runs use
(:mod:`.body`, :mod:`.obstacle_whiskers`):

* radial distance (6.5.4): per obstacle whisker, 5 contacts at each of 6 points 10 mm
  apart over the 50 mm nearest the tip (85-135 mm from the base; 135 rather than 140 so
  the contact does not slip off the tip). Each contact: a square block is placed with a
  corner on the whisker's line at that distance, 0-3 mm ahead of it, on the side that
  leaves the rest of the whisker clear, 1.5-2 mm to the side of the shaft (a corner
  placed on the line would start inside the shaft), and the robot creeps forward at the
  FWD_2 speed (0.02 m/s) for 1 s into it, as it does after HIT_1 in a run; the label is
  the true contact arc from the physics, the feature the peak deflection (what the
  control loop reads per step). The body whisk of 6.5.1 (:func:`body_whisk`) is written
  out as a scripted behaviour but not used here: the loop's radial reports come from
  forward creeping steps, and training on the same motion keeps the feature's speed
  dependence out.
* surface angle (6.5.5.3): the robot drives into a wall at 15 angles (20-160 deg, 10 deg
  steps) 4 times each: FWD_1 at 0.05 m/s until a whisker touches (HIT_1), then FWD_2
  creeping for 2 s (cut by the strain limit, after which the robot holds still and the
  recording holds its last value); 8 channels (4 whiskers x (x, y)) from HIT_1.
* floor texture (6.5.2): :func:`~vibrissa.robots.crunchbot.floor_whiskers.collect_floor_training`
  on the three tile textures of 6.5.1 (:data:`TILE_TEXTURES`).

The classifiers are :mod:`vibrissa.classify.realtime`'s.
"""

from __future__ import annotations

import math

import numpy as np

from vibrissa.classify.realtime import (
    FloorTextureNB,
    RadialDistanceLinear,
    SurfaceAngleTemplates,
    peak_deflection,
)
from vibrissa.robots.crunchbot import fsm
from vibrissa.robots.crunchbot.arena import Arena, Obstacle, Pose
from vibrissa.robots.crunchbot.body import plan_motion
from vibrissa.robots.crunchbot.floor_whiskers import collect_floor_training
from vibrissa.robots.crunchbot.obstacle_whiskers import CORNER_RADIUS_MM, ObstacleWhiskers
from vibrissa.robots.crunchbot.robot import RealtimeClassifiers, deflection_volts
from vibrissa.robots.crunchbot.synthetic import CRUNCHBOT_LAYOUT

__all__ = [
    "ANGLES_DEG",
    "RADIAL_POINTS_M",
    "TILE_TEXTURES",
    "body_whisk",
    "collect_angle_training",
    "collect_radial_training",
    "train_classifiers",
]

#: Where the radial-distance training contacts are (m from the base).
RADIAL_POINTS_M = 0.135 - 0.01 * np.arange(6)
#: Wall angles of the surface-angle training, in the robot's frame (deg).
ANGLES_DEG = np.arange(20, 161, 10)
#: The tile textures of the arena of 6.5.1: vinyl, smooth carpet and rough carpet.
TILE_TEXTURES = ("vinyl", "smooth-carpet", "rough-carpet")
#: Length of a surface-angle recording from HIT_1 (s).
ANGLE_RECORD_S = 2.0
_BLOCK_M = 0.05
_ARENA_M = 1.25
_START = np.array([0.4, 0.625, 0.0])


def body_whisk(
    settings: fsm.FsmSettings | None = None, toward: int = 1, reverse_m: float = 0.01
) -> tuple[fsm.MotorCommand, ...]:
    """The body whisk of 6.5.1 as motor commands.

    Reverse a little, rotate at pi/24 rad/s toward the object for 1 s, away for 1 s, reverse.

    ``toward``: +1 the object is on the robot's left (turn anticlockwise first), -1 right.
    """
    s = settings or fsm.FsmSettings()
    back = fsm.MotorCommand(-s.back_speed_m_s, 0.0, reverse_m / s.back_speed_m_s)
    rate = math.copysign(math.pi / 24, toward)
    return (back, fsm.MotorCommand(0.0, rate, 1.0), fsm.MotorCommand(0.0, -rate, 1.0), back)


def _block_at(corner: np.ndarray, pointing_left: bool) -> Obstacle:
    """A block with a corner at ``corner`` lying on the far side of a whisker's line.

    Below it for a whisker pointing left of ahead, above it for one pointing right.
    """
    if pointing_left:
        return Obstacle(float(corner[0]), float(corner[1]) - _BLOCK_M, _BLOCK_M)
    return Obstacle(float(corner[0]), float(corner[1]), _BLOCK_M)


def collect_radial_training(
    seed: int = 0, contacts_per_point: int = 5, whiskers: tuple[int, ...] = (0, 1, 2, 3)
) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Radial-distance training contacts per whisker.

    Returns
    -------
    dict
        whisker index -> ``(peak, distance_m)``: the step's peak deflection
        (:func:`~vibrissa.classify.realtime.peak_deflection` about the sensor's rest
        output, as the control loop reads it) and the true contact arc (m), one entry per
        contact that touched.
    """
    rng = np.random.default_rng(seed)
    lay = CRUNCHBOT_LAYOUT
    out: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    for w in whiskers:
        if abs(float(lay.angle_rad[w])) < 0.02:
            raise ValueError(
                f"whisker {w} points along the heading: a forward drive brings no corner "
                "onto its shaft"
            )
        d = np.array([math.cos(lay.angle_rad[w]), math.sin(lay.angle_rad[w])])
        feats, dists = [], []
        for r in RADIAL_POINTS_M:
            for _ in range(contacts_per_point):
                left = lay.angle_rad[w] > 0
                side = np.array([-d[1], d[0]]) * (1.0 if left else -1.0)
                # clear of the shaft at the start; driving forward closes the gap at
                # sin(phi) per metre while the corner slides cos(phi) toward the base, so
                # it starts that much further out and touches at r
                clear = rng.uniform(0.3e-3, 0.6e-3)
                gap = CORNER_RADIUS_MM * 1e-3 + clear
                ahead = clear / math.tan(abs(float(lay.angle_rad[w])))
                corner = _START[:2] + lay.base_m[w] + (r + ahead) * d - gap * side
                arena = Arena(
                    "radial", _ARENA_M, Pose(*_START), obstacles=(_block_at(corner, left),)
                )
                ow = ObstacleWhiskers(arena)
                poses, _ = plan_motion(arena, _START, fsm.MotorCommand(0.02, 0.0, 1.0))
                sig, _ = ow.advance(_START, poses, rng)
                if not sig.contact[:, w].any():
                    continue
                feats.append(peak_deflection(sig.hall_v[:, w], ow.sensor.offset_v))
                dists.append(sig.first_contact_m[w])
        out[w] = (np.array(feats), np.array(dists))
    return out


def _approach(angle_deg: float, rng: np.random.Generator) -> np.ndarray:
    """One drive into the right-hand wall with it at ``angle_deg`` in the robot's frame.

    Returns the 8-channel recording (volts about rest) from HIT_1, 2 s (held at its end).
    """
    s = fsm.FsmSettings()
    heading = math.radians(90.0 - angle_deg)
    reach = 0.15 + 0.14
    x = _ARENA_M - 0.17 - reach * max(math.cos(heading), 0.6) - rng.uniform(0.01, 0.03)
    pose = np.array([x, 0.625 + rng.uniform(-0.05, 0.05), heading])
    arena = Arena("wall", _ARENA_M, Pose(*pose))
    ow = ObstacleWhiskers(arena)
    offset = ow.sensor.offset_v
    for _ in range(20):  # FWD_1 until a whisker touches
        poses, _ = plan_motion(arena, pose, fsm.command_for(fsm.FWD_1, s, rng))
        sig, m = ow.advance(pose, poses, rng, s.strain_limit, stop_on_contact=True)
        if m:
            pose = poses[m - 1]
        if m == 0 or sig.contact.any():
            break
    n_rec = int(round(ANGLE_RECORD_S * ow.rate))
    chunks: list[np.ndarray] = []
    got = 0
    while got < n_rec:  # FWD_2 creeping from HIT_1
        poses, _ = plan_motion(arena, pose, fsm.command_for(fsm.FWD_2, s, rng))
        sig, m = ow.advance(pose, poses, rng, s.strain_limit)
        if m == 0:
            break
        pose = poses[m - 1]
        chunks.append(deflection_volts(sig.hall_v, offset).reshape(m, -1))
        got += m
        if m < len(poses) or sig.strain.max() > s.strain_limit:
            break
    rec = np.concatenate(chunks)[:n_rec] if chunks else np.zeros((1, 8))
    if len(rec) < n_rec:
        rec = np.vstack([rec, np.repeat(rec[-1:], n_rec - len(rec), axis=0)])
    return rec


def collect_angle_training(
    seed: int = 0, runs_per_angle: int = 4, angles_deg: np.ndarray = ANGLES_DEG
) -> tuple[np.ndarray, np.ndarray]:
    """Surface-angle training drives: ``(recordings (n, 4000, 8), angles_rad (n,))``."""
    rng = np.random.default_rng(seed)
    recs, labels = [], []
    for a in angles_deg:
        for _ in range(runs_per_angle):
            recs.append(_approach(float(a), rng))
            labels.append(math.radians(float(a)))
    return np.stack(recs), np.array(labels)


def train_classifiers(seed: int = 0, quick: bool = False) -> RealtimeClassifiers:
    """Collect the training data on the simulated robot and fit the three classifiers.

    ``quick``: 2 contacts per radial point, 2 drives per angle, 2 s of floor per texture
    (for tests and previews); otherwise the thesis' 5, 4 and 10 s.
    """
    radial_data = collect_radial_training(seed, 2 if quick else 5)
    radial = tuple(
        RadialDistanceLinear().fit(*radial_data[w]) for w in range(CRUNCHBOT_LAYOUT.n_whiskers)
    )
    recs, angles = collect_angle_training(seed + 1, 2 if quick else 4)
    angle = SurfaceAngleTemplates().fit(recs, angles, 2000.0)
    windows, labels = collect_floor_training(TILE_TEXTURES, 2.0 if quick else 10.0, seed + 2)
    floor = FloorTextureNB().fit(windows, labels, 2000.0)
    return RealtimeClassifiers(floor=floor, radial=radial, angle=angle)
