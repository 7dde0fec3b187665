"""Evaluation of the thesis' classifiers: metrics, the chapter-4 protocol, figures, reports.

- :mod:`~vibrissa.evaluate.metrics`: signed errors in physical units, exact-hit
  rate, Cohen's kappa (per parameter, joint, weighted), confusion matrices;
- :mod:`~vibrissa.evaluate.protocol`: :func:`run_chapter4` (thesis 4.2-4.4) and
  its building blocks (set split, reduced training subsets, scoring);
- :mod:`~vibrissa.evaluate.figures`: figures 3.7, 4.1-4.12 and 5.2 (matplotlib,
  no pyplot state);
- :mod:`~vibrissa.evaluate.report`: JSON/CSV/Markdown output beside the thesis'
  tables 4.1-4.7 (:data:`THESIS_CHAPTER4`).

The figures module imports matplotlib; it is loaded on first use.
"""

from vibrissa.evaluate.metrics import (
    confusion_matrix,
    error_summary,
    exact_hit_rate,
    joint_kappa,
    kappa,
    signed_errors,
)
from vibrissa.evaluate.protocol import (
    THESIS_FRACTIONS,
    Split,
    check_dataset,
    fit_and_score,
    run_chapter4,
    score_predictions,
    split_sets,
    subsample_indices,
)
from vibrissa.evaluate.report import THESIS_CHAPTER4, markdown_report, write_json, write_report

__all__ = [
    "THESIS_CHAPTER4",
    "THESIS_FRACTIONS",
    "Split",
    "check_dataset",
    "confusion_matrix",
    "error_summary",
    "exact_hit_rate",
    "fit_and_score",
    "joint_kappa",
    "kappa",
    "markdown_report",
    "run_chapter4",
    "score_predictions",
    "signed_errors",
    "split_sets",
    "subsample_indices",
    "write_json",
    "write_report",
]

# chapter 5 (angle, speed and texture; see docs/chapter5.md)
from vibrissa.evaluate.chapter5 import (  # noqa: E402
    kappa_from_confusion,
    reproduce_angle_texture,
    run_chapter5,
    score_chapter5,
    split_chapter5,
)
from vibrissa.evaluate.chapter5_report import (  # noqa: E402
    THESIS_CHAPTER5,
    write_chapter5_report,
)

__all__ += [
    "THESIS_CHAPTER5",
    "kappa_from_confusion",
    "reproduce_angle_texture",
    "run_chapter5",
    "score_chapter5",
    "split_chapter5",
    "write_chapter5_report",
]
