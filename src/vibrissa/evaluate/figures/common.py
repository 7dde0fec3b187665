"""What every figure module shares: axis labels, short names, new axes, PNG output."""

from __future__ import annotations

import os
from pathlib import Path

from matplotlib.axes import Axes
from matplotlib.figure import Figure

from vibrissa._atomic import atomic_path

__all__ = ["PARAMETER_LABELS", "SHORT_NAMES", "check_parameter", "new_axes", "save_figure"]

#: Axis labels of the result parameters.
PARAMETER_LABELS = {"radius_mm": "radial distance (mm)", "speed_mm_s": "speed (mm/s)"}

#: Short names of the chapter-4 classifiers, as in the legend of figure 4.12.
SHORT_NAMES = {
    "static_beam_measured": "Static (meas.)",
    "static_beam_fitted": "Static (fit)",
    "frequency": "Freq",
    "template": "Temp",
    "feature": "Feat",
    "naive_bayes_raw": "NB (raw)",
    "naive_bayes_velocity": "NB (vel.)",
}


def new_axes(ax: Axes | None, figsize: tuple[float, float] = (5.0, 4.0)) -> Axes:
    """``ax``, or the axes of a new standalone Figure (no pyplot state)."""
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def check_parameter(parameter: str) -> str:
    """``parameter`` if it is a key of :data:`PARAMETER_LABELS`, else ValueError."""
    if parameter not in PARAMETER_LABELS:
        raise ValueError(f"parameter must be one of {sorted(PARAMETER_LABELS)}, got {parameter!r}")
    return parameter


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: int = 200) -> Path:
    """Write ``fig`` as a PNG atomically (never a half-written file at ``path``).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (e.g. ``ax.figure``).
    path : path-like
        Destination; parent directories are created.
    dpi : int, default=200
        Resolution.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    return Path(path)
