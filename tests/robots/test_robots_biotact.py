"""The BIOTACT G1 head: where its whiskers meet a surface, and refused placements."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.biotact import G1Head
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.surfaces import make_surface


@pytest.mark.parametrize("distance_mm", [5.0, 10.0, 15.0])
def test_a_straight_whisker_at_its_contact_direction_has_its_tip_on_the_surface(distance_mm):
    head = G1Head()
    surface = make_surface("aluminium", 0)
    for i, L in enumerate(head.lengths_mm):
        model = RodModel(preset(f"biotact-g1-{L:g}"), 8)
        w = head.whisker(i, model, surface, distance_mm, side=0, hall_gain_v=1.0)
        n, _, _ = w.contact.frame()
        p = w.trajectory.position_mm[0]
        housing = math.radians(head.retracted_deg - head.contact_direction_deg(i, distance_mm))
        tip = L * np.array([math.sin(housing), math.cos(housing)])
        # the surface faces the head (-x in the whisker's frame): the tip is on it
        assert n[0] < 0
        assert abs(float((tip - p) @ n[[0, 2]])) < 1e-9
        # at full retraction the tip is clear of it, at full protraction beyond it
        for a, sign in ((0.0, 1.0), (head.amplitude_deg, -1.0)):
            t = L * np.array([math.sin(math.radians(a)), math.cos(math.radians(a))])
            assert sign * float((t - p) @ n[[0, 2]]) > 0


def test_the_three_whiskers_reach_a_plane_10_mm_ahead_together():
    head = G1Head()
    assert [head.contact_direction_deg(i, 10.0) for i in range(3)] == pytest.approx([60.0] * 3)
    for d in (5.0, 15.0):
        dirs = [head.contact_direction_deg(i, d) for i in range(3)]
        assert max(dirs) - min(dirs) < 2.5
    # and farther surfaces are met later in the protraction (smaller angle to the axis)
    for i in range(3):
        assert head.contact_direction_deg(i, 5.0) > head.contact_direction_deg(i, 15.0)


@pytest.mark.parametrize(
    ("distance", "match"),
    [
        (0.0, "places the head inside the surface"),
        (-4.0, "places the head inside the surface"),
        (80.0, "beyond the 80 mm whisker's reach"),
        (float("nan"), "distance_mm"),
    ],
)
def test_surface_placements_the_whisk_cannot_meet_are_refused(distance, match):
    with pytest.raises(ValueError, match=match):
        G1Head().check_distance(distance)


def test_a_surface_inside_the_reach_at_rest_is_refused():
    # a head whose whiskers rest pointing 60 deg from the axis already touch a plane 5 mm
    # ahead with the 158 mm whisker
    head = G1Head(retracted_deg=60.0, amplitude_deg=20.0)
    with pytest.raises(ValueError, match="inside the .* reach at full retraction"):
        head.check_distance(5.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"amplitude_deg": 90.0}, "must be below retracted_deg"),
        ({"setbacks_mm": (30.0, 46.0)}, "one value per whisker"),
        ({"setbacks_mm": (-1.0, 46.0, 69.0)}, "setbacks_mm must be >= 0"),
        ({"cone_half_angle_deg": 90.0}, "cone_half_angle_deg"),
        ({"amplitude_deg": -5.0}, "amplitude_deg"),
    ],
)
def test_impossible_heads_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        G1Head(**kwargs)


def test_whiskers_stand_on_the_cone():
    head = G1Head()
    tan = math.tan(math.radians(head.cone_half_angle_deg))
    for i, s in enumerate(head.setbacks_mm):
        assert head.base_radius_mm(i) == pytest.approx(head.front_radius_mm + s * tan)
