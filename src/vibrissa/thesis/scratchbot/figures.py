"""Figures of SCRATCHbot (thesis 6.3): features per condition, and figure 3.9's RCP gating."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

__all__ = ["gating_figure", "scratchbot_features_figure"]


def scratchbot_features_figure(conditions: Sequence[Mapping[str, Any]]) -> Figure:
    """Figure 6.5 in numbers, mean +/- std per condition.

    Peak deflection against radial distance (a) and contact duration against whisk
    frequency (b).
    """
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    panels = (
        (ax_a, "whisk_frequency_hz", "radial_distance_mm", "peak_deflection_v", "S = {:g} Hz"),
        (ax_b, "radial_distance_mm", "whisk_frequency_hz", "contact_duration_s", "R = {:g} mm"),
    )
    for ax, series, x_key, y_key, label in panels:
        for v in sorted({c[series] for c in conditions}):
            rows = sorted((c for c in conditions if c[series] == v), key=lambda c: c[x_key])
            ax.errorbar(
                [c[x_key] for c in rows],
                [c[y_key]["mean"] for c in rows],
                [c[y_key]["std"] for c in rows],
                marker="o",
                capsize=3,
                label=label.format(v),
            )
    ax_a.set(
        xlabel="radial distance (mm)",
        ylabel="peak deflection (V)",
        title="(a) peak deflection vs radial distance",
    )
    ax_b.set(
        xlabel="whisk frequency (Hz)",
        ylabel="contact duration (s)",
        title="(b) contact duration vs whisk speed",
    )
    ax_a.legend(fontsize=8)
    ax_b.legend(fontsize=8)
    return fig


def gating_figure(panels: Sequence[Mapping[str, Any]]) -> Figure:
    """Figure 3.9: whisk angles and the gating variable ``z``, per panel.

    Per panel, both sides' whisk angles with their obstructions (top) and the contacting
    side's gating variable ``z`` (bottom).

    Each panel maps ``title``, ``time_s``, ``angle_deg`` (2, n), ``gating`` (2, n)
    and ``obstacle_deg`` (2,).
    """
    fig = Figure(figsize=(5.0 * len(panels), 4.5), layout="constrained")
    axes = fig.subplots(
        2, len(panels), squeeze=False, sharex="col", gridspec_kw={"height_ratios": [3, 1]}
    )
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
