"""The classifiers' numba kernels give the numbers of the code they replaced, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from vibrissa.classify import StaticBeamClassifier, thesis_parameter_grid
from vibrissa.classify._kernels import l1_distances
from vibrissa.classify._template import nearest_template_l1


@pytest.mark.parametrize(("n", "m", "d"), [(1, 1, 1), (7, 300, 13), (517, 260, 64)])
def test_l1_distances_equal_cdist_bit_for_bit(n, m, d) -> None:
    rng = np.random.default_rng(n + m + d)
    F = rng.standard_normal((n, d)) * rng.choice([1e-3, 1.0, 1e3], size=(n, 1))
    T = rng.standard_normal((m, d))
    out = np.empty((n, m))
    l1_distances(F, np.ascontiguousarray(T.T), out)
    assert np.array_equal(out, cdist(F, T, metric="cityblock"))


def test_nearest_template_l1_equals_cdist_and_class_minimum() -> None:
    rng = np.random.default_rng(3)
    F, T = rng.standard_normal((600, 40)), rng.standard_normal((90, 40))
    t_class = rng.permutation(np.arange(90) % 30)  # three templates per class
    got = nearest_template_l1(F, T, t_class, 30, chunk_size=256)
    d = cdist(F, T, metric="cityblock")
    expect = np.stack([d[:, t_class == c].min(axis=1) for c in range(30)], axis=1)
    assert np.array_equal(got, expect)
    one = nearest_template_l1(F, T, np.arange(90), 90)
    assert np.array_equal(one, d)


class ExhaustiveBeam(StaticBeamClassifier):
    """The static beam with every grid point evaluated by the reference computation."""

    def _grid_errors(self, kappa, lengths_mm, moment, r_true):
        return np.column_stack([self._snapped_errors(kappa, L, moment, r_true) for L in lengths_mm])


def _beam_trials(whisker, radii, n_rep, seed):
    """Peak deflections of eq. 4.1 for another E and length (126 mm/s x 0.3 s), 5 % noise."""
    rng = np.random.default_rng(seed)
    r = np.repeat(np.asarray(radii, dtype=float), n_rep) * 1e-3
    E, L, d = 1.7e9, 0.205, 126.0 * 0.3e-3
    c = 3.0 * E * np.pi * (whisker["base_radius_mm"] * 1e-3) ** 4 / 4.0
    moment = c * (d / r) * (L - r) / (r * L) * (1.0 + 0.05 * rng.standard_normal(r.size))
    k_f, gain = whisker["follicle_stiffness_nm_per_rad"], whisker["hall_gain_v"]
    X = np.full((r.size, 1, 50), 2.5)
    X[:, 0, 25] += gain * np.tan(np.abs(moment) / k_f)
    return X, np.column_stack([r * 1e3, np.full(r.size, 126.0)])


@pytest.mark.parametrize("integer", [True, False])
@pytest.mark.parametrize("n_rep", [1, 6])
def test_static_beam_grid_search_equals_exhaustive_search(whisker, integer, n_rep) -> None:
    radii = np.arange(80.0, 181.0, 4.0)
    if not integer:
        radii = radii + np.random.default_rng(1).uniform(-0.4, 0.4, radii.size)
    X, y = _beam_trials(whisker, radii, n_rep, seed=n_rep)
    kw = {"whisker": whisker, "fit_parameters": True}
    fast = StaticBeamClassifier(**kw).fit(X, y)
    slow = ExhaustiveBeam(**kw).fit(X, y)
    for attr in (
        "youngs_modulus_gpa_",
        "base_radius_mm_",
        "length_mm_",
        "moment_scale_",
        "training_error_mm_",
        "residual_std_mm_",
    ):
        assert getattr(fast, attr) == getattr(slow, attr), attr
    assert np.array_equal(fast.predict(X), slow.predict(X), equal_nan=True)


def test_static_beam_grid_errors_exact_near_the_minimum(whisker) -> None:
    X, y = _beam_trials(whisker, np.arange(80.0, 181.0, 1.0) + 0.3, 3, seed=5)
    clf = StaticBeamClassifier(whisker=whisker).fit(X, y)
    moment = clf._moment(X)
    r_true = y[:, 0]
    grid = thesis_parameter_grid()
    kappa = np.sort(np.random.default_rng(0).uniform(1e1, 1e4, 200))
    fast = clf._grid_errors(kappa, grid["length_mm"], moment, r_true)
    slow = ExhaustiveBeam._grid_errors(clf, kappa, grid["length_mm"], moment, r_true)
    near = np.isfinite(fast)
    # every point within the tie tolerance of the minimum is evaluated exactly
    assert near[slow <= slow.min() + 1e-9].all()
    assert np.array_equal(fast[near], slow[near]) and fast.min() == slow.min()


def test_naive_bayes_counts_equal_the_bincount_of_the_bin_indices() -> None:
    from vibrissa.classify import StationaryNaiveBayes

    rng = np.random.default_rng(4)
    X = 2.5 + rng.standard_normal((30, 2, 200)) * np.array([0.2, 2.0])[None, :, None]
    y = np.repeat([1.0, 2.0, 3.0], 10)
    nb = StationaryNaiveBayes(signal="raw", n_bins=37, value_range=(2.0, 3.0)).fit(X, y)
    S = X.copy()
    S[0, 0, :3] = [-1e6, 1e6, 3.0]  # far outside, and on the upper edge
    n, c, _ = S.shape
    edges = nb.bin_edges_
    idx = np.floor(
        (S - edges[:, 0][None, :, None]) / ((edges[:, -1] - edges[:, 0])[None, :, None] / 37)
    ).astype(np.intp)
    np.clip(idx, 0, 36, out=idx)
    idx += (np.arange(n * c) * 37).reshape(n, c, 1)
    expect = np.bincount(idx.ravel(), minlength=n * c * 37).reshape(n, c * 37)
    assert np.array_equal(nb._counts(S), expect)
