"""Occupancy-grid evidence of tactile SLAM (6.5.5): blobs (eq. 6.1), oriented edges (eq. 6.2).

Every particle carries its own grid; grids are stacked as ``(n_particles, n, n)`` arrays
indexed ``[particle, ix, iy]`` (x first), cell ``(ix, iy)`` covering
``[ix * cell_m, (ix + 1) * cell_m)`` in x. The grids hold **log-odds**: the thesis adds a
likelihood ``Delta m`` per cell (0.5 meaning no evidence, above 0.5 occupied, below 0.5
free); we add ``logit(Delta m)``, the standard independent-cell Bayes update, so evidence
from several contacts accumulates and ``Delta m = 0.5`` adds nothing. A kernel's
likelihood falls from its peak ``Delta[x_c, y_c]`` to 0.5 away from the contact:
``Delta m = 0.5 + (Delta_c - 0.5) * exp(...)`` with the exponent of eq. 6.1 or 6.2 (the
printed equations would drive far cells to likelihood 0, i.e. certainly free, which the
text does not intend). Kernels are cut at ``radius_cells`` and where the likelihood
is within :data:`EXPLORED_DELTA` of 0.5.
"""

from __future__ import annotations

import numpy as np

#: A kernel's cells whose likelihood lies closer than this to 0.5 are left alone: neither
#: updated nor counted as explored (so a kernel's faint tail does not turn unexplored
#: cells, 0.3 in eq. 6.3, into explored ones at 0.5).
EXPLORED_DELTA = 0.01


def logit(p: np.ndarray | float) -> np.ndarray:
    """``log(p / (1 - p))``."""
    p = np.asarray(p, float)
    return np.log(p) - np.log1p(-p)


def occupancy(logodds: np.ndarray) -> np.ndarray:
    """Occupancy probability ``1 / (1 + exp(-l))`` of log-odds grids."""
    return 1.0 / (1.0 + np.exp(-np.asarray(logodds, float)))


def _window(n: int, centre_cell: np.ndarray, radius: int) -> tuple[np.ndarray, ...]:
    """Cells ``(ix, iy)`` of a ``(2r+1)^2`` window round each particle's cell, and validity."""
    off = np.arange(-radius, radius + 1)
    ix = centre_cell[:, 0, None, None] + off[None, :, None]
    iy = centre_cell[:, 1, None, None] + off[None, None, :]
    ix, iy = np.broadcast_arrays(ix, iy)
    valid = (ix >= 0) & (ix < n) & (iy >= 0) & (iy < n)
    return ix, iy, valid


def _add(
    logodds: np.ndarray,
    visited: np.ndarray,
    ix: np.ndarray,
    iy: np.ndarray,
    valid: np.ndarray,
    delta_p: np.ndarray,
    limit: float,
) -> None:
    """Add ``logit(delta_p)`` into each particle's window cells (in place, clipped)."""
    p_idx = np.broadcast_to(np.arange(logodds.shape[0])[:, None, None], ix.shape)
    keep = valid & (np.abs(delta_p - 0.5) >= EXPLORED_DELTA)
    sel = (p_idx[keep], ix[keep], iy[keep])
    # a particle's window cells are distinct, so plain fancy-index += adds each once
    logodds[sel] = np.clip(logodds[sel] + logit(delta_p[keep]), -limit, limit)
    visited[sel] = True


def cell_of(points_m: np.ndarray, cell_m: float) -> np.ndarray:
    """Integer cell ``(ix, iy)`` of map-frame points (any leading shape)."""
    return np.floor(np.asarray(points_m, float) / cell_m).astype(np.int64)


def add_blob(
    logodds: np.ndarray,
    visited: np.ndarray,
    centres_m: np.ndarray,
    peak_p: float,
    sigma_m: float,
    cell_m: float,
    radius_cells: int = 3,
    limit: float = 10.0,
) -> None:
    """Eq. 6.1: a Gaussian blob of evidence round each particle's contact cell (in place).

    ``Delta m[x, y] = 0.5 + (peak_p - 0.5) exp(-((x - x_c)^2 + (y - y_c)^2) / (2 sigma^2))``
    with ``(x_c, y_c)`` the centre of the cell holding the contact and ``(x, y)`` cell
    centres. ``peak_p > 0.5`` marks a contact, ``< 0.5`` free space (a free whisker's
    shaft, the robot's body).

    Parameters
    ----------
    logodds, visited
        ``(n_particles, n, n)`` grids, updated in place.
    centres_m
        ``(n_particles, 2)`` map-frame contact points, one per particle.
    """
    n = logodds.shape[1]
    c = cell_of(centres_m, cell_m)
    ix, iy, valid = _window(n, c, radius_cells)
    d2 = ((ix - c[:, 0, None, None]) ** 2 + (iy - c[:, 1, None, None]) ** 2) * cell_m**2
    dp = 0.5 + (peak_p - 0.5) * np.exp(-d2 / (2 * sigma_m**2))
    _add(logodds, visited, ix, iy, valid, dp, limit)


def edge_likelihood(
    dx_m: np.ndarray,
    dy_m: np.ndarray,
    angle_rad: np.ndarray,
    peak_p: float,
    sigma_r_m: float,
    sigma_theta_rad: float,
) -> np.ndarray:
    """Eq. 6.2's likelihood at offsets ``(dx, dy)`` from the contact midpoint.

    ``exp(-R^2 / (2 sigma_R^2) - (theta - theta_c)^2 / (2 sigma_theta^2))`` with
    ``(R, theta)`` the offset in polar form; an edge is a line, so ``theta - theta_c`` is
    taken modulo pi into ``[-pi/2, pi/2)``; at ``R = 0`` the angle term is 0.
    """
    r2 = dx_m**2 + dy_m**2
    dth = np.arctan2(dy_m, dx_m) - angle_rad
    dth = (dth + np.pi / 2) % np.pi - np.pi / 2
    dth = np.where(r2 > 0, dth, 0.0)
    return 0.5 + (peak_p - 0.5) * np.exp(
        -r2 / (2 * sigma_r_m**2) - dth**2 / (2 * sigma_theta_rad**2)
    )


def add_edge(
    logodds: np.ndarray,
    visited: np.ndarray,
    centres_m: np.ndarray,
    angle_rad: np.ndarray,
    peak_p: float,
    sigma_r_m: float,
    sigma_theta_rad: float,
    cell_m: float,
    radius_cells: int | None = None,
    limit: float = 10.0,
) -> None:
    """Eq. 6.2: a blur of long edges through each particle's contact midpoint (in place).

    Parameters
    ----------
    centres_m
        ``(n_particles, 2)`` map-frame contact midpoints.
    angle_rad
        ``(n_particles,)`` map-frame surface angles.
    radius_cells
        Window half-width; default three ``sigma_R``.
    """
    n = logodds.shape[1]
    r = radius_cells if radius_cells is not None else int(np.ceil(3 * sigma_r_m / cell_m))
    c = cell_of(centres_m, cell_m)
    ix, iy, valid = _window(n, c, r)
    dx = (ix + 0.5) * cell_m - centres_m[:, 0, None, None]
    dy = (iy + 0.5) * cell_m - centres_m[:, 1, None, None]
    dp = edge_likelihood(
        dx, dy, np.asarray(angle_rad, float)[:, None, None], peak_p, sigma_r_m, sigma_theta_rad
    )
    _add(logodds, visited, ix, iy, valid, dp, limit)


def occupancy_at(logodds: np.ndarray, points_m: np.ndarray, cell_m: float) -> np.ndarray:
    """Each particle's occupancy probability at its points ``(n_particles, k, 2)``.

    Points off the map read 0.5 (no knowledge).
    """
    n = logodds.shape[1]
    c = cell_of(points_m, cell_m)
    inside = np.all((c >= 0) & (c < n), axis=-1)
    ci = np.where(inside[..., None], c, 0)
    p_idx = np.broadcast_to(np.arange(logodds.shape[0])[:, None], inside.shape)
    lo = logodds[p_idx, ci[..., 0], ci[..., 1]]
    return np.where(inside, occupancy(lo), 0.5)
