"""Figures of CrunchBot's tactile SLAM (thesis 6.5).

Average maps (6.14), a floor-texture trace across tile boundaries (6.11),
radial-distance estimates (6.12) and a trajectory.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

__all__ = [
    "average_maps_figure",
    "radial_distance_figure",
    "texture_trace_figure",
    "trajectory_figure",
]


def average_maps_figure(
    truth: np.ndarray,
    mean_maps: Mapping[str, np.ndarray],
    errors: Mapping[str, float],
    cell_m: float = 0.05,
) -> Figure:
    """The smoothed ground truth beside each mode's map averaged over runs (figure 6.14).

    Grids are ``[ix, iy]``; shown with x to the right and y up.
    """
    panels = [("ground truth (smoothed)", truth)] + [
        (f"{m} (eq. 6.3 error {errors[m]:.3f})", g) for m, g in mean_maps.items()
    ]
    fig = Figure(figsize=(3.2 * len(panels), 3.4), layout="constrained")
    axes = fig.subplots(1, len(panels))
    extent = (0.0, truth.shape[0] * cell_m, 0.0, truth.shape[1] * cell_m)
    for ax, (title, g) in zip(np.atleast_1d(axes), panels, strict=True):
        im = ax.imshow(
            np.asarray(g).T, origin="lower", extent=extent, cmap="gray_r", vmin=0.0, vmax=1.0
        )
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("x (m)")
    np.atleast_1d(axes)[0].set_ylabel("y (m)")
    fig.colorbar(im, ax=axes, shrink=0.8, label="occupancy")
    return fig


def texture_trace_figure(
    time_s: np.ndarray,
    true_codes: np.ndarray,
    pred_codes: np.ndarray,
    textures: Sequence[str],
    names: Sequence[str],
) -> Figure:
    """True tile texture and the classifier's choice per floor whisker over a run (6.11).

    ``true_codes``/``pred_codes`` are ``(n_steps, n_floor_whiskers)`` indices into
    ``textures`` (-1: none).
    """
    n: int = true_codes.shape[1]
    fig = Figure(figsize=(8.0, 1.8 * n + 0.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True))
    for k, ax in enumerate(axes):
        t, p = np.asarray(true_codes)[:, k], np.asarray(pred_codes)[:, k]
        ax.step(
            time_s,
            np.where(t >= 0, t, np.nan),
            where="post",
            color="0.3",
            lw=2,
            label="tile under the tip",
        )
        wrong = (p != t) & (p >= 0)
        ax.plot(
            time_s[~wrong & (p >= 0)],
            p[~wrong & (p >= 0)],
            "o",
            ms=2.5,
            color="tab:green",
            label="classifier (right)",
        )
        ax.plot(time_s[wrong], p[wrong], "x", ms=4, color="tab:red", label="classifier (wrong)")
        ax.set_yticks(range(len(textures)), list(textures))
        ax.set_ylim(-0.5, len(textures) - 0.5)
        ax.set_title(names[k], fontsize=9)
    axes[-1].set_xlabel("robot time (s)")
    axes[0].legend(fontsize=7, loc="upper right", ncols=3)
    return fig


def radial_distance_figure(
    estimated_m: np.ndarray,
    true_m: np.ndarray,
    names: Sequence[str],
    errors_mm: Mapping[str, float],
) -> Figure:
    """Estimated against true contact distance per obstacle whisker, and the error (6.12).

    ``estimated_m``/``true_m`` are ``(n_contacts_steps, n_whiskers)`` with NaN where no
    contact.
    """
    fig = Figure(figsize=(9.0, 3.8), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    lims = [np.inf, -np.inf]
    for w, name in enumerate(names):
        ok = np.isfinite(estimated_m[:, w]) & np.isfinite(true_m[:, w])
        if not ok.any():
            continue
        e, t = 1000 * estimated_m[ok, w], 1000 * true_m[ok, w]
        err = errors_mm.get(name)
        shown = "—" if err is None or not np.isfinite(err) else f"{err:.2f}"
        a1.plot(t, e, ".", ms=3, label=f"{name} (std {shown} mm)")
        a2.hist(e - t, bins=30, histtype="step", label=name)
        lims = [min(lims[0], t.min(), e.min()), max(lims[1], t.max(), e.max())]
    if np.isfinite(lims).all():
        a1.plot(lims, lims, "k--", lw=0.8)
    a1.set_xlabel("true radial distance (mm)")
    a1.set_ylabel("estimated (mm)")
    a1.legend(fontsize=7)
    a2.set_xlabel("estimate - truth (mm)")
    a2.set_ylabel("contact steps")
    a2.legend(fontsize=7)
    return fig


def trajectory_figure(
    true_pose: np.ndarray,
    estimates: Mapping[str, np.ndarray],
    truth: np.ndarray | None = None,
    cell_m: float = 0.05,
) -> Figure:
    """One run's true path against the filter's pose estimate per mode, over the ground truth.

    Dead reckoning is drawn as well.
    """
    fig = Figure(figsize=(5.5, 5.0), layout="constrained")
    ax = fig.add_subplot()
    if truth is not None:
        ax.imshow(
            np.asarray(truth).T,
            origin="lower",
            cmap="gray_r",
            vmin=0,
            vmax=1,
            extent=(0.0, truth.shape[0] * cell_m, 0.0, truth.shape[1] * cell_m),
        )
    ax.plot(true_pose[:, 0], true_pose[:, 1], "k-", lw=2, label="true")
    for name, est in estimates.items():
        ax.plot(est[:, 0], est[:, 1], lw=1, label=name)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=7)
    return fig
