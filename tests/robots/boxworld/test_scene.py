"""Tests of vibrissa.robots.boxworld.scene: faces, boxes, worlds and ground truth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.data.schema import TEXTURE_CODES
from vibrissa.robots.boxworld import BOX_WORLDS, Box, BoxWorld, Face, box_world


def test_face_normal_and_direction() -> None:
    f = Face((0.0, 0.0), (10.0, 0.0), "p80")
    np.testing.assert_allclose(f.normal, [0.0, -1.0])
    assert f.direction_deg == pytest.approx(0.0)
    assert Face((0.0, 0.0), (-1.0, -1.0), "p80").direction_deg == pytest.approx(45.0)
    assert f.distance_mm((5.0, 3.0)) == pytest.approx(3.0)
    with pytest.raises(ValueError, match="texture"):
        Face((0.0, 0.0), (1.0, 0.0), "velvet")
    with pytest.raises(ValueError, match="start_mm != end_mm"):
        Face((0.0, 0.0), (0.0, 0.0), "p80")


def test_box_square_normals_point_out() -> None:
    b = Box.square((10.0, 20.0), 40.0, 30.0, ("aluminium", "p600", "p180", "p80"))
    world = BoxWorld((b,))
    for f in world.faces:
        mid = 0.5 * (np.asarray(f.start_mm) + np.asarray(f.end_mm))
        assert not b.contains(mid + 1.0 * f.normal)
        assert b.contains(mid - 1.0 * f.normal)
    assert [f.texture for f in world.faces] == list(b.textures)
    with pytest.raises(ValueError, match="convex"):
        Box(((0.0, 0.0), (0.0, 1.0), (1.0, 0.0)), "p80")  # clockwise
    with pytest.raises(ValueError, match="one texture per edge"):
        Box.square((0.0, 0.0), 1.0, 0.0, ("p80", "p80"))


def test_room_walls_face_inward_and_inside() -> None:
    w = BoxWorld((), (0.0, 0.0, 100.0, 50.0), ("p80", "p180", "p600", "aluminium"))
    assert len(w.faces) == 4 and all(f.box == -1 for f in w.faces)
    for f in w.faces:
        mid = 0.5 * (np.asarray(f.start_mm) + np.asarray(f.end_mm))
        assert not w.inside(mid + 1.0 * f.normal)
    west = w.faces[0]
    assert west.start_mm[0] == west.end_mm[0] == 0.0 and west.texture == "p80"
    assert w.inside((-1.0, 10.0)) and not w.inside((50.0, 25.0))
    assert w.clearance_mm((50.0, 25.0)) == pytest.approx(25.0)
    assert w.clearance_mm((50.0, -5.0)) == pytest.approx(-5.0)


def test_worlds_refuse_overlaps_and_boxes_outside() -> None:
    a = Box.square((0.0, 0.0), 10.0)
    with pytest.raises(ValueError, match="overlap"):
        BoxWorld((a, Box.square((5.0, 5.0), 10.0, 30.0)))
    with pytest.raises(ValueError, match="inside the room"):
        BoxWorld((a,), (0.0, 0.0, 100.0, 100.0))


def test_presets() -> None:
    assert set(BOX_WORLDS) == {"furniture", "corner", "calibration"}
    f = box_world("furniture")
    assert len(f.boxes) == 4
    assert {t for b in f.boxes for t in b.textures} == set(TEXTURE_CODES)
    sides = [math.dist(b.vertices_mm[0], b.vertices_mm[1]) for b in f.boxes]
    assert min(sides) >= 60.0 - 1e-9 and max(sides) <= 200.0 + 1e-9
    assert len(f.corners()) == 16 and len(f.corner_faces()) == 16
    assert len(box_world("corner").boxes) == 1
    with pytest.raises(ValueError, match="unknown box world"):
        box_world("kitchen")
    assert BoxWorld.from_dict(f.to_dict()) == f


def test_ground_truth_of_the_corner_world() -> None:
    w = box_world("corner")  # box 650-850 mm on both axes
    g = w.ground_truth(cell_mm=10.0)
    assert g["shape"] == (150, 150) and g["occupancy"].shape == (150, 150)
    occ = g["occupancy"]
    assert occ[75, 75] == 1 and occ[20, 20] == 0
    assert occ[66:84, 66:84].all() and not occ[60:64, 60:64].any()
    # the box's west face x = 650 (a cell boundary: in column 65) crosses cell (65, 70)
    fi = g["face_index"]
    k = int(fi[65, 70])
    assert w.faces[k].box == 0 and w.faces[k].start_mm[0] == w.faces[k].end_mm[0] == 650.0
    assert g["texture_code"][65, 70] == TEXTURE_CODES[w.faces[k].texture]
    assert g["face_direction_deg"][65, 70] == pytest.approx(90.0)
    assert fi[20, 20] == -1 and g["texture_code"][20, 20] == -1
    assert np.isnan(g["face_direction_deg"][20, 20])
    # the walls are faces too
    assert fi[0, 75] >= 0 and w.faces[fi[0, 75]].box == -1


@settings(max_examples=40, deadline=None)
@given(x=st.floats(-200.0, 200.0), y=st.floats(-200.0, 200.0), rot=st.floats(0.0, 90.0))
def test_clearance_sign_matches_inside(x: float, y: float, rot: float) -> None:
    w = BoxWorld((Box.square((0.0, 0.0), 100.0, rot),))
    c = w.clearance_mm((x, y))
    assert (c <= 0.0) == w.inside((x, y)) or abs(c) < 1e-9
    assert abs(c) <= math.hypot(x, y) + 1e-9 + 100.0
