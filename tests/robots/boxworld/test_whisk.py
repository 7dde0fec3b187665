"""Tests of vibrissa.robots.boxworld.whisk: first contacts, the whisks' physics, moves."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from vibrissa.robots.boxworld import (
    Box,
    BoxWorld,
    HeadPose,
    WhiskingHead,
    box_world,
    can_move,
    first_contact,
    whisk,
    whisker_frame,
)

# one whisker at the head's origin pointing -y at rest (heading +x, right side), so
# it protracts counter-clockwise toward +x; its follicle pivot is 10 mm behind its
# base (the xy-robot whisker's follicle depth): the centre of rotation is (0, 10)
#: One whisker, unmodulated (every contact pushed to full protraction), so the physics
#: checks below see a long contact; the reflex has its own test.
HEAD = WhiskingHead(
    n_whiskers=1, pivots_mm=((0.0, 0.0),), retracted_deg=(90.0,), reflex_latency_s=None
)
POSE = HeadPose(0.0, 0.0, 0.0)
CENTRE = np.array([0.0, 10.0])
REACH = 195.0  # follicle depth + length


def _at(rho: float, phi_deg: float) -> np.ndarray:
    """The point at ``rho`` from the pivot along the whisker turned by ``phi_deg``."""
    p = math.radians(phi_deg)
    return CENTRE + rho * np.array([math.sin(p), -math.cos(p)])


def _wall_box() -> Box:
    # a box whose west face is x = 100 (facing -x) from y = -300 to -100
    return Box(((100.0, -300.0), (300.0, -300.0), (300.0, -100.0), (100.0, -100.0)), "p180")


def _diamond(left_vertex: np.ndarray, side_mm: float, texture: str = "p80") -> Box:
    c = left_vertex + np.array([side_mm / math.sqrt(2.0), 0.0])
    return Box.square(c, side_mm, 45.0, texture)


def test_whisker_frame_of_the_test_head() -> None:
    base, z, x = whisker_frame(POSE, HEAD, 0)
    np.testing.assert_allclose(base, [0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(z, [0.0, -1.0], atol=1e-12)
    np.testing.assert_allclose(x, [1.0, 0.0], atol=1e-12)


def test_face_ahead_is_a_tip_contact() -> None:
    world = BoxWorld((_wall_box(),))
    c = first_contact(world, POSE, HEAD, 0)
    assert c is not None and c.kind == "tip"
    assert c.sweep_deg == pytest.approx(math.degrees(math.asin(100.0 / REACH)))
    assert c.radial_distance_mm == pytest.approx(185.0)
    assert c.point_mm == pytest.approx((100.0, 10.0 - math.sqrt(REACH**2 - 100.0**2)))
    assert c.face == 3 and c.texture == "p180"
    # the face is parallel to the rest axis and faces -x in the whisker frame
    assert c.surface_angle_deg == pytest.approx(0.0, abs=1e-9)
    assert c.surface_side == -1
    assert c.world_face_direction_deg == pytest.approx(90.0)


def test_corner_at_a_known_radius_is_a_shaft_contact() -> None:
    v = _at(130.0, 20.0)  # 120 mm from the whisker's base
    world = BoxWorld((_diamond(v, 50.0),))
    c = first_contact(world, POSE, HEAD, 0)
    assert c is not None and c.kind == "shaft"
    assert c.sweep_deg == pytest.approx(20.0)
    assert c.radial_distance_mm == pytest.approx(120.0)
    assert c.point_mm == pytest.approx(tuple(v))
    assert len(c.face) == 2  # the two faces meeting at the vertex
    for k in c.face:
        f = world.faces[k]
        assert min(math.dist(f.start_mm, v), math.dist(f.end_mm, v)) < 1e-9
    assert c.texture is None and math.isnan(c.surface_angle_deg)


def test_corner_hidden_behind_a_face_is_not_reported() -> None:
    hidden = _diamond(_at(160.0, 35.0), 5.0)  # a corner met at 35 deg, after the face
    world = BoxWorld((_wall_box(), hidden))
    c = first_contact(world, POSE, HEAD, 0)
    assert c is not None and c.kind == "tip"
    assert c.sweep_deg == pytest.approx(math.degrees(math.asin(100.0 / REACH)))
    # without the face the corner is the first contact
    c2 = first_contact(BoxWorld((hidden,)), POSE, HEAD, 0)
    assert c2 is not None and c2.kind == "shaft" and c2.sweep_deg == pytest.approx(35.0)


def test_pressed_and_air() -> None:
    across = Box.square((0.0, -120.0), 30.0, 0.0, "p600")  # across the resting whisker
    c = first_contact(BoxWorld((across,)), POSE, HEAD, 0)
    assert c is not None and c.kind == "pressed" and c.sweep_deg == 0.0
    around = Box.square((0.0, 0.0), 30.0, 0.0, "p600")  # the base inside a box
    assert first_contact(BoxWorld((around,)), POSE, HEAD, 0).kind == "pressed"
    far = Box.square((600.0, 600.0), 30.0)
    assert first_contact(BoxWorld((far,)), POSE, HEAD, 0) is None


def test_wall_ahead_gives_a_negative_surface_angle() -> None:
    # a wall square to the heading 80 mm ahead, met by the tip of a whisker resting
    # 100 deg from the heading (10 deg back from sideways)
    world = BoxWorld((), room=(-500.0, -500.0, 80.0, 500.0))
    head = WhiskingHead(n_whiskers=1, pivots_mm=((0.0, 0.0),), retracted_deg=(100.0,))
    c = first_contact(world, POSE, head, 0)
    assert c is not None and c.kind == "tip"
    # rest direction at -100 deg: z = (cos -100, sin -100); the wall's normal (-1, 0)
    # has z-component -cos(-100) > 0: the angle is negative
    assert c.surface_angle_deg == pytest.approx(-10.0)
    assert c.surface_side == -1


@settings(max_examples=60, deadline=None)
@given(
    cx=st.floats(-250.0, 250.0),
    cy=st.floats(-250.0, 0.0),
    side=st.floats(10.0, 120.0),
    rot=st.floats(0.0, 90.0),
    heading=st.floats(-180.0, 180.0),
)
# the face beside the whisker's base: its root runs into the face before the shaft
# reaches the box's vertex (found by hypothesis)
@example(cx=12.0, cy=0.0, side=22.0, rot=7.0, heading=0.0)
def test_first_contact_is_the_first_crossing(
    cx: float, cy: float, side: float, rot: float, heading: float
) -> None:
    """Before the reported angle the swept whisker is clear; at it, it touches."""
    world = BoxWorld((Box.square((cx, cy), side, rot),))
    pose = HeadPose(0.0, 0.0, heading)
    c = first_contact(world, pose, HEAD, 0)
    base, z, x = whisker_frame(pose, HEAD, 0)
    centre = base - 10.0 * z
    box = world.boxes[0]

    verts = box.vertices
    edges = np.roll(verts, -1, axis=0) - verts

    def segment_hits(theta_deg: float) -> bool:
        t = math.radians(theta_deg)
        d = math.cos(t) * z + math.sin(t) * x
        pts = centre + np.linspace(10.0, REACH, 400)[:, None] * d
        r = pts[:, None, :] - verts[None, :, :]
        inside = np.all(edges[None, :, 0] * r[..., 1] - edges[None, :, 1] * r[..., 0] >= 0, axis=1)
        return bool(inside.any())

    if c is None:
        assert not any(segment_hits(t) for t in np.linspace(0.0, 40.0, 81))
        return
    if c.kind == "pressed":
        return
    for t in np.linspace(0.0, c.sweep_deg - 0.5, 20):
        if t >= 0.0:
            assert not segment_hits(t)
    p = np.asarray(c.point_mm)
    t = math.radians(c.sweep_deg)
    d = math.cos(t) * z + math.sin(t) * x
    r = p - centre
    assert abs(r[0] * d[1] - r[1] * d[0]) < 1e-6  # on the whisker's line
    assert 10.0 < float(r @ d) <= REACH + 1e-6
    assert world.clearance_mm(p) == pytest.approx(0.0, abs=1e-6)


def test_whisk_pole_contact_physics() -> None:
    v = _at(130.0, 20.0)
    world = BoxWorld((_diamond(v, 50.0),))
    rec = whisk(world, POSE, HEAD, np.random.default_rng(1))
    n = int(round(HEAD.period_s * HEAD.sample_rate_hz)) + 1
    assert rec.hall_v.shape == (n, 1, 2) and rec.time_s.shape == (n,)
    assert rec.contacts[0].kind == "shaft"
    onset = rec.truth_onsets_s[0, 0]
    # the housing (pattern A (1 - cos 2 pi f t) / 2, servo lag ~16 ms) reaches 20 deg at
    t20 = math.acos(1.0 - 2.0 * 20.0 / HEAD.amplitude_deg) / (2 * math.pi * HEAD.frequency_hz)
    assert t20 - 0.03 < onset < t20 + 0.03
    assert rec.truth_ends_s[0, 0] > onset
    # the pole holds the whisker back (toward -x): x reads below rest while touching
    k = int(round((onset + 0.2) * HEAD.sample_rate_hz))
    assert rec.hall_v[k, 0, 0] < rec.rest_v - 0.1
    # before the contact the cancellation leaves only noise about the rest output
    pre = rec.hall_v[: int(onset * HEAD.sample_rate_hz) - 10, 0, 0]
    assert abs(pre.mean() - rec.rest_v) < 2e-3 and pre.std() < 5e-3


def test_whisk_tip_contact_on_a_wall_ahead_runs_and_touches() -> None:
    world = BoxWorld((), room=(-500.0, -500.0, 80.0, 500.0), wall_textures="p180")
    head = WhiskingHead(n_whiskers=1, pivots_mm=((0.0, 0.0),), retracted_deg=(100.0,))
    rec = whisk(world, POSE, head, 3)
    c = rec.contacts[0]
    assert c.kind == "tip" and c.surface_angle_deg < 0.0
    assert rec.contact_force_n[:, 0].max() > 0.0
    assert np.isfinite(rec.truth_onsets_s[0, 0])
    assert np.all(np.isfinite(rec.hall_v))


def test_whisk_in_air_and_seeds() -> None:
    world = BoxWorld((Box.square((600.0, 600.0), 30.0),))
    a = whisk(world, POSE, HEAD, 5)
    b = whisk(world, POSE, HEAD, 5)
    np.testing.assert_array_equal(a.hall_v, b.hall_v)
    assert a.contacts == [None] and np.isnan(a.truth_onsets_s).all()
    assert abs(a.hall_v[:, 0, 0].mean() - a.rest_v) < 1e-3
    with pytest.raises(ValueError, match="n_whisks"):
        whisk(world, POSE, HEAD, 0, n_whisks=0)


def test_two_whisks_are_one_run() -> None:
    v = _at(130.0, 20.0)
    rec = whisk(BoxWorld((_diamond(v, 50.0),)), POSE, HEAD, 2, n_whisks=2)
    assert rec.truth_onsets_s.shape == (1, 2)
    assert rec.truth_onsets_s[0, 1] == pytest.approx(rec.truth_onsets_s[0, 0] + 2.0, abs=0.02)


def test_can_move() -> None:
    world = box_world("corner")
    head = WhiskingHead()
    start = HeadPose(300.0, 300.0, 0.0)
    assert can_move(world, start, head, start.moved(200.0))
    # straight through the box (650-850 on both axes)
    assert not can_move(world, HeadPose(400.0, 750.0, 0.0), head, HeadPose(1100.0, 750.0, 0.0))
    # into the west wall
    assert not can_move(world, start, head, HeadPose(20.0, 300.0, 0.0))
    with pytest.raises(ValueError, match="margin_mm"):
        can_move(world, start, head, start, margin_mm=-1.0)


def test_the_reflex_ends_the_contact_soon_after_the_first_touch() -> None:
    """RCP as a reflex: the row retracts ``reflex_latency_s`` after the first touch."""
    v = _at(130.0, 20.0)
    world = BoxWorld((_diamond(v, 50.0),))
    free = whisk(world, POSE, HEAD, np.random.default_rng(1))
    head = dataclasses.replace(HEAD, reflex_latency_s=0.1)
    rec = whisk(world, POSE, head, np.random.default_rng(1))
    on, end = rec.truth_onsets_s[0, 0], rec.truth_ends_s[0, 0]
    assert abs(on - free.truth_onsets_s[0, 0]) < 2e-3  # the same first touch
    # released within the latency plus the servo's turn-around (a 20 Hz servo: < 0.1 s)
    assert 0.1 < end - on < 0.2
    assert free.truth_ends_s[0, 0] - free.truth_onsets_s[0, 0] > 0.5
    # the in-air reference follows the same reflexed command: before the touch and after
    # the whisker has settled, the cancelled signal is at rest
    fs = rec.sample_rate_hz
    before = rec.hall_v[: int(on * fs) - 40, 0, 0]
    assert np.all(np.abs(before - rec.rest_v) < 0.02)
