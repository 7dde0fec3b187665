"""The static beam with the thesis author's oracle protraction angle (issue 30, item 3)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.classify import StaticBeamClassifier
from vibrissa.classify._static_beam import (
    beam_radius_at_angle_mm,
    oracle_protraction_angle_rad,
    static_beam_radius_mm,
)

E_TRUE_GPA, L_TRUE_MM = 1.7, 205.0


def _beam_trials(whisker, radii, speeds, noise, seed):
    """Peak deflections of eq. 4.1 with each trial's own angle (speed x 0.3 s / r)."""
    rng = np.random.default_rng(seed)
    r_mm, v = (a.ravel() for a in np.meshgrid(radii, speeds, indexing="ij"))
    theta = v * 0.3 / r_mm
    c = 3.0 * E_TRUE_GPA * 1e9 * np.pi * (whisker["base_radius_mm"] * 1e-3) ** 4 / 4.0
    L, r = L_TRUE_MM * 1e-3, r_mm * 1e-3
    moment = c * theta * (L - r) / (r * L) * (1.0 + noise * rng.standard_normal(r.size))
    k_f, gain = whisker["follicle_stiffness_nm_per_rad"], whisker["hall_gain_v"]
    X = np.full((r.size, 1, 40), 2.5)
    X[:, 0, 20] += gain * np.tan(np.abs(moment) / k_f)
    return X, np.column_stack([r_mm, v])


class ExhaustiveOracleBeam(StaticBeamClassifier):
    """The oracle-angle grid search with every point evaluated directly."""

    def _oracle_grid_errors(self, kappa, lengths_mm, u, r_true):
        return np.column_stack(
            [self._oracle_snapped_errors(kappa, L, u, r_true) for L in lengths_mm]
        )


@settings(max_examples=60, deadline=None)
@given(
    moment=st.floats(1e-6, 1e-2),
    speed=st.floats(10.0, 300.0),
    e_gpa=st.floats(0.5, 3.0),
    rb=st.floats(0.5, 1.5),
    length=st.floats(150.0, 250.0),
)
def test_oracle_angle_at_the_fixed_angle_root_returns_that_root(
    moment, speed, e_gpa, rb, length
) -> None:
    # theta = d / r at the root r of the joint (fixed-speed) solution gives r back
    d = speed * 0.3
    r = float(static_beam_radius_mm(np.array([moment]), d, e_gpa, rb, length)[0])
    theta = oracle_protraction_angle_rad(speed, r, 0.3)
    back = float(beam_radius_at_angle_mm(moment, theta, e_gpa, rb, length))
    assert back == pytest.approx(r, rel=1e-9)
    assert 0 < back <= length


def test_oracle_angle_is_speed_times_latency_over_radius_and_checks_input() -> None:
    got = oracle_protraction_angle_rad([36.0, 216.0], [80.0, 180.0], 0.3)
    assert np.allclose(got, [36.0 * 0.3 / 80.0, 216.0 * 0.3 / 180.0])
    with pytest.raises(ValueError, match="speed_mm_s"):
        oracle_protraction_angle_rad([0.0], [80.0])
    with pytest.raises(ValueError, match="radius_mm"):
        oracle_protraction_angle_rad([36.0], [np.nan])
    with pytest.raises(ValueError, match="latency_s"):
        oracle_protraction_angle_rad([36.0], [80.0], latency_s=-1.0)


def test_oracle_angle_recovers_noiseless_radii_that_a_fixed_speed_misses(whisker) -> None:
    radii, speeds = np.arange(80.0, 181.0, 5.0), np.array([36.0, 126.0, 216.0])
    X, y = _beam_trials(whisker, radii, speeds, noise=0.0, seed=0)
    grid = {"youngs_modulus_gpa": [E_TRUE_GPA], "length_mm": [L_TRUE_MM]}
    oracle = StaticBeamClassifier(
        whisker=whisker, fit_parameters=True, param_grid=grid, angle="oracle"
    ).fit(X, y)
    assert oracle.youngs_modulus_gpa_ == E_TRUE_GPA and oracle.length_mm_ == L_TRUE_MM
    assert np.isnan(oracle.protraction_mm_)
    pred = oracle.predict_with_oracle_angle(X, y[:, 1], y[:, 0])
    assert pred.shape == y.shape and np.all(np.isnan(pred[:, 1]))
    assert np.array_equal(pred[:, 0], y[:, 0])
    assert oracle.training_error_mm_ == 0.0
    # one assumed speed cannot: its errors grow away from the median speed
    fixed = StaticBeamClassifier(whisker=whisker, fit_parameters=True, param_grid=grid).fit(X, y)
    assert np.mean(np.abs(fixed.predict(X)[:, 0] - y[:, 0])) > 5.0
    # the oracle method also works on a fixed-speed fit (its parameters, the true angle)
    assert np.array_equal(fixed.predict_with_oracle_angle(X, y[:, 1], y[:, 0])[:, 0], y[:, 0])


def test_oracle_mode_refuses_the_methods_that_have_no_true_labels(whisker) -> None:
    X, y = _beam_trials(whisker, np.arange(80.0, 181.0, 20.0), np.array([72.0, 144.0]), 0.0, 1)
    clf = StaticBeamClassifier(whisker=whisker, angle="oracle").fit(X, y)
    for call in (clf.predict, clf.predict_proba, clf.predict_radius_mm):
        with pytest.raises(ValueError, match="predict_with_oracle_angle"):
            call(X)
    with pytest.raises(ValueError, match="speed_mm_s must have shape"):
        clf.predict_with_oracle_angle(X, y[:3, 1], y[:, 0])
    with pytest.raises(ValueError, match="speed column"):
        StaticBeamClassifier(whisker=whisker, angle="oracle").fit(X, y[:, 0])
    with pytest.raises(ValueError, match="angle must be one of"):
        StaticBeamClassifier(whisker=whisker, angle="true").fit(X, y)


@pytest.mark.parametrize("n_rep", [1, 4])
def test_oracle_grid_search_equals_exhaustive_search(whisker, n_rep) -> None:
    radii = np.arange(80.0, 181.0, 4.0) + 0.3
    speeds = np.array([36.0, 90.0, 162.0, 216.0])
    X, y = _beam_trials(whisker, np.repeat(radii, n_rep), speeds, noise=0.05, seed=n_rep)
    kw = {"whisker": whisker, "fit_parameters": True, "angle": "oracle"}
    fast = StaticBeamClassifier(**kw).fit(X, y)
    slow = ExhaustiveOracleBeam(**kw).fit(X, y)
    for attr in (
        "youngs_modulus_gpa_",
        "base_radius_mm_",
        "length_mm_",
        "moment_scale_",
        "training_error_mm_",
    ):
        assert getattr(fast, attr) == getattr(slow, attr), attr
    assert fast.training_error_mm_ > 0
    same = fast.predict_with_oracle_angle(X, y[:, 1], y[:, 0])
    assert np.array_equal(same, slow.predict_with_oracle_angle(X, y[:, 1], y[:, 0]), equal_nan=True)


def test_default_angle_leaves_the_fixed_speed_fit_unchanged(whisker) -> None:
    X, y = _beam_trials(whisker, np.arange(80.0, 181.0, 5.0), np.array([36.0, 216.0]), 0.05, 2)
    a = StaticBeamClassifier(whisker=whisker, fit_parameters=True).fit(X, y)
    b = StaticBeamClassifier(whisker=whisker, fit_parameters=True, angle="fixed_speed").fit(X, y)
    assert a.get_params()["angle"] == "fixed_speed"
    assert np.array_equal(a.predict(X), b.predict(X), equal_nan=True)
    assert a.protraction_mm_ == pytest.approx(126.0 * 0.3)
