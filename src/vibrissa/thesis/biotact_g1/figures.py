"""Figures of the BIOTACT G1 (thesis 6.4): hit rate against training whisks (6.6, 6.7)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from matplotlib.figure import Figure

__all__ = ["hit_rate_figure"]


def hit_rate_figure(
    hit_rate: Mapping[str, Mapping[str, Sequence[float | None]]],
    title: str,
    spread: Mapping[str, Any] | None = None,
) -> Figure:
    """Figures 6.6 / 6.7: hit rate against training whisks.

    One panel per task (joint, texture, distance), one line per control strategy.

    ``hit_rate[strategy][task]`` lists one rate per number of training whisks (1, 2,
    ...); ``None`` (no validation whisk left) is not drawn. ``spread[strategy][task]``
    (optional, the same shape; leaves of :func:`vibrissa.evaluate.spread.spread_leaf`)
    adds the standard deviation over the sessions as error bars.
    """
    styles = ("-", "--", ":", "-.")
    tasks = ("joint", "texture", "distance")
    fig = Figure(figsize=(10.0, 3.4), layout="constrained")
    axes = fig.subplots(1, len(tasks), sharey=True)
    for ax, (letter, task) in zip(axes, zip("ABC", tasks, strict=True), strict=True):
        for k, (strategy, curves) in enumerate(hit_rate.items()):
            rates = curves[task]
            n = [i + 1 for i, r in enumerate(rates) if r is not None]
            leaves = ((spread or {}).get(strategy) or {}).get(task) or [None] * len(rates)
            err = [
                (leaf or {}).get("std") or 0.0
                for leaf, r in zip(leaves, rates, strict=False)
                if r is not None
            ]
            ax.errorbar(
                n,
                [r for r in rates if r is not None],
                yerr=err if len(err) == len(n) and any(err) else None,
                fmt=styles[k % len(styles)],
                marker="o",
                ms=3,
                color="k",
                capsize=2,
                label=strategy,
            )
        ax.set(xlabel="training whisks", title=f"({letter}) {task}", ylim=(0, 1.05))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("hit rate")
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(title, fontsize=10)
    return fig
