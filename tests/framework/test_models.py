"""Tests of vibrissa.framework.models: model windows, fitting helpers, default estimators."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.base import clone

from vibrissa.classify import MiniRocketClassifier, StationaryNaiveBayes
from vibrissa.framework.detect import contact_windows
from vibrissa.framework.models import (
    WhatModel,
    WhereModel,
    default_what_estimator,
    default_where_estimator,
    fit_what,
    fit_where,
    model_windows,
)

from .test_detect import FS, match, synthetic_stream


def test_model_windows_identity_resample_and_channels():
    rng = np.random.default_rng(0)
    X = rng.standard_normal((3, 2, 1000))
    np.testing.assert_array_equal(model_windows(X, FS, FS), X)
    np.testing.assert_array_equal(model_windows(X, FS, FS, (1,)), X[:, [1]])
    down = model_windows(X, 4000.0, 2000.0)
    assert down.shape == (3, 2, 500)
    up = model_windows(X, 2000.0, 3000.0, (1, 0))
    assert up.shape == (3, 2, 1500)
    # a slow sine survives resampling
    t = np.arange(1000) / 4000.0
    s = np.sin(2 * np.pi * 20 * t)[None, None]
    np.testing.assert_allclose(
        model_windows(s, 4000.0, 2000.0)[0, 0, 50:450], s[0, 0, 100:900:2], atol=1e-2
    )


@pytest.mark.parametrize(
    ("args", "name"),
    [
        ((np.zeros((2, 1000)), FS, FS), "windows"),
        ((np.zeros((1, 2, 10)), -1.0, FS), "stream_rate_hz"),
        ((np.zeros((1, 2, 10)), FS, 0.0), "model_rate_hz"),
        ((np.zeros((1, 2, 10)), FS, FS, (2,)), "channels"),
        ((np.zeros((1, 2, 10)), 1.0, np.pi), "ratio"),
    ],
)
def test_model_windows_bad_input_named(args, name):
    with pytest.raises((ValueError, TypeError), match=name):
        model_windows(*args)


@pytest.fixture(scope="module")
def training():
    x, events = synthetic_stream(30.0, 4, seed=3)
    contacts = contact_windows(x, FS)
    labels = np.array([e[2] for e in match(contacts, events)])
    return np.stack([c.window for c in contacts]), labels


def test_fit_where_and_what_default_estimators(training):
    W, y = training
    n = len(W) // 2
    where = fit_where(default_where_estimator(1000.0), W[:n], y[:n, :2], FS, 1000.0, 55.0)
    assert isinstance(where.estimator, StationaryNaiveBayes)
    assert where.sample_rate_hz == 1000.0 and where.estimator.sample_rate_hz_ == 1000.0
    pred = where.classes[np.argmax(where.predict_proba(W[n:], FS), axis=1)]
    assert np.mean(pred[:, 0] == y[n:, 0]) >= 0.85  # tip or shaft
    tip = y[:, 0] == 60.0
    Wt, yt = W[tip], y[tip][:, [2, 1, 3]]  # (angle, speed, texture), texture column 2
    m = len(Wt) // 2
    what = fit_what(default_what_estimator(FS), Wt[:m], yt[:m], FS, FS)
    assert isinstance(what.estimator, MiniRocketClassifier)
    p = what.predict_proba(Wt[m:], FS)
    np.testing.assert_allclose(p.sum(axis=1), 1.0)
    pred = what.classes[np.argmax(p, axis=1)]
    assert np.mean((pred[:, [0, 2]] == yt[m:, [0, 2]]).all(axis=1)) >= 0.8
    rows, index = what.surface_classes()
    np.testing.assert_array_equal(rows[index], what.classes[:, [0, 2]])


def test_default_estimators_are_built_for_the_rate():
    assert default_where_estimator(2000.0).sample_rate_hz == 2000.0
    assert default_what_estimator(4000.0).pool == 8
    assert default_what_estimator(2000.0).pool == 4
    with pytest.raises(ValueError, match="sample_rate_hz"):
        default_what_estimator(0.0)


def test_models_check_their_parts(training):
    W, y = training
    est = clone(default_where_estimator(FS)).fit(W[:20], y[:20, :2], sample_rate_hz=FS)
    with pytest.raises(ValueError, match="fitted"):
        WhereModel(default_where_estimator(FS), FS, 55.0)
    with pytest.raises(ValueError, match="speed_column"):
        WhereModel(est, FS, 55.0, speed_column=2)
    with pytest.raises(ValueError, match="tip_radial_distance_mm"):
        WhereModel(est, FS, float("nan"))
    with pytest.raises(ValueError, match="texture_column"):
        WhatModel(est, FS)
    with pytest.raises(TypeError, match="predict_proba"):
        WhatModel(object(), FS)
    with pytest.raises(ValueError, match="labels"):
        fit_where(default_where_estimator(FS), W[:5], y[:4, :2], FS, FS, 55.0)
