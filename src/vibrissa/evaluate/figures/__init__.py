"""Figures every experiment shares: dataset figures and the figure helpers.

Every plotting function takes ``ax=None`` (or ``axes``/``fig``) and returns the
axes it drew on; with ``ax=None`` it creates a standalone
:class:`matplotlib.figure.Figure` (no pyplot state, no GUI backend, nothing is
shown). :func:`save_figure` writes PNGs atomically.

Dataset figures (input: an :class:`xarray.Dataset` of the package schema):

- :func:`deflection_traces`, :func:`typical_traces_figure` - figure 3.7 (and 6.5);
- :func:`angle_texture_traces` - figure 5.2;
- :func:`feature_grid`, :func:`feature_contours` - figure 4.1;
- :mod:`~vibrissa.evaluate.figures.whisking`: whisk trajectories with contacts (6.3, 6.4).

Each experiment's results figures live in its own package
(:mod:`vibrissa.thesis.<experiment>.figures`).
"""

from vibrissa.evaluate.figures.common import PARAMETER_LABELS, SHORT_NAMES, save_figure
from vibrissa.evaluate.figures.dataset import (
    angle_texture_traces,
    deflection_traces,
    feature_contours,
    feature_grid,
    typical_traces_figure,
)

__all__ = [
    "PARAMETER_LABELS",
    "SHORT_NAMES",
    "angle_texture_traces",
    "deflection_traces",
    "feature_contours",
    "feature_grid",
    "save_figure",
    "typical_traces_figure",
]
