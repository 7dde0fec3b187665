"""Map error of tactile SLAM (thesis eq. 6.3) and its random-map baseline.

The thesis compares each run's grid map ``m`` with a ground-truth grid ``gt`` (occupied 1,
free 0) smoothed by a 5 x 5 Gaussian filter of standard deviation 2.5 cells, cells the
robot never explored counting as 0.3 (about the arena's mean occupancy):

    error = 1/N sum_runs 1/50 sum_x 1/50 sum_y |m[x, y] - gt[x, y]|        (6.3)

and quotes 0.47 for a random map drawn cell by cell from Bernoulli(0.5).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from vibrissa import _validate as v

#: The thesis' unexplored-cell occupancy and smoothing.
UNEXPLORED = 0.3
SMOOTH_SIZE = 5
SMOOTH_SIGMA = 2.5


def gaussian_kernel(size: int = SMOOTH_SIZE, sigma: float = SMOOTH_SIGMA) -> np.ndarray:
    """A ``size x size`` Gaussian filter summing to 1 (MATLAB's ``fspecial('gaussian')``)."""
    if isinstance(size, bool) or not isinstance(size, int) or size <= 0 or size % 2 == 0:
        raise ValueError(f"size must be a positive odd integer, got {size!r}")
    v.positive("sigma", sigma)
    r = np.arange(size) - size // 2
    k = np.exp(-(r[:, None] ** 2 + r[None, :] ** 2) / (2 * sigma**2))
    return k / k.sum()


def smooth_ground_truth(
    grid: np.ndarray, size: int = SMOOTH_SIZE, sigma: float = SMOOTH_SIGMA
) -> np.ndarray:
    """The ground truth as the thesis compares against: smoothed, zero beyond the map."""
    g = v.finite_array("ground truth", grid)
    if g.ndim != 2:
        raise ValueError(f"ground truth must be a 2-D grid, got shape {g.shape}")
    return ndimage.convolve(g, gaussian_kernel(size, sigma), mode="constant", cval=0.0)


def map_error(maps: np.ndarray, ground_truth: np.ndarray, mask: np.ndarray | None = None) -> float:
    """Eq. 6.3: mean absolute cell error of one map ``(n, n)`` or of runs ``(N, n, n)``.

    ``ground_truth`` is the already smoothed grid (:func:`smooth_ground_truth`); maps
    carry :data:`UNEXPLORED` where unexplored (``SlamRun.best_map`` does). ``mask``
    (boolean, the grid's shape) restricts the mean to its cells (e.g.
    :func:`arena_mask`); ``None``: every cell, as the thesis.
    """
    gt = v.finite_array("ground truth", ground_truth)
    m = v.finite_array("maps", maps)
    if m.shape[-2:] != gt.shape or m.ndim not in (2, 3):
        raise ValueError(f"maps must be {gt.shape} grids, got shape {m.shape}")
    err = np.abs(m - gt)
    if mask is None:
        return float(np.mean(err))
    keep = np.asarray(mask)
    if keep.shape != gt.shape or keep.dtype != bool:
        raise ValueError(f"mask must be a boolean {gt.shape} grid, got {keep.dtype} {keep.shape}")
    if not keep.any():
        raise ValueError("mask selects no cell")
    return float(np.mean(err[..., keep]))


def arena_mask(n_cells: int, cell_m: float, offset_m: float, size_m: float) -> np.ndarray:
    """The cells of a square map that hold the arena or its walls.

    A cell counts when its centre lies within ``[offset_m - cell_m, offset_m + size_m +
    cell_m]`` on both axes: the arena and the one-cell wall ring around it (where
    ``Arena.occupancy_grid`` puts the walls).
    """
    if isinstance(n_cells, bool) or not isinstance(n_cells, int) or n_cells <= 0:
        raise ValueError(f"n_cells must be a positive integer, got {n_cells!r}")
    v.positive("cell_m", cell_m)
    v.non_negative("offset_m", offset_m)
    v.positive("size_m", size_m)
    c = (np.arange(n_cells) + 0.5) * cell_m
    inside = (c >= offset_m - cell_m) & (c <= offset_m + size_m + cell_m)
    return inside[:, None] & inside[None, :]


def random_map_error(
    ground_truth: np.ndarray,
    rng: np.random.Generator,
    n_maps: int = 100,
    p: float = 0.5,
    smooth: bool = False,
    mask: np.ndarray | None = None,
) -> float:
    """The error of ``n_maps`` random maps, each cell Bernoulli(``p``), against the truth.

    With ``smooth=False`` its expectation is exactly 0.5 whatever the truth when
    ``p = 0.5`` (``E|B - g| = 0.5 (1 - g) + 0.5 g``); ``smooth=True`` passes each random
    map through the same 5 x 5 filter as the truth first. ``mask``: as :func:`map_error`.
    """
    if isinstance(n_maps, bool) or not isinstance(n_maps, int) or n_maps <= 0:
        raise ValueError(f"n_maps must be a positive integer, got {n_maps!r}")
    v.in_range("p", p, 0.0, 1.0)
    gt = v.finite_array("ground truth", ground_truth)
    maps = (rng.random((n_maps, *gt.shape)) < p).astype(float)
    if smooth:
        k = gaussian_kernel()
        maps = np.stack([ndimage.convolve(mp, k, mode="constant") for mp in maps])
    return map_error(maps, gt, mask)
