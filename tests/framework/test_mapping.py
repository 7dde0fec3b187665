"""The touch map: occupancy from contacts, texture and direction per cell, and its score."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.framework.mapping import UNEXPLORED, TouchMap, score_touch_map


def grid() -> TouchMap:
    return TouchMap((0.0, 0.0), 10.0, (20, 20))


def test_a_contact_marks_free_space_along_the_whisker_and_a_hit_at_its_point():
    tm = grid()
    tm.add_contact((15.0, 15.0), (155.0, 15.0))
    occ = tm.occupancy()
    assert occ[15, 1] > 0.5  # the contact's cell
    assert np.all(occ[2:15, 1] < 0.5)  # the cells the whisker swept
    assert occ[1, 1] < 0.5  # the pivot's cell was crossed too
    assert occ[10, 10] == UNEXPLORED  # nowhere near


def test_texture_is_the_arg_max_of_summed_log_posteriors():
    tm = grid()
    weak_wrong = np.array([0.1, 0.6, 0.2, 0.1])
    strong_right = np.array([0.0, 0.05, 0.95, 0.0])
    tm.add_contact((5.0, 5.0), (55.0, 55.0), weak_wrong)
    assert tm.texture_labels()[5, 5] == 1
    tm.add_contact((5.0, 5.0), (55.0, 55.0), strong_right)
    assert tm.texture_labels()[5, 5] == 2
    assert tm.texture_labels()[0, 19] == -1


def test_direction_is_a_circular_mean_mod_180():
    tm = grid()
    tm.add_contact((5.0, 5.0), (55.0, 55.0), direction_deg=179.0)
    tm.add_contact((5.0, 5.0), (55.0, 55.0), direction_deg=3.0)
    d = tm.directions_deg()[5, 5]
    assert min(abs(d - 1.0), abs(d - 181.0)) < 1e-6
    assert np.isnan(tm.directions_deg()[0, 0])


def test_score_counts_texture_only_on_wall_cells():
    tm = grid()
    occupancy = np.zeros((20, 20))
    occupancy[10:, :] = 1.0
    tex = np.full((20, 20), -1)
    tex[10, :] = 3
    direction = np.full((20, 20), np.nan)
    direction[10, :] = 90.0
    arena = np.ones((20, 20), dtype=bool)
    # two contacts on the wall (x = 100 mm), one right and one wrong, and one far off it
    tm.add_contact((5.0, 55.0), (101.0, 55.0), np.array([0, 0, 0, 1.0]), direction_deg=92.0)
    tm.add_contact((5.0, 125.0), (101.0, 125.0), np.array([1.0, 0, 0, 0]), direction_deg=80.0)
    tm.add_contact((5.0, 185.0), (45.0, 185.0), np.array([1.0, 0, 0, 0]))
    s = score_touch_map(tm, occupancy, tex, direction, arena)
    assert s["texture_cells"] == 2
    assert s["texture_accuracy"] == 0.5
    assert s["off_wall_texture_cells"] == 1
    assert s["direction_error_deg"] == pytest.approx(6.0)
    assert s["empty_map_error"] > 0 and s["occupancy_error"] > 0


def test_bad_input_is_refused_by_name():
    with pytest.raises(ValueError, match="cell_mm"):
        TouchMap((0.0, 0.0), 0.0, (5, 5))
    tm = grid()
    with pytest.raises(ValueError, match="point_mm"):
        tm.add_contact((0.0, 0.0), (np.nan, 1.0))
    with pytest.raises(ValueError, match="texture_proba"):
        tm.add_contact((0.0, 0.0), (10.0, 10.0), np.ones(3))
    with pytest.raises(ValueError, match="shape"):
        score_touch_map(tm, np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), np.ones((3, 3)))


@settings(max_examples=50, deadline=None)
@given(
    st.tuples(st.floats(-50, 250), st.floats(-50, 250)),
    st.tuples(st.floats(-50, 250), st.floats(-50, 250)),
)
def test_any_contact_keeps_the_map_a_probability(pivot, point):
    tm = grid()
    tm.add_contact(pivot, point, np.array([0.25, 0.25, 0.25, 0.25]), direction_deg=10.0)
    occ = tm.occupancy()
    assert np.all((occ >= 0) & (occ <= 1))
    assert set(np.unique(tm.texture_labels())) <= {-1, 0, 1, 2, 3}
