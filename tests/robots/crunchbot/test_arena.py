"""CrunchBot's arena files, presets, validation and ground-truth grid (thesis 6.5.1, 6.5.3)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vibrissa.robots.crunchbot import PRESETS, ROBOT_RADIUS_M, Arena, Obstacle, Pose
from vibrissa.robots.crunchbot.arena import arena_from_dict, get_arena, load_arena

TOML = """
name = "two-boxes"
size_m = 1.0
tiles = [["vinyl", "rough-carpet"], ["smooth-carpet", "vinyl"]]
start = {x_m = 0.25, y_m = 0.25, heading_deg = 90.0}

[[obstacles]]
x_m = 0.6
y_m = 0.6
size_m = 0.2
"""


def _spec(**over: object) -> dict:
    spec = {
        "name": "t",
        "size_m": 1.25,
        "start": {"x_m": 0.3, "y_m": 0.3},
        "obstacles": [{"x_m": 0.5, "y_m": 0.5, "size_m": 0.25}],
    }
    spec.update(over)
    return spec


def test_presets_are_the_thesis_sizes() -> None:
    assert PRESETS["tiles"].size_m == 2.5 and len(PRESETS["tiles"].tiles) == 5
    assert PRESETS["slam"].size_m == 1.25 and len(PRESETS["slam"].obstacles) >= 2
    assert all(PRESETS[name].note for name in PRESETS)


def test_tiled_preset_obstacles_stand_on_carpet_and_use_all_three_textures() -> None:
    a = PRESETS["tiles"]
    for ob in a.obstacles:
        centre = a.texture_at(ob.x_m + ob.size_m / 2, ob.y_m + ob.size_m / 2)
        assert str(centre).endswith("carpet")
    assert {t for row in a.tiles for t in row} == {"vinyl", "smooth-carpet", "rough-carpet"}


def test_toml_and_json_files_give_the_same_arena(tmp_path) -> None:
    t = tmp_path / "a.toml"
    t.write_text(TOML)
    a = load_arena(t)
    assert a.obstacles == (Obstacle(0.6, 0.6, 0.2),)
    assert a.start == Pose(0.25, 0.25, np.pi / 2)
    assert a.texture_at(0.75, 0.25) == "rough-carpet"
    assert a.texture_at(0.25, 0.75) == "smooth-carpet"
    j = tmp_path / "a.json"
    j.write_text(
        json.dumps(
            {
                "name": "two-boxes",
                "size_m": 1.0,
                "tiles": [["vinyl", "rough-carpet"], ["smooth-carpet", "vinyl"]],
                "start": {"x_m": 0.25, "y_m": 0.25, "heading_deg": 90.0},
                "obstacles": [{"x_m": 0.6, "y_m": 0.6, "size_m": 0.2}],
            }
        )
    )
    assert get_arena(j) == a


@pytest.mark.parametrize(
    ("over", "words"),
    [
        (
            {"tiles": [["vinyl", "shag"], ["vinyl", "vinyl"]], "size_m": 1.0},
            "unknown tile texture 'shag'",
        ),
        ({"tiles": [["vinyl"]], "size_m": 1.0}, "tiles must be 2 rows of 2"),
        (
            {
                "obstacles": [
                    {"x_m": 0.5, "y_m": 0.5, "size_m": 0.25},
                    {"x_m": 0.7, "y_m": 0.6, "size_m": 0.25},
                ]
            },
            "obstacles[1] overlaps obstacles[0]",
        ),
        ({"obstacles": [{"x_m": 1.1, "y_m": 0.5, "size_m": 0.25}]}, "obstacles[0] lies outside"),
        ({"start": {"x_m": 0.6, "y_m": 0.6}}, "starts inside obstacles[0]"),
        ({"start": {"x_m": 0.35, "y_m": 0.6}}, "starts inside obstacles[0]"),
        ({"start": {"x_m": 0.1, "y_m": 0.3}}, "starts outside the arena"),
        ({"start": {"x_m": 3.0, "y_m": 0.3}}, "starts outside the arena"),
        ({"size_m": -1.0}, "size_m must be positive"),
        ({"colour": "red"}, "unknown key 'colour'"),
        ({"obstacles": [{"x_m": 0.5}]}, "each obstacle needs"),
    ],
)
def test_bad_arenas_are_refused_in_one_line_naming_the_problem(over: dict, words: str) -> None:
    with pytest.raises(ValueError) as info:
        arena_from_dict(_spec(**over), "my.toml")
    msg = str(info.value)
    assert words in msg and "\n" not in msg and "my.toml" in msg


def test_touching_obstacles_are_not_overlapping() -> None:
    Arena("t", 1.25, Pose(0.3, 0.3), (Obstacle(0.5, 0.5, 0.25), Obstacle(0.75, 0.5, 0.25)))


def test_files_of_other_formats_and_unknown_names_are_refused(tmp_path) -> None:
    bad = tmp_path / "a.yaml"
    bad.write_text("size_m: 1")
    with pytest.raises(ValueError, match="must end in .toml or .json"):
        load_arena(bad)
    broken = tmp_path / "b.toml"
    broken.write_text("size_m = [")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_arena(broken)
    with pytest.raises(ValueError, match="unknown arena 'moon'"):
        get_arena("moon")


def test_ground_truth_grid_counts_walls_and_obstacles_by_hand() -> None:
    a = PRESETS["slam"]
    g = a.occupancy_grid(cell_m=0.05, map_size_m=2.5)
    assert g.shape == (50, 50)
    assert a.map_offset_m(2.5, 0.05) == pytest.approx(0.6)
    # walls: the one-cell ring round the 25 x 25 cell arena; obstacles: 0.25 m -> 5 x 5
    # cells, 0.2 m -> 4 x 4 cells
    ring = 27**2 - 25**2
    assert g.sum() == ring + 25 + 16 + 16
    # the robot's start cell is free, the central obstacle's centre cell occupied
    assert g[int((0.3 + 0.6) / 0.05), int((0.3 + 0.6) / 0.05)] == 0
    assert g[int((0.625 + 0.6) / 0.05), int((0.625 + 0.6) / 0.05)] == 1
    assert g[int(0.59 / 0.05), 25] == 1 and g[int(0.54 / 0.05), 25] == 0


def test_segments_are_the_walls_and_obstacle_edges() -> None:
    a = PRESETS["slam"]
    seg = a.segments()
    assert seg.shape == (4 * (1 + len(a.obstacles)), 4)
    assert ROBOT_RADIUS_M == pytest.approx(0.17)
