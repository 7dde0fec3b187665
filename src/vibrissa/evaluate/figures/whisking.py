"""Figures every whisking robot shares: whisk trajectories with contacts (figures 6.5, 6.7)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

__all__ = ["whisk_trajectories_figure"]


def whisk_trajectories_figure(
    time_s: np.ndarray,
    angle_deg: np.ndarray,
    volts: np.ndarray,
    force_n: np.ndarray,
    titles: Sequence[str],
    gating: np.ndarray | None = None,
    signal_label: str = "Hall x (V)",
) -> Figure:
    """Housing angle (top), a deflection signal (middle) and gating ``z`` (bottom) of runs.

    The gating variable ``z`` is drawn only if given; contacts are shaded.

    Arrays are ``(n_runs, n)``; NaN pads are dropped.
    """
    n = len(titles)
    rows = 2 if gating is None else 3
    fig = Figure(figsize=(3.2 * n, 2.25 * rows), layout="constrained")
    axes = fig.subplots(rows, n, sharex="col", squeeze=False)
    for i in range(n):
        ok = np.isfinite(angle_deg[i])
        t = time_s[ok]
        touch = force_n[i][ok] > 0
        panels = [
            (axes[0, i], angle_deg[i][ok], "housing angle (deg)"),
            (axes[1, i], volts[i][ok], signal_label),
        ]
        if gating is not None:
            panels.append((axes[2, i], gating[i][ok], "z"))
        for ax, y, lab in panels:
            ax.plot(t, y, lw=0.8, color="k")
            lo, hi = np.nanmin(y), np.nanmax(y)
            ax.fill_between(
                t, lo, hi, where=touch, color="tab:red", alpha=0.25, lw=0, label="contact"
            )
            if i == 0:
                ax.set_ylabel(lab)
        axes[0, i].set_title(titles[i], fontsize=9)
        axes[-1, i].set_xlabel("time (s)")
    axes[0, 0].legend(loc="upper right", fontsize=8)
    return fig
