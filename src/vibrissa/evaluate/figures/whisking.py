"""Figures of the whisking robots: whisk trajectories with contacts, figs 6.5-6.7 and 3.9."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

__all__ = ["gating_figure", "hit_rate_figure", "scratchbot_features_figure",
           "whisk_trajectories_figure"]


def whisk_trajectories_figure(time_s: np.ndarray, angle_deg: np.ndarray, volts: np.ndarray,
                              force_n: np.ndarray, titles: Sequence[str],
                              gating: np.ndarray | None = None,
                              signal_label: str = "Hall x (V)") -> Figure:
    """Housing angle (top), a deflection signal (middle) and, if given, the gating
    variable ``z`` (bottom) of some runs, contacts shaded.

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
        panels = [(axes[0, i], angle_deg[i][ok], "housing angle (deg)"),
                  (axes[1, i], volts[i][ok], signal_label)]
        if gating is not None:
            panels.append((axes[2, i], gating[i][ok], "z"))
        for ax, y, lab in panels:
            ax.plot(t, y, lw=0.8, color="k")
            lo, hi = np.nanmin(y), np.nanmax(y)
            ax.fill_between(t, lo, hi, where=touch, color="tab:red", alpha=0.25, lw=0,
                            label="contact")
            if i == 0:
                ax.set_ylabel(lab)
        axes[0, i].set_title(titles[i], fontsize=9)
        axes[-1, i].set_xlabel("time (s)")
    axes[0, 0].legend(loc="upper right", fontsize=8)
    return fig


def scratchbot_features_figure(conditions: Sequence[Mapping[str, Any]]) -> Figure:
    """Figure 6.5 in numbers: peak deflection against radial distance (a) and
    contact duration against whisk frequency (b), mean +/- std per condition."""
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    panels = ((ax_a, "whisk_frequency_hz", "radial_distance_mm", "peak_deflection_v",
               "S = {:g} Hz"),
              (ax_b, "radial_distance_mm", "whisk_frequency_hz", "contact_duration_s",
               "R = {:g} mm"))
    for ax, series, x_key, y_key, label in panels:
        for v in sorted({c[series] for c in conditions}):
            rows = sorted((c for c in conditions if c[series] == v), key=lambda c: c[x_key])
            ax.errorbar([c[x_key] for c in rows], [c[y_key]["mean"] for c in rows],
                        [c[y_key]["std"] for c in rows], marker="o", capsize=3,
                        label=label.format(v))
    ax_a.set(xlabel="radial distance (mm)", ylabel="peak deflection (V)",
             title="(a) peak deflection vs radial distance")
    ax_b.set(xlabel="whisk frequency (Hz)", ylabel="contact duration (s)",
             title="(b) contact duration vs whisk speed")
    ax_a.legend(fontsize=8)
    ax_b.legend(fontsize=8)
    return fig


def gating_figure(panels: Sequence[Mapping[str, Any]]) -> Figure:
    """Figure 3.9: per panel, both sides' whisk angles with their obstructions (top)
    and the contacting side's gating variable ``z`` (bottom).

    Each panel maps ``title``, ``time_s``, ``angle_deg`` (2, n), ``gating`` (2, n)
    and ``obstacle_deg`` (2,).
    """
    fig = Figure(figsize=(5.0 * len(panels), 4.5), layout="constrained")
    axes = fig.subplots(2, len(panels), squeeze=False, sharex="col",
                        gridspec_kw={"height_ratios": [3, 1]})
    for i, p in enumerate(panels):
        t = np.asarray(p["time_s"])
        ax = axes[0, i]
        ax.plot(t, p["angle_deg"][0], color="k", lw=2.0, label="left (contacting)")
        ax.plot(t, p["angle_deg"][1], color="k", lw=0.8, label="right")
        for k, ls in ((0, ":"), (1, ":")):
            ax.axhline(p["obstacle_deg"][k], color="grey", ls=ls, lw=1.0)
        ax.set_title(p["title"], fontsize=9)
        ax.set_ylabel("protraction angle (deg)")
        axes[1, i].plot(t, p["gating"][0], color="k")
        axes[1, i].set(xlabel="time (s)", ylabel="z (left)", ylim=(-0.05, 1.05))
    axes[0, 0].legend(fontsize=8, loc="lower right")
    return fig


def hit_rate_figure(hit_rate: Mapping[str, Mapping[str, Sequence[float | None]]],
                    title: str) -> Figure:
    """Figures 6.6 / 6.7: hit rate against training whisks, one panel per task
    (joint, texture, distance), one line per control strategy.

    ``hit_rate[strategy][task]`` lists one rate per number of training whisks (1, 2,
    ...); ``None`` (no validation whisk left) is not drawn.
    """
    styles = ("-", "--", ":", "-.")
    tasks = ("joint", "texture", "distance")
    fig = Figure(figsize=(10.0, 3.4), layout="constrained")
    axes = fig.subplots(1, len(tasks), sharey=True)
    for ax, (letter, task) in zip(axes, zip("ABC", tasks, strict=True), strict=True):
        for k, (strategy, curves) in enumerate(hit_rate.items()):
            rates = curves[task]
            n = [i + 1 for i, r in enumerate(rates) if r is not None]
            ax.plot(n, [r for r in rates if r is not None], styles[k % len(styles)],
                    marker="o", ms=3, color="k", label=strategy)
        ax.set(xlabel="training whisks", title=f"({letter}) {task}", ylim=(0, 1.05))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("hit rate")
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(title, fontsize=10)
    return fig
