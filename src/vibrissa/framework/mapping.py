"""A map of what was touched: occupancy (as in 6.5) with a texture and a surface direction per cell.

Thesis 6.5 builds occupancy grids from whisker contacts; section 7.2 asks for texture in the
map too. :class:`TouchMap` keeps, per cell of a regular grid:

* **occupancy** as log odds: a contact point adds ``hit_log_odds`` to its cell, the straight
  whisker from its pivot to the contact adds ``free_log_odds`` (< 0) to every cell it crosses
  before the contact (the whisker passed through free space); a cell never touched by either
  is *unexplored* and reads :data:`UNEXPLORED` (0.3, the thesis' convention for eq. 6.3);
* **texture evidence**: the sum of the log posteriors of every tip contact in the cell (the
  sequential rule of :mod:`vibrissa.classify._sequential`, floored like it), whose arg max is
  the cell's texture;
* **surface direction**: the circular mean (mod 180 deg) of the surface directions the tip
  contacts in the cell reported.

Scoring (:func:`score_touch_map`): eq. 6.3 against the smoothed ground truth over the whole
grid and over the arena only, beside an empty map (all unexplored); texture-label accuracy
and surface-direction error over the touched cells that lie on a wall (a ground-truth face
within ``tolerance_cells`` of the cell).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import ndimage

from vibrissa._validate import finite, finite_array, positive
from vibrissa.slam.error import UNEXPLORED, smooth_ground_truth

__all__ = ["UNEXPLORED", "TouchMap", "score_touch_map"]


@dataclass
class TouchMap:
    """Occupancy, texture evidence and surface direction on a grid.

    Parameters
    ----------
    origin_mm : tuple of float
        World (x, y) of the grid's corner (the low edge of cell (0, 0)).
    cell_mm : float
        Cell size (mm).
    shape : tuple of int
        (n_x, n_y) cells.
    n_textures : int
        Texture classes (codes 0 .. n_textures - 1).
    hit_log_odds, free_log_odds : float
        Log-odds added by a contact in a cell and by the whisker crossing a cell.
    min_probability : float
        Floor of a contact's texture posterior before its log is added.
    """

    origin_mm: tuple[float, float]
    cell_mm: float
    shape: tuple[int, int]
    n_textures: int = 4
    hit_log_odds: float = 2.0
    free_log_odds: float = -0.4
    min_probability: float = 1e-3
    log_odds: np.ndarray = field(init=False, repr=False)
    explored: np.ndarray = field(init=False, repr=False)
    texture_evidence: np.ndarray = field(init=False, repr=False)
    texture_contacts: np.ndarray = field(init=False, repr=False)
    direction_sum: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        positive("cell_mm", self.cell_mm)
        if len(self.shape) != 2 or min(self.shape) < 1:
            raise ValueError(f"shape must be two positive cell counts, got {self.shape!r}")
        self.shape = (int(self.shape[0]), int(self.shape[1]))
        self.origin_mm = (
            finite("origin x", self.origin_mm[0]),
            finite("origin y", self.origin_mm[1]),
        )
        if self.hit_log_odds <= 0 or self.free_log_odds >= 0:
            raise ValueError("hit_log_odds must be > 0 and free_log_odds < 0")
        self.log_odds = np.zeros(self.shape)
        self.explored = np.zeros(self.shape, dtype=bool)
        self.texture_evidence = np.zeros((*self.shape, self.n_textures))
        self.texture_contacts = np.zeros(self.shape, dtype=int)
        self.direction_sum = np.zeros(self.shape, dtype=complex)

    # ------------------------------------------------------------------ updates
    def cell_of(self, point_mm: Any) -> tuple[int, int] | None:
        """The (i, j) cell holding a world point, or None outside the grid."""
        p = finite_array("point_mm", point_mm)
        i = int(math.floor((p[0] - self.origin_mm[0]) / self.cell_mm))
        j = int(math.floor((p[1] - self.origin_mm[1]) / self.cell_mm))
        if 0 <= i < self.shape[0] and 0 <= j < self.shape[1]:
            return i, j
        return None

    def add_contact(
        self,
        pivot_mm: Any,
        point_mm: Any,
        texture_proba: Any | None = None,
        direction_deg: float | None = None,
    ) -> None:
        """One contact: free space along the whisker, a hit at ``point_mm``.

        Parameters
        ----------
        pivot_mm, point_mm : array-like of shape (2,)
            The whisker's pivot and the (estimated) contact point, world mm.
        texture_proba : array-like of shape (n_textures,), optional
            The contact's texture posterior (tip contacts).
        direction_deg : float, optional
            The touched surface's direction in the world (deg, mod 180).
        """
        a = finite_array("pivot_mm", pivot_mm)
        b = finite_array("point_mm", point_mm)
        hit = self.cell_of(b)
        length = float(np.hypot(*(b - a)))
        n = max(2, int(math.ceil(length / (0.5 * self.cell_mm))) + 1)
        crossed: set[tuple[int, int]] = set()
        for t in np.linspace(0.0, 1.0, n)[:-1]:
            c = self.cell_of(a + t * (b - a))
            if c is not None and c != hit:
                crossed.add(c)
        for c in crossed:
            self.log_odds[c] += self.free_log_odds
            self.explored[c] = True
        if hit is None:
            return
        self.log_odds[hit] += self.hit_log_odds
        self.explored[hit] = True
        if texture_proba is not None:
            p = finite_array("texture_proba", texture_proba)
            if p.shape != (self.n_textures,):
                raise ValueError(
                    f"texture_proba must have shape ({self.n_textures},), got {p.shape}"
                )
            p = np.maximum(p / max(p.sum(), 1e-300), self.min_probability)
            self.texture_evidence[hit] += np.log(p / p.sum())
            self.texture_contacts[hit] += 1
        if direction_deg is not None and math.isfinite(direction_deg):
            self.direction_sum[hit] += np.exp(2j * math.radians(direction_deg))

    # ------------------------------------------------------------------ read-outs
    def occupancy(self) -> np.ndarray:
        """Occupancy probability per cell; :data:`UNEXPLORED` where nothing was learnt."""
        p = 1.0 / (1.0 + np.exp(-self.log_odds))
        return np.where(self.explored, p, UNEXPLORED)

    def texture_labels(self) -> np.ndarray:
        """Most probable texture code per cell, -1 where no tip contact landed."""
        lab = np.argmax(self.texture_evidence, axis=-1)
        return np.where(self.texture_contacts > 0, lab, -1)

    def directions_deg(self) -> np.ndarray:
        """Mean surface direction per cell (deg in [0, 180)), NaN where none was reported."""
        d = np.degrees(np.angle(self.direction_sum)) / 2.0 % 180.0
        return np.where(np.abs(self.direction_sum) > 0, d, np.nan)


def score_touch_map(
    touch: TouchMap,
    occupancy: np.ndarray,
    texture_code: np.ndarray,
    face_direction_deg: np.ndarray,
    arena: np.ndarray,
    tolerance_cells: int = 1,
) -> dict[str, Any]:
    """Score a map against the ground truth of the same grid.

    Parameters
    ----------
    touch : TouchMap
    occupancy : ndarray of shape (n_x, n_y)
        1 where solid, 0 where free.
    texture_code : ndarray of int, shape (n_x, n_y)
        Texture code of the face crossing each cell, -1 where none.
    face_direction_deg : ndarray of shape (n_x, n_y)
        Direction of that face (deg, mod 180), NaN where none.
    arena : ndarray of bool, shape (n_x, n_y)
        Cells inside the arena (the room and its walls).
    tolerance_cells : int
        A touched cell is on a wall when a face crosses a cell within this many cells.

    Returns
    -------
    dict
        ``occupancy_error`` and ``empty_map_error`` (eq. 6.3 over the grid),
        ``occupancy_error_arena`` and ``empty_map_error_arena`` (over the arena's cells),
        ``touched_cells``, ``texture_cells`` (touched wall cells with a texture),
        ``texture_accuracy``, ``off_wall_texture_cells`` (texture cells with no face within the
        tolerance), ``direction_error_deg`` (median absolute error over wall cells).
    """
    shapes = {a.shape for a in (occupancy, texture_code, face_direction_deg, arena)}
    if shapes != {touch.shape}:
        raise ValueError(f"ground-truth grids must all have the map's shape {touch.shape}")
    truth = smooth_ground_truth(np.asarray(occupancy, dtype=float))
    m = touch.occupancy()
    empty = np.full(truth.shape, UNEXPLORED)
    inside = np.asarray(arena, dtype=bool)
    # nearest face cell within the tolerance: its texture and direction
    faces = np.asarray(texture_code) >= 0
    dist, (ii, jj) = ndimage.distance_transform_edt(~faces, return_indices=True)
    near = dist <= tolerance_cells
    labels = touch.texture_labels()
    have = labels >= 0
    wall = have & near
    true_tex = np.asarray(texture_code)[ii, jj]
    dirs = touch.directions_deg()
    true_dir = np.asarray(face_direction_deg, dtype=float)[ii, jj]
    dmask = wall & np.isfinite(dirs) & np.isfinite(true_dir)
    derr = np.abs((dirs[dmask] - true_dir[dmask] + 90.0) % 180.0 - 90.0)
    return {
        "occupancy_error": float(np.mean(np.abs(m - truth))),
        "empty_map_error": float(np.mean(np.abs(empty - truth))),
        "occupancy_error_arena": float(np.mean(np.abs(m - truth)[inside])),
        "empty_map_error_arena": float(np.mean(np.abs(empty - truth)[inside])),
        "touched_cells": int(np.count_nonzero(touch.explored & (touch.log_odds > 0))),
        "texture_cells": int(np.count_nonzero(wall)),
        "texture_accuracy": float(np.mean(labels[wall] == true_tex[wall])) if wall.any() else None,
        "off_wall_texture_cells": int(np.count_nonzero(have & ~near)),
        "direction_error_deg": float(np.median(derr)) if derr.size else None,
    }
