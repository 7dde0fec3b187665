"""Figures of the thesis' chapters 3-5, split by what they draw.

Every plotting function takes ``ax=None`` (or ``axes``/``fig``) and returns the
axes it drew on; with ``ax=None`` it creates a standalone
:class:`matplotlib.figure.Figure` (no pyplot state, no GUI backend, nothing is
shown). :func:`save_figure` writes PNGs atomically.

Results figures (input: the dict of :func:`vibrissa.evaluate.chapter4.run_chapter4`):

- :func:`error_histogram`, :func:`error_scatter`, :func:`prediction_scatter` and
  :func:`classifier_figure` - figures 4.2, 4.3, 4.5, 4.7, 4.9, 4.11;
- :func:`training_size_plot` - figures 4.4, 4.6, 4.8, 4.10;
- :func:`static_beam_speed_plot` - figures 4.2b, 4.3b;
- :func:`comparison_plot` - figure 4.12;
- :func:`chapter4_figures` - all of them into a directory.

Dataset figures (input: an :class:`xarray.Dataset` of the package schema):

- :func:`deflection_traces`, :func:`typical_traces_figure` - figure 3.7 (and 6.5);
- :func:`angle_texture_traces` - figure 5.2;
- :func:`feature_grid`, :func:`feature_contours` - figure 4.1.
"""


from vibrissa.evaluate.figures.chapter4 import (
    chapter4_figures,
    classifier_figure,
    comparison_plot,
    error_histogram,
    error_scatter,
    prediction_scatter,
    static_beam_speed_plot,
    training_size_plot,
)
from vibrissa.evaluate.figures.chapter5 import (
    chapter5_figures,
    confusion_figure,
    kappa_figure,
    sequential_figure,
)
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
    "chapter4_figures",
    "chapter5_figures",
    "classifier_figure",
    "comparison_plot",
    "confusion_figure",
    "deflection_traces",
    "error_histogram",
    "error_scatter",
    "feature_contours",
    "feature_grid",
    "kappa_figure",
    "prediction_scatter",
    "save_figure",
    "sequential_figure",
    "static_beam_speed_plot",
    "training_size_plot",
    "typical_traces_figure",
]
