"""CrunchBot's real-time classifiers on synthetic arrays with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.classify.realtime import (
    FloorTextureNB,
    RadialDistanceLinear,
    SurfaceAngleTemplates,
    peak_deflection,
)

FS = 2000.0


def _windows(rng: np.random.Generator, n: int, sd: float) -> np.ndarray:
    return 2.5 + rng.normal(0.0, sd, (n, 200, 2))


@pytest.fixture(scope="module")
def floor_nb() -> tuple[FloorTextureNB, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    quiet, rough = _windows(rng, 40, 0.01), _windows(rng, 40, 0.04)
    nb = FloorTextureNB().fit(np.concatenate([quiet, rough]), ["vinyl"] * 40 + ["carpet"] * 40, FS)
    test = np.concatenate([_windows(rng, 20, 0.01), _windows(rng, 20, 0.04)])
    return nb, test, np.array(["vinyl"] * 20 + ["carpet"] * 20)


def test_naive_bayes_separates_two_distributions(floor_nb) -> None:
    nb, test, truth = floor_nb
    assert nb.classes_ == ("carpet", "vinyl")
    pred = np.array([nb.predict(w) for w in test])
    assert np.mean(pred == truth) == 1.0


def test_loglik_is_the_estimators_summed_log_likelihood(floor_nb) -> None:
    """Softmax of loglik is the StationaryNaiveBayes posterior (flat priors)."""
    nb, test, _ = floor_nb
    ll = np.array([nb.loglik(w) for w in test[:5]])
    assert ll.shape == (5, 2) and np.all(ll < 0)
    post = np.exp(ll - ll.max(axis=1, keepdims=True))
    post /= post.sum(axis=1, keepdims=True)
    np.testing.assert_allclose(
        post, nb.estimator_.predict_proba(np.moveaxis(test[:5], 2, 1)), atol=1e-9
    )


def test_naive_bayes_bad_input(floor_nb) -> None:
    nb, test, _ = floor_nb
    with pytest.raises(ValueError, match="not fitted"):
        FloorTextureNB().loglik(test[0])
    with pytest.raises(ValueError, match="window must have shape"):
        nb.loglik(test[0][:100])
    bad = test[0].copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        nb.loglik(bad)
    with pytest.raises(ValueError, match="1000 Hz"):
        nb.loglik(test[0], sample_rate_hz=1000.0)
    with pytest.raises(ValueError, match="labels"):
        FloorTextureNB().fit(test, ["a"] * 3, FS)
    with pytest.raises(ValueError, match="windows must be 3-D"):
        FloorTextureNB().fit(test[0], ["a"] * 200, FS)


def test_a_linear_fit_recovers_a_line() -> None:
    rng = np.random.default_rng(1)
    peak = np.repeat(np.linspace(0.2, 1.2, 6), 5)
    dist = 0.14 - 0.05 * peak + rng.normal(0.0, 0.002, peak.size)
    fit = RadialDistanceLinear().fit(peak, dist)
    assert fit.intercept_m_ == pytest.approx(0.14, abs=0.003)
    assert fit.slope_m_per_v_ == pytest.approx(-0.05, abs=0.004)
    assert fit.residual_std_m_ == pytest.approx(0.002, rel=0.35)
    assert isinstance(fit.predict(0.5), float)
    np.testing.assert_allclose(
        fit.predict(np.array([0.2, 1.0])),
        fit.intercept_m_ + fit.slope_m_per_v_ * np.array([0.2, 1.0]),
    )
    exact = RadialDistanceLinear().fit(np.array([0.0, 1.0, 2.0]), np.array([1.0, 3.0, 5.0]))
    assert exact.predict(3.0) == pytest.approx(7.0) and exact.residual_std_m_ < 1e-12


def test_linear_fit_bad_input() -> None:
    with pytest.raises(ValueError, match="not fitted"):
        RadialDistanceLinear().predict(0.3)
    with pytest.raises(ValueError, match="same length"):
        RadialDistanceLinear().fit(np.ones(4), np.ones(5))
    with pytest.raises(ValueError, match="all peaks are equal"):
        RadialDistanceLinear().fit(np.ones(4), np.arange(4.0))
    with pytest.raises(ValueError, match="NaN"):
        RadialDistanceLinear().fit(np.array([0.1, np.nan, 0.3]), np.ones(3))


def test_peak_deflection_is_the_largest_magnitude() -> None:
    h = np.full((10, 2), 2.5)
    h[4] = [2.5 + 0.3, 2.5 - 0.4]
    h[7] = [2.5 - 0.45, 2.5]
    assert peak_deflection(h) == pytest.approx(0.5)
    with pytest.raises(ValueError, match=r"shape \(n, 2\)"):
        peak_deflection(np.ones((5, 3)))


def _angle_runs(rng: np.random.Generator, angles: np.ndarray, reps: int, n: int) -> np.ndarray:
    """Smooth 8-channel responses whose shape depends on the angle, plus noise."""
    t = np.arange(n) / FS
    ch = np.arange(8)
    clean = np.array(
        [
            2.5
            + 0.3
            * np.sin(2 * np.pi * (0.5 + ch[None] * 0.1) * t[:, None] + 3.0 * a + ch[None])
            * np.cos(a + ch[None])
            for a in angles
        ]
    )
    return np.repeat(clean, reps, axis=0) + rng.normal(0.0, 0.05, (len(angles) * reps, n, 8))


def test_templates_classify_noisy_copies_of_themselves() -> None:
    rng = np.random.default_rng(2)
    angles = np.radians(np.arange(20, 161, 10))
    runs = _angle_runs(rng, angles, 4, 4000)
    tm = SurfaceAngleTemplates().fit(runs, np.repeat(angles, 4), FS)
    assert tm.templates_.shape == (15, 4000, 8)
    np.testing.assert_allclose(tm.angles_rad_, angles)
    fresh = _angle_runs(rng, angles, 1, 4000)
    for a, rec in zip(angles, fresh, strict=True):
        assert tm.predict(rec) == pytest.approx(a)
        assert tm.predict(rec[:1200]) == pytest.approx(a)  # shorter than the templates


def test_template_scores_are_the_mean_squared_error_over_the_recordings_length() -> None:
    rng = np.random.default_rng(5)
    runs = _angle_runs(rng, np.array([0.3, 0.6, 0.9]), 2, 600)
    tm = SurfaceAngleTemplates().fit(runs, np.repeat([0.3, 0.6, 0.9], 2), FS)
    for m in (1, 37, 600, 900):
        rec = rng.normal(2.5, 0.2, (m, 8))
        k = min(m, 600)
        d = tm.templates_[:, :k] - tm.preprocess(rec[:k])[None]
        np.testing.assert_allclose(tm.scores(rec), np.mean(d * d, axis=(1, 2)), rtol=1e-9)
    with pytest.raises(ValueError, match="empty"):
        tm.scores(np.zeros((0, 8)))


def test_template_filters_are_causal() -> None:
    """A recording's first m preprocessed samples do not depend on what follows."""
    rng = np.random.default_rng(3)
    tm = SurfaceAngleTemplates().fit(
        _angle_runs(rng, np.array([0.3, 0.6]), 2, 1000), np.repeat([0.3, 0.6], 2), FS
    )
    rec = rng.normal(2.5, 0.1, (1000, 8))
    np.testing.assert_allclose(tm.preprocess(rec)[:300], tm.preprocess(rec[:300]))
    flat = np.full((50, 8), 2.7)
    np.testing.assert_allclose(tm.preprocess(flat), flat)  # steady state from the start


def test_templates_bad_input() -> None:
    rng = np.random.default_rng(4)
    runs = _angle_runs(rng, np.array([0.3, 0.6]), 2, 400)
    with pytest.raises(ValueError, match="not fitted"):
        SurfaceAngleTemplates().predict(runs[0])
    with pytest.raises(ValueError, match="8 channels"):
        SurfaceAngleTemplates().fit(runs[..., :6], np.repeat([0.3, 0.6], 2), FS)
    with pytest.raises(ValueError, match="one angle per recording"):
        SurfaceAngleTemplates().fit(runs, np.array([0.3, 0.6]), FS)
    tm = SurfaceAngleTemplates().fit(runs, np.repeat([0.3, 0.6], 2), FS)
    with pytest.raises(ValueError, match="1000 Hz"):
        tm.predict(runs[0], sample_rate_hz=1000.0)
    with pytest.raises(ValueError, match="NaN"):
        tm.predict(np.full((10, 8), math.nan))
    with pytest.raises(ValueError, match="Nyquist"):
        SurfaceAngleTemplates(cutoff_hz=1500.0).fit(runs, np.repeat([0.3, 0.6], 2), FS)
