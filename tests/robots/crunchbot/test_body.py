"""The Create base: arcs sampled at 2 kHz, the bumper, odometry with ~10 % error."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.crunchbot.arena import ROBOT_RADIUS_M, Arena, Pose
from vibrissa.robots.crunchbot.body import (
    body_collides_many,
    odometry,
    plan_motion,
    relative_increment,
)
from vibrissa.robots.crunchbot.fsm import MotorCommand

ARENA = Arena("open", 1.25, Pose(0.6, 0.6, 0.0))


def test_forward_step_is_sampled_at_2_khz_and_goes_its_distance() -> None:
    poses, bumped = plan_motion(ARENA, ARENA.start.as_array(), MotorCommand(0.05, 0.0, 0.5))
    assert not bumped and poses.shape == (1000, 3)
    assert poses[-1, 0] == pytest.approx(0.625) and poses[-1, 1] == pytest.approx(0.6)
    assert np.diff(poses[:, 0]) == pytest.approx(np.full(999, 0.05 / 2000))


def test_turn_on_the_spot_keeps_the_centre_and_turns_by_rate_times_time() -> None:
    poses, _ = plan_motion(ARENA, ARENA.start.as_array(), MotorCommand(0.0, 0.3, 1.0))
    assert poses[:, :2] == pytest.approx(np.tile([0.6, 0.6], (2000, 1)))
    assert poses[-1, 2] == pytest.approx(0.3)


def test_the_bumper_stops_the_step_before_the_body_overlaps_a_wall() -> None:
    x0 = 1.25 - ROBOT_RADIUS_M - 0.01  # 10 mm from the wall
    poses, bumped = plan_motion(ARENA, np.array([x0, 0.6, 0.0]), MotorCommand(0.05, 0.0, 0.5))
    assert bumped
    assert len(poses) == pytest.approx(0.01 / 0.05 * 2000, abs=2)
    assert not body_collides_many(ARENA, poses[:, :2]).any()


def test_odometry_error_is_about_ten_percent_of_each_movement() -> None:
    rng = np.random.default_rng(1)
    start, end = (
        np.array([0.2, 0.2, 0.3]),
        np.array([0.2 + 0.025 * math.cos(0.3), 0.2 + 0.025 * math.sin(0.3), 0.3]),
    )
    true = relative_increment(start, end)
    assert true == pytest.approx([0.025, 0.0, 0.0], abs=1e-12)
    draws = np.array([odometry(start, end, rng) for _ in range(4000)])
    assert draws[:, 0].mean() == pytest.approx(0.025, rel=0.01)
    assert draws[:, 0].std() == pytest.approx(0.0025, rel=0.05)
    assert draws[:, 2].std() == pytest.approx(0.1 * 0.025, rel=0.05)  # heading drift per m
    turn = np.array([odometry(start, start + [0, 0, 0.5], rng) for _ in range(4000)])
    assert turn[:, 2].std() == pytest.approx(0.05, rel=0.05)
