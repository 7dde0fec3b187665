"""The exact whisker-contact oracle and the synthetic CrunchBot run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.crunchbot.arena import PRESETS
from vibrissa.robots.crunchbot.fsm import STATES
from vibrissa.robots.crunchbot.synthetic import (
    CRUNCHBOT_LAYOUT,
    cast_rays,
    front_array_layout,
    synthetic_log,
    whisker_contacts,
)
from vibrissa.slam.filter import apply_motion, to_world


def test_rays_stop_at_the_first_segment_within_their_length() -> None:
    segs = np.array([[0.5, -1.0, 0.5, 1.0], [0.3, -1.0, 0.3, 1.0], [2.0, 0.0, 2.0, 1.0]])
    d, s = cast_rays(
        segs,
        np.zeros((3, 2)),
        np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        np.array([1.0, 0.2, 1.0]),
    )
    assert d[0] == pytest.approx(0.3) and s[0] == 1
    assert math.isinf(d[1]) and s[1] == -1
    assert math.isinf(d[2])
    slanted = np.array([[1.0, 0.0, 0.0, 1.0]])
    d, _ = cast_rays(
        slanted, np.zeros((1, 2)), np.array([[math.sqrt(0.5), math.sqrt(0.5)]]), np.array([1.0])
    )
    assert d[0] == pytest.approx(math.sqrt(0.5))


def test_the_front_array_sits_side_by_side_at_its_pitch_and_splays_outward() -> None:
    lay = front_array_layout(0.03, 0.3)
    assert np.diff(lay.base_m[:, 1]) == pytest.approx([0.03, 0.03, 0.03])
    assert np.hypot(*lay.base_m.T) == pytest.approx(np.full(4, 0.15))
    assert lay.angle_rad == pytest.approx([-0.3, -0.1, 0.1, 0.3])
    # right to left, mirror-symmetric about the heading
    assert lay.base_m[::-1, 1] == pytest.approx(-lay.base_m[:, 1])
    assert front_array_layout(0.02, 0.0).angle_rad == pytest.approx(np.zeros(4))


@pytest.mark.parametrize(
    ("pitch", "splay", "message"),
    [
        (0.0, 0.3, "pitch_m"),
        (0.03, -0.1, "splay_rad"),
        (0.2, 0.3, "front arc"),
        (0.03, math.nan, "splay_rad"),
    ],
)
def test_a_front_array_that_cannot_exist_is_refused(
    pitch: float, splay: float, message: str
) -> None:
    with pytest.raises(ValueError, match=message):
        front_array_layout(pitch, splay)


def test_a_whisker_facing_a_wall_touches_at_the_gap() -> None:
    arena = PRESETS["slam"]
    # facing the right wall (x = 1.25) from 0.1 m short of the whisker bases' reach
    pose = np.array([1.25 - 0.15 - 0.1, 0.6, 0.0])
    d, seg = whisker_contacts(arena, pose)
    base = apply_motion(pose, np.c_[CRUNCHBOT_LAYOUT.base_m, np.zeros(4)])
    ang = CRUNCHBOT_LAYOUT.angle_rad
    expect = (1.25 - base[:, 0]) / np.cos(ang)
    expect[expect > 0.14] = np.inf
    np.testing.assert_allclose(d, expect)
    assert np.all(seg[np.isfinite(d)] == 1)  # the wall's right edge


def test_synthetic_run_contacts_lie_on_walls_and_obstacles_and_odometry_is_exact() -> None:
    arena = PRESETS["slam"]
    log = synthetic_log(arena, 120.0, seed=3, odometry_error=0.0, heading_drift_rad_m=0.0)
    assert set(log.state) <= set(STATES) and "HIT_1" in set(log.state)
    truth = arena.occupancy_grid()
    rows = np.flatnonzero(log.contact.any(axis=1))
    assert rows.size > 0
    for t in rows:
        w = np.flatnonzero(log.contact[t])
        pts = to_world(
            log.true_pose[t + 1][None], CRUNCHBOT_LAYOUT.points(log.radial_distance_m[t])[w]
        )[0]
        for x, y in pts:  # on an edge: an occupied cell within one cell
            i, j = int(x / 0.05), int(y / 0.05)
            assert truth[i - 1 : i + 2, j - 1 : j + 2].max() == 1
    pose = log.start_pose
    for inc in log.odometry:
        pose = apply_motion(pose, inc)
    np.testing.assert_allclose(pose[:2], log.true_pose[-1, :2], atol=1e-9)


def test_the_robot_never_drives_into_things_and_same_seed_same_log() -> None:
    arena = PRESETS["slam"]
    a = synthetic_log(arena, 60.0, seed=5)
    b = synthetic_log(arena, 60.0, seed=5)
    np.testing.assert_array_equal(a.odometry, b.odometry)
    off = arena.map_offset_m(2.5, 0.05)
    xy = a.true_pose[:, :2] - off
    assert np.all(xy > 0.17 - 1e-9) and np.all(xy < 1.25 - 0.17 + 1e-9)


def test_tiled_arena_gives_floor_likelihoods_of_the_true_tile() -> None:
    log = synthetic_log(PRESETS["tiles"], 20.0, seed=0, floor_likelihood=0.8)
    assert log.textures == ("rough-carpet", "smooth-carpet", "vinyl")
    assert log.floor_loglik.shape == (log.n_steps, 2, 3)
    assert np.allclose(np.exp(log.floor_loglik).max(axis=2), 0.8)
    assert synthetic_log(PRESETS["slam"], 5.0).floor_loglik is None


def test_synthetic_record_wraps_the_log_with_synthetic_signals() -> None:
    from vibrissa.robots.crunchbot.synthetic import synthetic_record

    arena = PRESETS["slam"]
    rec = synthetic_record(arena, 30.0, seed=3)
    log = synthetic_log(arena, 30.0, seed=3)
    assert np.array_equal(rec.log.state, log.state)
    assert np.allclose(rec.log.true_pose, log.true_pose)
    # robot time: FWD/BACK 0.5 s each, TURN its angle at 0.3 rad/s, events none
    assert rec.seconds >= 30.0 and rec.step_start[-1] == len(rec.time_s)
    # the poses at step boundaries are the true ones, in the arena frame
    offset = arena.map_offset_m(2.5, 0.05)
    inside = rec.step_start[:-1] < len(rec.time_s)
    at = rec.pose[rec.step_start[:-1][inside]]
    want = log.true_pose[:-1][inside] - [offset, offset, 0.0]
    assert np.allclose(at[:, :2], want[:, :2])
    # a touching whisker is deflected during its step, a free one reads only noise
    touch = np.flatnonzero(log.contact[:, 0] & (np.diff(rec.step_start) > 0))
    assert touch.size
    t = touch[0]
    seg = rec.hall_v[rec.step_start[t] : rec.step_start[t + 1], 0, 0]
    length = CRUNCHBOT_LAYOUT.length_m[0]
    assert np.mean(seg) == pytest.approx((length - log.radial_distance_m[t, 0]) / length, abs=0.01)
    assert np.array_equal(np.isfinite(rec.contact_true_m), log.contact)
    assert rec.latency_s == {} and rec.wall_seconds > 0


def test_synthetic_record_predicts_the_true_tile_texture() -> None:
    from vibrissa.robots.crunchbot.synthetic import synthetic_record

    rec = synthetic_record(PRESETS["tiles"], 20.0, seed=1)
    assert set(np.unique(rec.floor_texture_true)) <= {"vinyl", "smooth-carpet", "rough-carpet"}
    assert np.array_equal(rec.floor_texture_true, rec.floor_texture_pred)
    with pytest.raises(ValueError, match="sample_rate_hz"):
        synthetic_record(PRESETS["tiles"], 5.0, sample_rate_hz=0.0)
