"""The four obstacle whiskers: rigid-motion bookkeeping, strain stop, skipping physics."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.robots.crunchbot import obstacle_whiskers as ow
from vibrissa.robots.crunchbot.arena import PRESETS, Arena, Obstacle, Pose
from vibrissa.robots.crunchbot.body import plan_motion
from vibrissa.robots.crunchbot.fsm import MotorCommand
from vibrissa.robots.crunchbot.synthetic import CRUNCHBOT_LAYOUT, whisker_contacts

OPEN = Arena("open", 1.25, Pose(0.6, 0.6, 0.0))


def _drive(
    arena: Arena,
    pose: np.ndarray,
    command: MotorCommand,
    seed: int = 0,
    whiskers: ow.ObstacleWhiskers | None = None,
    **kw,
):
    w = whiskers or ow.ObstacleWhiskers(arena)
    poses, _ = plan_motion(arena, pose, command)
    sig, m = w.advance(pose, poses, np.random.default_rng(seed), **kw)
    return w, poses[:m], sig


def test_features_leave_out_faces_and_corners_hidden_in_the_walls() -> None:
    feats = ow.arena_features(PRESETS["slam"])
    planes = [f for f in feats if f.kind == "plane"]
    poles = [f for f in feats if f.kind == "pole"]
    # 4 walls + 4 faces of the middle block + 2 free faces of each corner block
    assert len(planes) == 4 + 4 + 2 + 2
    # 4 corners of the middle block + 1 free corner of each corner block
    assert len(poles) == 4 + 1 + 1
    for f in planes[:4]:  # the walls' normals point into the arena
        mid = 0.5 * (f.a + f.b)
        assert np.all(np.abs(mid + 0.1 * f.normal - 0.625) < 0.625)


def test_a_wall_met_head_on_touches_when_the_ray_oracle_says() -> None:
    start = np.array([1.25 - 0.15 - 0.14 - 0.01, 0.6, 0.0])  # tips of w2, w3 ~10 mm away
    w, poses, sig = _drive(OPEN, start, MotorCommand(0.05, 0.0, 0.5))
    first = int(np.argmax(sig.contact[:, 1]))
    assert sig.contact[:, 1].any() and sig.contact[:, 2].any()
    oracle = [np.isfinite(whisker_contacts(OPEN, p)[0][1]) for p in poses]
    k_oracle = int(np.argmax(oracle))
    assert abs(first - k_oracle) <= 20  # within 0.5 mm of travel at 50 mm/s
    assert sig.first_contact_m[1] == pytest.approx(0.14)  # a tip contact


def test_the_contact_arc_of_a_contact_near_the_tip_on_a_corner_is_near_135_mm() -> None:
    # w3 (the inner left whisker) passes 135 mm along through the upper-left corner of a
    # block below-right of it, 5 mm ahead of the robot
    base, phi = CRUNCHBOT_LAYOUT.base_m[2], CRUNCHBOT_LAYOUT.angle_rad[2]
    corner = np.array([0.3, 0.6]) + base + 0.135 * np.array([np.cos(phi), np.sin(phi)])
    arena = Arena(
        "corner",
        1.25,
        Pose(0.295, 0.6, 0.0),
        obstacles=(Obstacle(corner[0], corner[1] - 0.2, 0.2),),
    )
    w, _, sig = _drive(arena, arena.start.as_array(), MotorCommand(0.02, 0.0, 0.5))
    assert sig.contact[:, 2].any()
    assert w.features[w.whiskers[2].feature].kind == "pole"
    assert sig.first_contact_m[2] == pytest.approx(0.135, abs=0.005)


def test_turning_into_a_wall_bends_the_whisker_away_from_the_turn() -> None:
    # the wall on the robot's left; w4 (the outer left whisker) just short of it
    base, phi = CRUNCHBOT_LAYOUT.base_m[3], CRUNCHBOT_LAYOUT.angle_rad[3]
    y = 1.25 - base[1] - 0.139 * np.sin(phi) - 0.003
    start = np.array([0.6, y, 0.0])
    w, _, sig = _drive(OPEN, start, MotorCommand(0.0, 0.3, 0.5))
    assert sig.contact[:, 3].any()
    bend = sig.hall_v[-50:, 3, 0].mean() - w.sensor.offset_v
    assert bend < -0.05  # turned toward +x (left), the wall pushes it back toward -x
    _, _, away = _drive(OPEN, start, MotorCommand(0.0, -0.3, 0.5))
    assert not away.contact[:, 3].any()


def test_the_strain_limit_stops_forward_motion() -> None:
    start = np.array([1.25 - 0.15 - 0.14 + 0.002, 0.6, 0.0])
    w, poses, sig = _drive(OPEN, start, MotorCommand(0.05, 0.0, 1.0), stop_strain=0.6)
    assert len(poses) < 2000
    assert sig.strain[-1].max() > 0.6 and sig.strain[:-1].max() <= 0.6
    # strain is the Hall reading over its full scale: each axis clamps at 1
    assert sig.strain.max() <= np.sqrt(2) + 1e-12
    _, free_poses, _ = _drive(
        OPEN, OPEN.start.as_array(), MotorCommand(0.05, 0.0, 0.5), stop_strain=1.0
    )
    assert len(free_poses) == 1000


def test_skipping_the_physics_gives_what_running_it_gives_when_nothing_is_near(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    cmd = MotorCommand(0.05, 0.0, 0.5)
    _, _, skipped = _drive(OPEN, OPEN.start.as_array(), cmd, seed=3)
    assert not skipped.physics.any()
    monkeypatch.setattr(ow, "REACH_MARGIN_M", 10.0)  # everything "within reach"
    _, _, ran = _drive(OPEN, OPEN.start.as_array(), cmd, seed=3)
    assert ran.physics.all() and not ran.contact.any()
    np.testing.assert_allclose(ran.hall_v, skipped.hall_v, atol=1e-9)
