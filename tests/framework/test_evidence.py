"""Tests of vibrissa.framework.evidence: contact-by-contact accumulation as accumulate_evidence."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vibrissa.classify import accumulate_evidence
from vibrissa.framework.evidence import EvidenceAccumulator, floored_log_posterior

CLASSES = np.array([[0.0, 0.0], [0.0, 3.0], [30.0, 0.0], [30.0, 3.0]])


@settings(max_examples=60, deadline=None)
@given(
    arrays(float, st.tuples(st.integers(1, 12), st.just(4)), elements=st.floats(0, 1)),
    st.floats(0.5, 0.999),
    st.sampled_from([1e-3, 1e-2, 0.1]),
)
def test_one_by_one_matches_accumulate_evidence(raw, threshold, floor):
    proba = raw + 1e-9
    proba = proba / proba.sum(axis=1, keepdims=True)
    acc = EvidenceAccumulator(CLASSES, threshold=threshold, min_probability=floor)
    for i, row in enumerate(proba):
        acc.add(row, whisker=i % 3)
        if acc.decided:
            break
    lp = floored_log_posterior(proba, floor)[None]
    decision, n_used, posterior = accumulate_evidence(lp, threshold)
    assert acc.n_contacts == n_used[0]
    np.testing.assert_allclose(acc.posterior(), posterior[0], rtol=1e-9, atol=1e-12)
    best, p = acc.best()
    assert p == acc.posterior().max()
    np.testing.assert_array_equal(best, CLASSES[np.argmax(acc.posterior())])
    assert int(np.argmax(acc.posterior())) == decision[0]
    assert acc.whiskers == {i % 3 for i in range(acc.n_contacts)}


def test_floor_keeps_one_contact_from_vetoing_a_class():
    acc = EvidenceAccumulator(CLASSES, threshold=0.99, min_probability=1e-3)
    acc.add([1.0, 0.0, 0.0, 0.0], whisker=0)  # one-hot against class 1
    for _ in range(3):
        acc.add([0.0, 1.0, 0.0, 0.0], whisker=1)
    assert acc.best()[0].tolist() == [0.0, 3.0] and acc.decided
    assert not EvidenceAccumulator(CLASSES).decided  # no contact: never decided


def test_reset_and_uniform_start():
    acc = EvidenceAccumulator(CLASSES)
    np.testing.assert_allclose(acc.posterior(), 0.25)
    acc.add([0.7, 0.1, 0.1, 0.1], whisker=4)
    acc.reset()
    assert acc.n_contacts == 0 and acc.whiskers == set()
    np.testing.assert_allclose(acc.posterior(), 0.25)


@pytest.mark.parametrize(
    ("kwargs", "row", "name"),
    [
        ({"min_probability": 0.0}, None, "min_probability"),
        ({"min_probability": 1.5}, None, "min_probability"),
        ({"threshold": 0.0}, None, "threshold"),
        ({}, [0.5, 0.5], "proba_row"),
        ({}, [0.5, np.nan, 0.0, 0.5], "proba_row"),
    ],
)
def test_bad_input_named(kwargs, row, name):
    with pytest.raises(ValueError, match=name):
        EvidenceAccumulator(CLASSES, **kwargs).add(row, 0)
