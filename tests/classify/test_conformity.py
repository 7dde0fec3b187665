"""sklearn conformity and bad-input handling of every chapter-4 classifier (3-D input)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import GridSearchCV, KFold
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import FunctionTransformer

from vibrissa.classify import CHAPTER4_KEYS, chapter4_classifiers

FS = 1000.0
WHISKER = {
    "length_mm": 185.0,
    "base_radius_mm": 1.0,
    "youngs_modulus_gpa": 2.35,
    "follicle_stiffness_nm_per_rad": 0.1,
    "hall_gain_v": 12.0,
}
# the estimators themselves (the line-up wraps each in a window Pipeline; the thesis
# presets' Pipelines are tested in test_thesis_presets.py)
ESTIMATORS = {
    k: v.steps[-1][1] for k, v in chapter4_classifiers(FS, WHISKER, preset="vibrissa").items()
}
# one parameter per estimator for GridSearchCV
GRID = {
    "static_beam_measured": {"latency_s": [0.2, 0.3]},
    "static_beam_fitted": {"latency_s": [0.3]},
    "frequency": {"cutoff_hz": [50.0, None]},
    "template": {"templates": ["all", "mean"]},
    "feature": {"degree": [2, 3]},
    "naive_bayes_raw": {"n_bins": [20, 50]},
    "naive_bayes_velocity": {"smoothing_sigma": [0.0, 2.0]},
    "naive_bayes_velocity_robust": {"smoothing_sigma": [0.0, 2.0]},
}
SMALL_GRID = {
    "youngs_modulus_gpa": [1.5, 2.35],
    "base_radius_mm": [1.0],
    "length_mm": [185.0, 230.0],
    "moment_scale": [1.0],
}


def _est(key: str):
    est = clone(ESTIMATORS[key])
    if key == "static_beam_fitted":
        est.set_params(param_grid=SMALL_GRID)  # keep the tests fast
    return est


def test_factory_keys_and_types() -> None:
    for preset in ("thesis", "vibrissa"):
        ests = chapter4_classifiers(1000.0, WHISKER, preset=preset)
        assert tuple(ests) == CHAPTER4_KEYS
        assert all(isinstance(e, Pipeline) for e in ests.values())
        assert ests["static_beam_fitted"][-1].fit_parameters is True
    assert ESTIMATORS["naive_bayes_velocity"].signal == "velocity"
    with pytest.raises(ValueError, match="sample_rate_hz"):
        chapter4_classifiers(0.0, WHISKER)


@pytest.mark.parametrize("key", CHAPTER4_KEYS)
def test_fit_predict_proba_consistency(key: str, trials) -> None:
    X, y = trials
    est = _est(key)
    assert est.fit(X, y) is est
    pred = est.predict(X)
    proba = est.predict_proba(X)
    assert pred.shape == y.shape
    assert proba.shape == (len(X), len(est.classes_))
    np.testing.assert_allclose(proba.sum(axis=1), 1.0)
    np.testing.assert_array_equal(est.classes_[np.argmax(proba, axis=1)], pred)
    assert est.n_channels_ == 2 and est.n_timepoints_ == X.shape[2]
    if key.startswith("static_beam"):
        assert np.all(np.isnan(pred[:, 1]))
        assert set(pred[:, 0]) <= set(y[:, 0])
    else:
        assert {tuple(r) for r in pred} <= {tuple(r) for r in y}
        assert est.score(X, y) > 0.5  # separable synthetic classes


@pytest.mark.parametrize("key", CHAPTER4_KEYS)
def test_clone_pickle_pipeline(key: str, trials) -> None:
    X, y = trials
    est = _est(key).fit(X, y)
    assert clone(est).get_params() == est.get_params()
    with pytest.raises(NotFittedError):
        clone(est).predict(X)
    again = pickle.loads(pickle.dumps(est))
    np.testing.assert_array_equal(again.predict(X), est.predict(X))
    np.testing.assert_array_equal(again.predict_proba(X), est.predict_proba(X))
    pipe = Pipeline([("identity", FunctionTransformer()), ("clf", _est(key))]).fit(X, y)
    np.testing.assert_array_equal(pipe.predict(X), est.predict(X))


@pytest.mark.parametrize("key", CHAPTER4_KEYS)
def test_grid_search_over_one_parameter(key: str, trial_factory) -> None:
    X, y = trial_factory(reps=4, seed=3)
    gs = GridSearchCV(_est(key), GRID[key], cv=KFold(2, shuffle=True, random_state=0))
    gs.fit(X, y)
    assert set(gs.best_params_) == set(GRID[key])
    assert gs.predict(X).shape == y.shape


@pytest.mark.parametrize("key", CHAPTER4_KEYS)
def test_one_dimensional_y_and_two_dimensional_X(key: str, trials) -> None:
    X, y = trials
    est = _est(key).fit(X[:, 0], y[:, 0])
    assert est.predict(X[:, 0]).shape == (len(X),)
    assert est.n_features_in_ == X.shape[2]


@pytest.mark.parametrize("key", CHAPTER4_KEYS)
def test_bad_input(key: str, trials) -> None:
    X, y = trials
    est = _est(key)
    with pytest.raises(NotFittedError):
        est.predict(X)
    for bad in (np.nan, np.inf):
        Xb = X.copy()
        Xb[1, 0, 5] = bad
        with pytest.raises(ValueError, match="NaN|infinity"):
            clone(est).fit(Xb, y)
    with pytest.raises(ValueError, match="single"):
        clone(est).fit(X, np.tile(y[:1], (len(X), 1)))
    with pytest.raises(ValueError, match="inconsistent"):
        clone(est).fit(X, y[:-1])
    est.fit(X, y)
    Xb = X.copy()
    Xb[0, 1, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        est.predict(Xb)
    with pytest.raises(ValueError, match="3 channels.*expecting 2 channels"):
        est.predict(np.concatenate([X, X[:, :1]], axis=1))
    with pytest.raises(ValueError, match="timepoints"):
        est.predict(X[:, :, :-1])
    with pytest.raises(ValueError, match="2-D"):
        est.predict(X[:, 0])
    with pytest.raises(ValueError, match="rectangular"):
        est.predict([X[0, 0], X[1, 0, :-3]])


def test_nan_labels_rejected(trials) -> None:
    X, y = trials
    yb = y.astype(float).copy()
    yb[0, 1] = np.nan
    with pytest.raises(ValueError, match="y contains NaN"):
        _est("template").fit(X, yb)
