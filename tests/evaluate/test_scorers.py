"""Scorers for joint labels in scikit-learn's model selection (issue 13, finding 9)."""

from __future__ import annotations

import warnings

import numpy as np
from sklearn.model_selection import GridSearchCV, GroupKFold, cross_val_score

from vibrissa.classify import TimeTemplateClassifier
from vibrissa.evaluate import joint_accuracy_scorer, joint_kappa_scorer
from vibrissa.evaluate.scorers import joint_accuracy, joint_kappa_score


def _data():
    rng = np.random.default_rng(1)
    y = np.array([[r, s] for r in (50.0, 100.0) for s in (36.0, 43.2)] * 8)
    t = np.arange(60)
    X = rng.normal(0, 0.3, size=(len(y), 1, 60)) + (y[:, 0] / 50)[:, None, None] * np.sin(
        t * y[:, 1][:, None, None] / 100
    )
    return X, y, np.repeat(np.arange(4), 8)


def test_cross_val_score_on_joint_labels_is_finite() -> None:
    X, y, groups = _data()
    est = TimeTemplateClassifier(cutoff_hz=None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sk = cross_val_score(est, X, y, cv=GroupKFold(4), groups=groups, scoring="accuracy")
    assert np.isnan(sk).all()  # what scikit-learn's own accuracy gives on joint labels
    for scorer in (joint_accuracy_scorer, joint_kappa_scorer):
        s = cross_val_score(est, X, y, cv=GroupKFold(4), groups=groups, scoring=scorer)
        assert s.shape == (4,) and np.isfinite(s).all() and (s > 0.25).all()


def test_grid_search_with_joint_scorers() -> None:
    X, y, groups = _data()
    g = GridSearchCV(
        TimeTemplateClassifier(cutoff_hz=None),
        {"templates": ["all", "mean"]},
        cv=GroupKFold(4),
        scoring={"accuracy": joint_accuracy_scorer, "kappa": joint_kappa_scorer},
        refit="kappa",
        error_score="raise",
    ).fit(X, y, groups=groups)
    assert np.isfinite(g.cv_results_["mean_test_accuracy"]).all()
    assert np.isfinite(g.best_score_) and g.best_params_["templates"] in ("all", "mean")


def test_score_functions() -> None:
    t = np.array([[1.0, 2.0], [1.0, 3.0], [2.0, 2.0], [2.0, 3.0]])
    p = t.copy()
    p[0, 1] = 3.0
    assert joint_accuracy(t, p) == 0.75
    assert joint_accuracy(t[:, 0], p[:, 0]) == 1.0
    assert joint_kappa_score(t, t) == 1.0
    assert 0 < joint_kappa_score(t, p) < 1
    assert joint_kappa_score(t[:, 1], p[:, 1]) < 1
    assert np.isnan(joint_accuracy(t[:0], p[:0]))
