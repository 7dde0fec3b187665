"""MiniRocket's compiled features equal the NumPy code they replaced, trial by trial."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.special import log_softmax

from vibrissa.classify import MiniRocketClassifier
from vibrissa.classify._rocket import (
    _conv_stack,
    _decision_values,
    _log_softmax_rows,
    _pool,
    minirocket_kernels,
)


def reference_ppv(model: MiniRocketClassifier, Z: np.ndarray) -> np.ndarray:
    """The NumPy ``_ppv`` the kernel replaced: trials in chunks, kernels and dilations looped."""
    K = minirocket_kernels()
    n, c, _ = Z.shape
    nb = model.biases_.shape[-1]
    out = np.empty((n, len(model.dilations_), len(K), c, nb), dtype=np.float32)
    for s in range(0, n, int(model.chunk_size)):
        z = Z[s : s + int(model.chunk_size)]
        for di, d in enumerate(model.dilations_):
            G, A = _conv_stack(z, int(d))
            L = A.shape[-1]
            pairs = {}
            for ki, (a, b, cc) in enumerate(K):
                if (a, b) not in pairs:
                    pairs = {(a, b): A + G[a] + G[b]}
                C = pairs[(a, b)] + G[cc]
                bias = model.biases_[di, ki]  # (c, nb)
                out[s : s + len(z), di, ki] = (
                    np.count_nonzero(C[..., None, :] > bias[None, :, :, None], axis=-1) / L
                )
    return out.reshape(n, -1)


def _trials(rng: np.random.Generator, n: int, c: int, t: int, integer: bool) -> np.ndarray:
    if integer:  # small integers: exact ties between outputs and biases
        return rng.integers(-3, 4, size=(n, c, t)).astype(float)
    return rng.standard_normal((n, c, t)).cumsum(axis=-1) * rng.choice([1e-3, 1.0, 1e3])


def _fitted(X: np.ndarray, seed: int, **params) -> MiniRocketClassifier:
    y = np.arange(len(X)) % 3
    return MiniRocketClassifier(random_state=seed, **params).fit(X, y)


@pytest.mark.parametrize(
    ("c", "t", "params", "integer"),
    [
        (2, 1000, {}, False),  # the default: 4 kHz trials pooled by 8
        (2, 1000, {}, True),
        (3, 200, {"pool": 2, "n_dilations": 8, "n_biases": 3, "chunk_size": 5}, False),
        (1, 40, {"pool": 8}, False),  # pool reduced to 4 for a short trial
        (1, 5, {"pool": 1}, True),  # zero-padded to the 9 taps
    ],
)
def test_features_equal_reference_bit_for_bit(c, t, params, integer) -> None:
    rng = np.random.default_rng(t + c)
    X = _trials(rng, 24, c, t, integer)
    model = _fitted(X, 1, **params)
    Xt = _trials(rng, 17, c, t, integer)
    Z = _pool(Xt, model.pool_)
    got = model._ppv(Z)
    assert got.dtype == np.float32
    assert np.array_equal(got, reference_ppv(model, Z))
    # the standardised features (transform) from the reference PPV, as before
    ref = (reference_ppv(model, Z) - model.feature_mean_) / model.feature_scale_
    assert np.array_equal(model.transform(Xt), ref)


@settings(max_examples=20, deadline=None)
@given(
    seed=st.integers(0, 2**16),
    c=st.integers(1, 3),
    t=st.integers(5, 300),
    pool=st.integers(1, 8),
    n_biases=st.integers(1, 3),
    integer=st.booleans(),
)
def test_single_trial_features_equal_batch_and_reference(
    seed, c, t, pool, n_biases, integer
) -> None:
    rng = np.random.default_rng(seed)
    model = _fitted(_trials(rng, 9, c, t, integer), seed, pool=pool, n_biases=n_biases)
    Xt = _trials(rng, 7, c, t, integer)
    batch = model.transform(Xt)
    Z = _pool(Xt, model.pool_)
    assert np.array_equal(model._ppv(Z), reference_ppv(model, Z))
    for i in range(len(Xt)):
        # a contact's features do not depend on the other trials of the call
        assert np.array_equal(model.transform(Xt[i : i + 1]), batch[i : i + 1])


def test_single_trial_predictions_agree_with_batch() -> None:
    rng = np.random.default_rng(5)
    X = _trials(rng, 60, 2, 1000, False)
    y = np.column_stack([np.arange(60) % 3, (np.arange(60) // 3) % 2, np.arange(60) % 4])
    model = MiniRocketClassifier(sample_rate_hz=4000.0).fit(X, y)
    Xt = _trials(rng, 12, 2, 1000, False)
    batch = model.predict_proba(Xt)
    single = np.concatenate([model.predict_proba(Xt[i : i + 1]) for i in range(len(Xt))])
    # the same features; the logistic heads' coefficients are float32 (fitted on float32
    # features) but the decision values are computed in float64, so BLAS's
    # matrix-vector and matrix-matrix products differ only in float64's last bits
    # (in float32 they differed by 2.7e-7 on an AMD EPYC: sklearn's subset check failed)
    np.testing.assert_allclose(single, batch, rtol=1e-12, atol=1e-15)
    assert all(h.coef_.dtype == np.float32 for h in model.heads_)
    assert np.array_equal(model.classes_[single.argmax(1)], model.predict(Xt))


@pytest.mark.parametrize("head", ["logistic", "ridge"])
@pytest.mark.parametrize("n_classes", [2, 4])
def test_decision_values_are_scikit_learns_in_float64(head, n_classes) -> None:
    rng = np.random.default_rng(n_classes)
    X = _trials(rng, 30, 2, 120, False)
    model = MiniRocketClassifier(pool=2, n_dilations=3, head=head).fit(X, np.arange(30) % n_classes)
    F = model.transform(_trials(rng, 9, 2, 120, False))
    (h,) = model.heads_
    for rows in (F, F[:1]):
        expect = h.decision_function(rows.astype(np.float64))
        got = _decision_values(h, rows)
        assert got.dtype == np.float64
        assert got.shape == expect.shape and np.array_equal(got, expect)
        # within float32 rounding of scikit-learn's own float32 product
        np.testing.assert_allclose(got, h.decision_function(rows), rtol=1e-4, atol=1e-5)
    # a trial's values do not depend on the batch it came in
    np.testing.assert_allclose(_decision_values(h, F[:1]), _decision_values(h, F)[:1], rtol=1e-12)


@pytest.mark.parametrize("head", ["logistic", "ridge"])
def test_probabilities_equal_reference_path(head, monkeypatch) -> None:
    rng = np.random.default_rng(11)
    X = _trials(rng, 40, 2, 1000, False)
    y = np.column_stack([np.arange(40) % 3, (np.arange(40) // 3) % 2, np.arange(40) % 4])
    model = MiniRocketClassifier(head=head, sample_rate_hz=4000.0).fit(X, y)
    Xt = _trials(rng, 6, 2, 1000, False)
    got = [model.predict_proba(Xt), model.predict_proba(Xt[2:3]), model.predict(Xt)]
    # the path before the compiled features: NumPy PPV, scikit-learn's decision_function
    monkeypatch.setattr(model, "_ppv", lambda Z: reference_ppv(model, Z))
    monkeypatch.setattr(
        "vibrissa.classify._rocket._decision_values",
        lambda h, F: h.decision_function(F.astype(np.float64)),
    )
    monkeypatch.setattr(
        "vibrissa.classify._rocket._log_softmax_rows", lambda d: log_softmax(d, axis=1)
    )
    expect = [model.predict_proba(Xt), model.predict_proba(Xt[2:3]), model.predict(Xt)]
    for a, b in zip(got, expect, strict=True):
        assert np.array_equal(a, b)


@settings(max_examples=60, deadline=None)
@given(
    arrays(
        np.float64,
        st.tuples(st.integers(1, 5), st.integers(1, 6)),
        elements=st.one_of(
            st.floats(-1e3, 1e3), st.sampled_from([np.inf, -np.inf, 0.0, 745.0, -745.0])
        ),
    )
)
def test_log_softmax_rows_equals_scipy(x) -> None:
    with np.errstate(invalid="ignore", over="ignore"):
        expect = log_softmax(x, axis=1)
        got = _log_softmax_rows(x.copy())
    assert np.array_equal(got, expect, equal_nan=True)
