"""Evaluation shared by the thesis' experiments: metrics, evaluation loops, reports, figures.

Works the same on simulated and imported datasets (it never imports the simulator):

- :mod:`~vibrissa.evaluate.metrics`: signed errors in physical units, exact-hit
  rate, Cohen's kappa (per parameter, joint, weighted, from a confusion matrix);
- :mod:`~vibrissa.evaluate.scorers`: ``scoring=`` objects for scikit-learn's model
  selection on joint labels (:data:`joint_accuracy_scorer`, :data:`joint_kappa_scorer`);
- :mod:`~vibrissa.evaluate.loop`: the fit-and-score step, progress and JSON values
  every experiment shares;
- :mod:`~vibrissa.evaluate.jobs`: evaluation jobs on worker processes over shared arrays;
- :mod:`~vibrissa.evaluate.report_common`: JSON output, the report header, tables;
- :mod:`~vibrissa.evaluate.html`: the self-contained HTML report;
- :mod:`~vibrissa.evaluate.baseline`: an earlier run's results beside this one's;
- :mod:`~vibrissa.evaluate.figures`: dataset figures and the figure helpers every
  experiment uses (matplotlib, no pyplot state; loaded on first use).

Each thesis experiment's own evaluation, report, figures and reference values live in
its package, :mod:`vibrissa.thesis.<experiment>` (e.g. chapter 4's
:func:`vibrissa.thesis.radial_distance.evaluation.run_chapter4`). Running an experiment
end to end (dataset cache -> evaluation -> report) is the orchestration layer's job:
:mod:`vibrissa.reproduce`.
"""

from vibrissa.evaluate.metrics import (
    confusion_matrix,
    error_summary,
    exact_hit_rate,
    joint_kappa,
    kappa,
    kappa_from_confusion,
    signed_errors,
)
from vibrissa.evaluate.report_common import load_results, write_json
from vibrissa.evaluate.scorers import joint_accuracy_scorer, joint_kappa_scorer

__all__ = [
    "confusion_matrix",
    "error_summary",
    "exact_hit_rate",
    "joint_accuracy_scorer",
    "joint_kappa",
    "joint_kappa_scorer",
    "kappa",
    "kappa_from_confusion",
    "load_results",
    "signed_errors",
    "write_json",
]
