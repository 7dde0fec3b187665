"""Each chapter-4 method on synthetic data where the answer is known."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.special import softmax

from vibrissa.classify import (
    FeatureRegressionClassifier,
    FrequencyTemplateClassifier,
    StaticBeamClassifier,
    StationaryNaiveBayes,
    TimeTemplateClassifier,
    nearest_template_scores,
    polynomial_powers,
    static_beam_radius_mm,
)

FS = 1000.0


# --- static beam (4.3.1) ------------------------------------------------------------------
def _beam_trials(whisker, radii, speed_mm_s, E=None, rb=None, L=None, n_t=101):
    """Noise-free trials whose peak voltage follows eqs. 4.1-4.2 with theta = d / r."""
    E = whisker["youngs_modulus_gpa"] if E is None else E
    rb = whisker["base_radius_mm"] if rb is None else rb
    L = whisker["length_mm"] if L is None else L
    c = 3.0 * E * 1e9 * math.pi * (rb * 1e-3) ** 4 / 4.0
    r = np.asarray(radii, dtype=float)
    theta = speed_mm_s * 0.3 / r
    moment = c * theta * (L - r) * 1e-3 / (r * 1e-3 * L * 1e-3)  # M = C theta (L - r) / (r L)
    dv = whisker["hall_gain_v"] * np.tan(moment / whisker["follicle_stiffness_nm_per_rad"])
    t = np.arange(n_t) - n_t // 2
    pulse = np.exp(-0.5 * (t / 10.0) ** 2)
    X = np.stack([2.5 + dv[:, None] * pulse, np.full((len(r), n_t), 2.5)], axis=1)
    return X


def test_static_beam_formula_limits() -> None:
    assert static_beam_radius_mm(0.0, 36.0, 2.4, 1.0, 185.0) == pytest.approx(185.0)
    r = static_beam_radius_mm(np.array([1e-4, 1e-3, 1e-2]), 36.0, 2.4, 1.0, 185.0)
    assert np.all(np.diff(r) < 0)  # a larger moment means a closer contact


def test_static_beam_inverts_noise_free_data_exactly(whisker) -> None:
    radii = np.arange(80.0, 181.0, 5.0)
    X = _beam_trials(whisker, radii, 126.0)
    y = np.column_stack([radii, np.full_like(radii, 126.0)])
    est = StaticBeamClassifier(whisker=whisker).fit(X, y)
    assert est.protraction_mm_ == pytest.approx(126.0 * 0.3)
    np.testing.assert_allclose(est.predict_radius_mm(X), radii, rtol=1e-10)
    pred = est.predict(X)
    np.testing.assert_array_equal(pred[:, 0], radii)
    assert np.all(np.isnan(pred[:, 1]))
    assert est.training_error_mm_ == 0.0
    assert est.score(X, y) == 1.0
    # 1-D y: the radius; speed from speed_mm_s; whisker given as JSON (the Dataset attr)
    est1 = StaticBeamClassifier(whisker=json.dumps(whisker), speed_mm_s=126.0).fit(X, radii)
    np.testing.assert_array_equal(est1.predict(X), radii)


def test_static_beam_uses_median_training_speed(whisker) -> None:
    radii = np.array([90.0, 120.0, 150.0, 150.0, 120.0])
    X = _beam_trials(whisker, radii, 100.0)
    y = np.column_stack([radii, [40.0, 100.0, 100.0, 160.0, 100.0]])  # median 100
    est = StaticBeamClassifier(whisker=whisker).fit(X, y)
    np.testing.assert_allclose(est.predict_radius_mm(X), radii, rtol=1e-10)


def test_static_beam_grid_fit_recovers_other_parameters(whisker) -> None:
    radii = np.arange(80.0, 181.0, 4.0)
    X = _beam_trials(whisker, radii, 126.0, E=1.5, rb=1.2, L=230.0)
    y = np.column_stack([radii, np.full_like(radii, 126.0)])
    measured = StaticBeamClassifier(whisker=whisker).fit(X, y)
    assert measured.training_error_mm_ > 5.0
    fitted = StaticBeamClassifier(whisker=whisker, fit_parameters=True).fit(X, y)
    assert fitted.training_error_mm_ == 0.0
    assert np.max(np.abs(fitted.predict_radius_mm(X) - radii)) < 2.0
    # Several grid points snap every trial correctly; on a grid holding only the true
    # length, E, r_base and the scale are identified through S / (E r_base^4).
    # With r_base held at 1 mm, E = 1.5 * 1.2^4 GPa is equivalent to the truth.
    e_equiv = 1.5 * 1.2**4
    grid = {"length_mm": [185.0, 230.0], "youngs_modulus_gpa": [2.0, e_equiv, 4.0]}
    exact = StaticBeamClassifier(whisker=whisker, fit_parameters=True, param_grid=grid)
    exact.fit(X, y)
    assert (exact.youngs_modulus_gpa_, exact.length_mm_) == (pytest.approx(e_equiv), 230.0)
    np.testing.assert_allclose(exact.predict_radius_mm(X), radii, rtol=1e-9)
    np.testing.assert_array_equal(fitted.predict(X)[:, 0], radii)


@pytest.mark.parametrize(
    ("whisker_arg", "exc", "match"),
    [
        (None, ValueError, "whisker is required"),
        ({"length_mm": 185.0}, ValueError, "missing"),
        ("{not json", ValueError, "JSON"),
        (42, TypeError, "whisker"),
    ],
)
def test_static_beam_bad_whisker(whisker_arg, exc, match, trials) -> None:
    X, y = trials
    with pytest.raises(exc, match=match):
        StaticBeamClassifier(whisker=whisker_arg).fit(X, y)


def test_static_beam_bad_grid(whisker, trials) -> None:
    X, y = trials
    est = StaticBeamClassifier(whisker=whisker, fit_parameters=True, param_grid={"E": [1.0]})
    with pytest.raises(ValueError, match="unknown key"):
        est.fit(X, y)


# --- templates (4.3.2, 4.3.3) -------------------------------------------------------------
def test_sse_matrix_matches_brute_force() -> None:
    rng = np.random.default_rng(0)
    F, T = rng.normal(size=(7, 5)), rng.normal(size=(6, 5))
    cls = np.array([2, 0, 1, 0, 2, 1])
    got = nearest_template_scores(F, T, cls, 3, chunk_size=2)
    sse = ((F[:, None, :] - T[None, :, :]) ** 2).sum(-1)
    want = np.stack([sse[:, cls == k].min(axis=1) for k in range(3)], axis=1)
    np.testing.assert_allclose(got, want, atol=1e-10)


@pytest.mark.parametrize("templates", ["all", "mean"])
def test_time_template_recovers_shifted_copy(templates: str, trials) -> None:
    X, y = trials
    est = TimeTemplateClassifier(templates=templates).fit(X, y)
    shifted = np.roll(X, 2, axis=-1) + 0.001  # 2 ms later, small offset
    np.testing.assert_array_equal(est.predict(shifted), y)


def test_time_template_mean_templates_are_class_means(trials) -> None:
    X, y = trials
    est = TimeTemplateClassifier(templates="mean", cutoff_hz=None).fit(X, y)
    k = 3
    members = np.all(y == est.classes_[k], axis=1)
    want = X[members].reshape(members.sum(), -1).mean(axis=0) - est.center_
    np.testing.assert_allclose(est.templates_[k], want, atol=1e-12)


def test_frequency_templates_ignore_phase() -> None:
    rng = np.random.default_rng(1)
    n_t, freqs = 400, np.array([10.0, 25.0, 40.0])
    t = np.arange(n_t) / FS

    def make(phases):
        return np.stack(
            [2.5 + np.sin(2 * np.pi * f * t + p) for f, p in zip(freqs, phases, strict=True)]
        )

    X = np.concatenate([make(rng.uniform(0, 6.3, 3)) for _ in range(2)])
    y = np.tile(freqs, 2)
    est = FrequencyTemplateClassifier(sample_rate_hz=FS, cutoff_hz=None).fit(X, y)
    assert est.n_bins_ == n_t // 2 + 1
    Xt = make(rng.uniform(0, 6.3, 3))  # new phases
    np.testing.assert_array_equal(est.predict(Xt), freqs)
    # keeping only the bins up to 30 Hz
    low = FrequencyTemplateClassifier(sample_rate_hz=FS, max_frequency_hz=30.0).fit(X, y)
    assert low.n_bins_ == int(30.0 * n_t / FS) + 1


# --- features (4.3.4) ---------------------------------------------------------------------
def test_feature_regression_recovers_a_known_polynomial() -> None:
    amps = np.linspace(0.2, 1.5, 6)
    widths = np.arange(20, 80, 10)  # samples above threshold
    n_t = 301
    X, f = [], []
    for a in amps:
        for w in widths:
            x = np.full(n_t, 2.5)
            x[150 - w // 2 : 150 - w // 2 + w] += a
            X.append(x)
            f.append((a, w / FS))
    X, f = np.asarray(X), np.asarray(f)
    # Targets from a known degree-2 polynomial in (f1 [V], f2 [s]).
    target_a = 100.0 + 40.0 * f[:, 0] - 300.0 * f[:, 1] + 500.0 * f[:, 0] * f[:, 1]
    target_b = 20.0 + 10.0 * f[:, 0] ** 2 + 2000.0 * f[:, 1]
    y = np.column_stack([target_a, target_b])
    est = FeatureRegressionClassifier(sample_rate_hz=FS, degree=2).fit(X, y)
    np.testing.assert_allclose(est.predict_targets(X), y, rtol=1e-9)
    np.testing.assert_array_equal(est.predict(X), y)
    assert est.coef_.shape == (2, len(polynomial_powers(2))) == (2, 6)


def test_polynomial_powers_degree_five() -> None:
    p = polynomial_powers(5)
    assert len(p) == 21 and p.sum(axis=1).max() == 5
    assert len({tuple(r) for r in p}) == 21


def test_feature_rounds_to_nearest_class_per_target(trials) -> None:
    X, y = trials
    est = FeatureRegressionClassifier(degree=3).fit(X, y)
    est_cont = est.predict_targets(X)
    pred = est.predict(X)
    # on a full grid the nearest joint class is each target's nearest value
    for k in range(2):
        vals = np.unique(y[:, k])
        nearest = vals[np.argmin(np.abs(est_cont[:, k, None] - vals[None, :]), axis=1)]
        np.testing.assert_array_equal(pred[:, k], nearest)


# --- stationary naive Bayes (4.3.5) -------------------------------------------------------
@pytest.mark.parametrize("signal", ["raw", "velocity"])
def test_naive_bayes_posterior_is_sum_of_sample_log_likelihoods(signal: str, trials) -> None:
    from vibrissa.signal import velocity

    X, y = trials
    est = StationaryNaiveBayes(signal=signal, n_bins=30, smoothing_sigma=1.5).fit(X, y)
    Xt = X[:5] + 0.003
    S = Xt if signal == "raw" else velocity(Xt, FS, sigma_samples=3.0)
    brute = np.zeros((len(Xt), len(est.classes_)))
    for i in range(len(Xt)):
        for c in range(S.shape[1]):
            edges = est.bin_edges_[c]
            b = np.clip(np.digitize(S[i, c], edges[1:-1]), 0, len(edges) - 2)
            for k in range(len(est.classes_)):
                brute[i, k] += est.log_likelihood_[k, c, b].sum()
    np.testing.assert_allclose(est.predict_proba(Xt), softmax(brute, axis=1), atol=1e-12)
    np.testing.assert_array_equal(est.predict(Xt), est.classes_[np.argmax(brute, axis=1)])


def test_naive_bayes_likelihoods_are_normalised_histograms(trials) -> None:
    X, y = trials
    est = StationaryNaiveBayes(
        signal="raw", n_bins=10, value_range=None, smoothing_sigma=0.0, likelihood_floor=1e-300
    ).fit(X, y)
    k = 2
    members = np.all(y == est.classes_[k], axis=1)
    hist, _ = np.histogram(X[members, 0].ravel(), bins=est.bin_edges_[0])
    want = np.log(np.maximum(hist / hist.sum(), 1e-300))
    np.testing.assert_allclose(est.log_likelihood_[k, 0], want)
    assert est.bin_edges_[0, 0] == X[:, 0].min() and est.bin_edges_[0, -1] == X[:, 0].max()


def test_naive_bayes_fixed_value_range_and_bad_parameters(trials) -> None:
    X, y = trials
    est = StationaryNaiveBayes(signal="raw", value_range=(0.0, 5.0), n_bins=501).fit(X, y)
    np.testing.assert_allclose(est.bin_edges_[:, [0, -1]], [[0.0, 5.0], [0.0, 5.0]])
    assert est.score(X, y) > 0.5
    for params, match in [
        ({"signal": "acc"}, "signal"),
        ({"n_bins": 0}, "n_bins"),
        ({"value_range": (1.0, 1.0)}, "value_range"),
        ({"smoothing_sigma": -1.0}, "smoothing_sigma"),
        ({"likelihood_floor": 0.0}, "likelihood_floor"),
    ]:
        with pytest.raises(ValueError, match=match):
            StationaryNaiveBayes(**params).fit(X, y)


def test_template_bad_parameters(trials) -> None:
    X, y = trials
    for est, match in [
        (TimeTemplateClassifier(templates="median"), "templates"),
        (TimeTemplateClassifier(cutoff_hz=800.0), "cutoff_hz"),
        (TimeTemplateClassifier(chunk_size=0), "chunk_size"),
        (FrequencyTemplateClassifier(max_frequency_hz=-1.0), "max_frequency_hz"),
        (FeatureRegressionClassifier(degree=-1), "degree"),
        (FeatureRegressionClassifier(channel=5), "channel"),
    ]:
        with pytest.raises(ValueError, match=match):
            est.fit(X, y)
