"""scikit-learn scorers for joint (multi-column) labels.

scikit-learn's own ``scoring="accuracy"`` rejects multiclass-multioutput targets
(rows such as ``[radial_distance_mm, speed_mm_s]``), so ``cross_val_score`` and
``GridSearchCV`` report NaN for every fold. These scorers score the joint class
instead (a trial counts as right when its whole row is right) and work for 1-D
labels too::

    from sklearn.model_selection import GroupKFold, cross_val_score
    from vibrissa.evaluate import joint_accuracy_scorer

    cross_val_score(TimeTemplateClassifier(), X, y, cv=GroupKFold(4), groups=sets,
                    scoring=joint_accuracy_scorer)
"""

from __future__ import annotations

from typing import Any

import numpy as np
from sklearn.metrics import make_scorer

from vibrissa.evaluate.metrics import exact_hit_rate, joint_kappa, kappa

__all__ = ["joint_accuracy", "joint_accuracy_scorer", "joint_kappa_scorer", "joint_kappa_score"]


def joint_accuracy(y_true: Any, y_pred: Any) -> float:
    """Fraction of trials whose whole label row is predicted exactly (NaN for none).

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,) or (n_trials, n_targets)
        Numeric labels (physical units, texture codes).

    Returns
    -------
    float
        In [0, 1]; compared after rounding as :func:`~vibrissa.evaluate.metrics.exact_hit_rate`.
    """
    rate = exact_hit_rate(y_true, y_pred)
    return float("nan") if rate is None else rate


def joint_kappa_score(y_true: Any, y_pred: Any) -> float:
    """Cohen's kappa of the joint class (each distinct label row is one class).

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,) or (n_trials, n_targets)
        Numeric labels; a 1-D label is one column.

    Returns
    -------
    float
        Unweighted kappa; NaN when it is undefined (no trials, or a single class
        in both ``y_true`` and ``y_pred``).
    """
    t, p = np.asarray(y_true), np.asarray(y_pred)
    value = joint_kappa(t, p) if t.ndim == 2 else kappa(t, p)
    return float("nan") if value is None else float(value)


#: ``scoring=`` for joint accuracy (larger is better).
joint_accuracy_scorer = make_scorer(joint_accuracy)
#: ``scoring=`` for the joint Cohen's kappa (larger is better).
joint_kappa_scorer = make_scorer(joint_kappa_score)
