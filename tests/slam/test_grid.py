"""Occupancy evidence of tactile SLAM by hand: eq. 6.1 blobs and eq. 6.2 oriented edges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.slam.grid import (
    EXPLORED_DELTA,
    add_blob,
    add_edge,
    edge_likelihood,
    logit,
    occupancy,
    occupancy_at,
)

CELL = 0.05


def _grids(n_particles: int = 1, n: int = 50) -> tuple[np.ndarray, np.ndarray]:
    return np.zeros((n_particles, n, n)), np.zeros((n_particles, n, n), dtype=bool)


def test_eq_6_1_blob_at_a_known_contact_by_hand() -> None:
    lo, seen = _grids()
    # a contact anywhere in cell (10, 12): eq. 6.1 centres the blob on that cell
    add_blob(
        lo,
        seen,
        np.array([[10.3 * CELL, 12.9 * CELL]]),
        peak_p=0.75,
        sigma_m=CELL,
        cell_m=CELL,
        radius_cells=3,
    )
    assert lo[0, 10, 12] == pytest.approx(math.log(3.0))  # logit(0.75)
    one = 0.5 + 0.25 * math.exp(-0.5)  # one cell away, sigma one cell
    assert lo[0, 11, 12] == pytest.approx(math.log(one / (1 - one)))
    assert lo[0, 10, 11] == pytest.approx(lo[0, 11, 12])
    diag = 0.5 + 0.25 * math.exp(-1.0)
    assert lo[0, 9, 13] == pytest.approx(math.log(diag / (1 - diag)))
    assert lo[0, 14, 12] == 0 and not seen[0, 14, 12]  # beyond the 3-cell radius
    three = 0.25 * math.exp(-4.5)  # three cells away: within EXPLORED_DELTA of 0.5
    assert (three >= EXPLORED_DELTA) == bool(seen[0, 13, 12])
    assert np.count_nonzero(lo) == np.count_nonzero(seen)


def test_negative_evidence_lowers_occupancy_and_evidence_adds_up() -> None:
    lo, seen = _grids()
    centre = np.array([[20.5 * CELL, 20.5 * CELL]])
    add_blob(lo, seen, centre, peak_p=0.4, sigma_m=CELL, cell_m=CELL)
    assert lo[0, 20, 20] == pytest.approx(logit(0.4))
    assert occupancy(lo)[0, 20, 20] == pytest.approx(0.4)
    add_blob(lo, seen, centre, peak_p=0.75, sigma_m=CELL, cell_m=CELL)
    assert lo[0, 20, 20] == pytest.approx(logit(0.4) + logit(0.75))


def test_each_particle_gets_its_own_blob_and_the_map_edge_clips() -> None:
    lo, seen = _grids(2)
    add_blob(
        lo,
        seen,
        np.array([[5.5 * CELL, 5.5 * CELL], [0.2 * CELL, 49.5 * CELL]]),
        peak_p=0.75,
        sigma_m=CELL,
        cell_m=CELL,
    )
    assert lo[0, 5, 5] == pytest.approx(math.log(3)) and lo[1, 5, 5] == 0
    assert lo[1, 0, 49] == pytest.approx(math.log(3)) and lo[0, 0, 49] == 0


def test_eq_6_2_edge_at_a_known_contact_by_hand() -> None:
    lo, seen = _grids()
    sr, st = 0.25, math.pi / 12
    centre = np.array([[25.5 * CELL, 25.5 * CELL]])  # a cell centre
    add_edge(
        lo,
        seen,
        centre,
        np.array([0.0]),
        peak_p=0.75,
        sigma_r_m=sr,
        sigma_theta_rad=st,
        cell_m=CELL,
    )
    assert lo[0, 25, 25] == pytest.approx(math.log(3))  # R = 0
    along = 0.5 + 0.25 * math.exp(-((5 * CELL) ** 2) / (2 * sr**2))  # 0.25 m along the edge
    assert lo[0, 30, 25] == pytest.approx(logit(along))
    assert lo[0, 20, 25] == pytest.approx(lo[0, 30, 25])  # a line: both ways
    assert lo[0, 25, 30] == 0 and not seen[0, 25, 30]  # across the edge: nothing
    # the edge reaches far: 0.5 m along it still counts, 0.1 m across it does not
    assert lo[0, 35, 25] > 0 and lo[0, 25, 27] == 0


def test_eq_6_2_angle_term_by_hand() -> None:
    sr, st = 0.25, math.pi / 12
    r = 0.1
    a = st  # one sigma_theta off the edge's direction
    p = edge_likelihood(
        np.array(r * math.cos(a)), np.array(r * math.sin(a)), np.array(0.0), 0.75, sr, st
    )
    assert p == pytest.approx(0.5 + 0.25 * math.exp(-(r**2) / (2 * sr**2) - 0.5))
    # an edge at pi/2 is the same line as one at -pi/2
    q1 = edge_likelihood(np.array(0.0), np.array(0.2), np.array(math.pi / 2), 0.75, sr, st)
    q2 = edge_likelihood(np.array(0.0), np.array(0.2), np.array(-math.pi / 2), 0.75, sr, st)
    assert q1 == pytest.approx(q2) == pytest.approx(0.5 + 0.25 * math.exp(-0.32))
    assert edge_likelihood(np.array(0.0), np.array(0.0), np.array(1.0), 0.75, sr, st) == 0.75


def test_occupancy_at_reads_each_particles_grid_and_half_off_the_map() -> None:
    lo, _ = _grids(2)
    lo[0, 3, 4] = logit(0.9)
    pts = np.array(
        [[[3.5 * CELL, 4.5 * CELL], [-1.0, 0.0]], [[3.5 * CELL, 4.5 * CELL], [9.0, 9.0]]]
    )
    np.testing.assert_allclose(occupancy_at(lo, pts, CELL), [[0.9, 0.5], [0.5, 0.5]])
