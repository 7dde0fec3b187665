"""The shared fit-and-classify step passes the dataset's sample rate (issue 13, finding 9)."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.classify import MiniRocketClassifier, SignalTransform, TimeTemplateClassifier
from vibrissa.evaluate.loop import check_rates, fit_predict


def _trials() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    y = np.repeat([[1.0, 10.0], [2.0, 10.0], [1.0, 20.0], [2.0, 20.0]], 4, axis=0)
    t = np.arange(64)
    X = y[:, :1, None] * np.sin(t * y[:, 1:, None] / 100.0) + 0.01 * rng.standard_normal(
        (len(y), 1, 64)
    )
    return X, y


def test_fit_predict_fits_at_the_given_rate() -> None:
    X, y = _trials()
    rec = fit_predict(
        "mr", MiniRocketClassifier(pool=2, n_dilations=2), X, y, X, sample_rate_hz=500.0
    )
    assert rec.estimator.sample_rate_hz_ == 500.0
    assert rec.y_pred.shape == y.shape
    bare = fit_predict("mr", MiniRocketClassifier(pool=2, n_dilations=2), X, y, X)
    assert bare.estimator.sample_rate_hz_ is None
    np.testing.assert_array_equal(bare.y_pred, rec.y_pred)


def test_fit_predict_refuses_an_estimator_built_for_another_rate() -> None:
    X, y = _trials()
    with pytest.raises(
        ValueError,
        match="'tt' failed to fit: TimeTemplateClassifier is built "
        "for sample_rate_hz=1000 Hz, but the data are sampled "
        "at 500 Hz",
    ):
        fit_predict("tt", TimeTemplateClassifier(), X, y, X, sample_rate_hz=500.0)


def test_check_rates_names_the_classifier() -> None:
    check_rates({"a": TimeTemplateClassifier(), "b": object()}, 1000.0)
    with pytest.raises(
        ValueError,
        match="classifier 'b' does not fit the dataset: "
        "SignalTransform is built for sample_rate_hz=4000 Hz",
    ):
        check_rates({"a": TimeTemplateClassifier(), "b": SignalTransform()}, 1000.0)
