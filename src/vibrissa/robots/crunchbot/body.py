"""CrunchBot's iRobot Create base: differential drive, bumper and odometry (thesis 3.5.1).

The base carries out one :class:`~vibrissa.robots.crunchbot.fsm.MotorCommand` (forward
speed, yaw rate, duration) as constant-velocity motion along an arc, sampled at the
whiskers' 2 kHz. Starting and stopping are instant: the thesis gives no acceleration and
at 0.05 m/s the Create's own ramp (its Open Interface drives set speeds directly) is
short against a 0.5 s step, so the base's translational acceleration is left out here
as it is in the whisker frames (:mod:`~vibrissa.robots.crunchbot.obstacle_whiskers`).

The step ends early at the sample before the body disc would overlap a wall or an
obstacle (the Create's bumper). The whiskers' strain stop is decided by the robot loop
(:mod:`~vibrissa.robots.crunchbot.robot`), which cuts the planned samples short.

Odometry is the true increment over the step plus the relative error the particle
filter's motion model assumes (:func:`vibrissa.slam.filter.noisy_increment`, ~10 % of
each movement), as in :func:`~vibrissa.robots.crunchbot.synthetic.synthetic_log`.
"""

from __future__ import annotations

import math

import numpy as np

from vibrissa.robots.crunchbot.arena import ROBOT_RADIUS_M, Arena
from vibrissa.robots.crunchbot.fsm import MotorCommand
from vibrissa.slam.filter import noisy_increment

__all__ = ["body_collides_many", "plan_motion", "relative_increment", "odometry"]


def body_collides_many(
    arena: Arena, xy: np.ndarray, radius_m: float = ROBOT_RADIUS_M
) -> np.ndarray:
    """Whether the body disc, per row of ``xy``, leaves the arena or overlaps an obstacle.

    ``xy`` is ``(n, 2)`` arena metres; touching does not count.
    """
    x, y = xy[:, 0], xy[:, 1]
    hit = (
        (x < radius_m)
        | (y < radius_m)
        | (x > arena.size_m - radius_m)
        | (y > arena.size_m - radius_m)
    )
    for ob in arena.obstacles:
        x0, y0, x1, y1 = ob.bounds()
        dx = x - np.clip(x, x0, x1)
        dy = y - np.clip(y, y0, y1)
        hit |= dx * dx + dy * dy < radius_m * radius_m
    return hit


def plan_motion(
    arena: Arena,
    pose: np.ndarray,
    command: MotorCommand,
    sample_rate_hz: float = 2000.0,
    radius_m: float = ROBOT_RADIUS_M,
) -> tuple[np.ndarray, bool]:
    """The true poses at the step's samples, cut at the bumper.

    Parameters
    ----------
    arena
        Where the robot drives.
    pose
        ``(3,)`` arena-frame pose at the step's start.
    command
        What to carry out; its duration is rounded to whole samples.
    sample_rate_hz
        The sample rate.
    radius_m
        The body disc.

    Returns
    -------
    poses, bumped
        ``(m, 3)`` poses at ``t0 + k / rate``, ``k = 1..m`` (``m`` = 0 for a zero-length
        command or a bump at once) and whether the bumper stopped the step.
    """
    n = int(round(command.duration_s * sample_rate_hz))
    if n <= 0:
        return np.zeros((0, 3)), False
    t = np.arange(1, n + 1) / sample_rate_hz
    v, w = command.linear_m_s, command.angular_rad_s
    h0 = float(pose[2])
    h = h0 + w * t
    if abs(w) < 1e-12:
        x = pose[0] + v * t * math.cos(h0)
        y = pose[1] + v * t * math.sin(h0)
    else:
        x = pose[0] + v / w * (np.sin(h) - math.sin(h0))
        y = pose[1] - v / w * (np.cos(h) - math.cos(h0))
    poses = np.column_stack([x, y, h])
    if v == 0.0:
        return poses, False  # turning on the spot never moves the disc
    hit = body_collides_many(arena, poses[:, :2], radius_m)
    if hit.any():
        return poses[: int(np.argmax(hit))], True
    return poses, False


def relative_increment(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """The true increment ``(forward_m, left_m, rotation_rad)`` from ``start`` to ``end``.

    The increment is in the frame of ``start``.
    """
    c, s = math.cos(start[2]), math.sin(start[2])
    dx, dy = end[0] - start[0], end[1] - start[1]
    return np.array(
        [c * dx + s * dy, -s * dx + c * dy, math.remainder(end[2] - start[2], math.tau)]
    )


def odometry(
    start: np.ndarray,
    end: np.ndarray,
    rng: np.random.Generator,
    error: float = 0.1,
    drift_rad_m: float = 0.1,
) -> np.ndarray:
    """The Create's measured increment: the true one with ``error`` of each movement."""
    return noisy_increment(relative_increment(start, end), 1, error, drift_rad_m, rng)[0]
