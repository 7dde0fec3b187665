"""Evaluation of the thesis' classifiers: metrics, evaluation loops, report sections, figures.

Works the same on simulated and imported datasets (it never imports the simulator):

- :mod:`~vibrissa.evaluate.metrics`: signed errors in physical units, exact-hit
  rate, Cohen's kappa (per parameter, joint, weighted, from a confusion matrix);
- :mod:`~vibrissa.evaluate.scorers`: ``scoring=`` objects for scikit-learn's model
  selection on joint labels (:data:`joint_accuracy_scorer`, :data:`joint_kappa_scorer`);
- :mod:`~vibrissa.evaluate.loop`: the fit-and-score step, progress and JSON values
  every experiment shares;
- :mod:`~vibrissa.evaluate.chapter4`: :func:`run_chapter4` (thesis 4.2-4.4) and its
  building blocks (set split, reduced training subsets, scoring);
- :mod:`~vibrissa.evaluate.chapter5`: :func:`run_chapter5` (5.3-5.4);
- :mod:`~vibrissa.evaluate.chapter4_report`, :mod:`~vibrissa.evaluate.chapter5_report`:
  report sections beside the thesis' values (:data:`THESIS_CHAPTER4`,
  :data:`THESIS_CHAPTER5`), CSV tables, figures;
- :mod:`~vibrissa.evaluate.report_common`: JSON output, the report header, tables;
- :mod:`~vibrissa.evaluate.html`: the self-contained HTML report;
- :mod:`~vibrissa.evaluate.figures`: dataset and result figures (matplotlib, no
  pyplot state; loaded on first use).

Running an experiment end to end (dataset cache -> evaluation -> report) is the
orchestration layer's job: :mod:`vibrissa.reproduce`.
"""

from vibrissa.evaluate.chapter4 import (
    THESIS_FRACTIONS,
    Split,
    check_dataset,
    fit_and_score,
    run_chapter4,
    score_predictions,
    split_sets,
    subsample_indices,
)
from vibrissa.evaluate.chapter4_report import THESIS_CHAPTER4, markdown_report
from vibrissa.evaluate.chapter5 import (
    run_chapter5,
    score_chapter5,
    split_chapter5,
)
from vibrissa.evaluate.chapter5_report import THESIS_CHAPTER5, markdown_chapter5
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
    "THESIS_CHAPTER4",
    "THESIS_CHAPTER5",
    "THESIS_FRACTIONS",
    "Split",
    "check_dataset",
    "confusion_matrix",
    "error_summary",
    "exact_hit_rate",
    "fit_and_score",
    "joint_accuracy_scorer",
    "joint_kappa",
    "joint_kappa_scorer",
    "kappa",
    "kappa_from_confusion",
    "load_results",
    "markdown_chapter5",
    "markdown_report",
    "run_chapter4",
    "run_chapter5",
    "score_chapter5",
    "score_predictions",
    "signed_errors",
    "split_chapter5",
    "split_sets",
    "subsample_indices",
    "write_json",
]
