"""Tests of vibrissa.framework.reports: exact JSON round trips, marginals and intervals."""

from __future__ import annotations

import json

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.framework.reports import (
    ContactReport,
    SurfaceEvidence,
    WhatEstimate,
    WhereEstimate,
    marginal,
    marginal_interval,
)

finite = st.floats(-1e6, 1e6, allow_nan=False)
prob = st.floats(0, 1)


@st.composite
def reports(draw):
    where = draw(
        st.none()
        | st.builds(
            WhereEstimate,
            finite,
            st.tuples(finite, finite),
            st.none() | finite,
            st.none() | st.tuples(finite, finite),
            prob,
        )
    )
    what = draw(
        st.none()
        | st.builds(
            WhatEstimate,
            st.dictionaries(finite, prob, max_size=4),
            st.dictionaries(st.sampled_from(["aluminium", "p80"]), prob),
        )
    )
    evidence = draw(
        st.none()
        | st.builds(
            SurfaceEvidence,
            st.integers(0, 99),
            st.integers(1, 50),
            st.lists(st.integers(0, 23), max_size=5).map(tuple),
            finite,
            st.sampled_from(["aluminium", "p600"]),
            prob,
            st.booleans(),
            st.dictionaries(finite, prob, max_size=4),
            st.dictionaries(st.sampled_from(["p180", "p80"]), prob),
        )
    )
    decision = draw(
        st.none()
        | st.fixed_dictionaries(
            {
                "angle_deg": finite,
                "texture": st.just("p80"),
                "probability": prob,
                "n_contacts": st.integers(1, 9),
                "whiskers": st.lists(st.integers(0, 23), max_size=3),
            }
        )
    )
    return ContactReport(
        draw(st.integers(0, 23)),
        draw(finite),
        draw(finite),
        draw(finite),
        draw(st.booleans()),
        draw(prob),
        where,
        what,
        evidence,
        draw(st.integers(0, 99)),
        decision,
        draw(st.booleans()),
    )


@settings(max_examples=80, deadline=None)
@given(reports())
def test_round_trip_exact_through_json(report):
    d = report.to_dict()
    text = json.dumps(d, allow_nan=False)
    back = ContactReport.from_dict(json.loads(text))
    assert back == report
    assert back.to_dict() == d


def test_marginal_and_interval():
    values = np.array([60.0, 20.0, 40.0, 60.0])
    proba = np.array([0.25, 0.1, 0.4, 0.25])
    v, m = marginal(values, proba)
    np.testing.assert_array_equal(v, [20.0, 40.0, 60.0])
    np.testing.assert_allclose(m, [0.1, 0.4, 0.5])
    mean, lo, hi = marginal_interval(v, m)
    assert mean == np.dot(v, m) and (lo, hi) == (20.0, 60.0)
    mean, lo, hi = marginal_interval(v, np.array([0.0, 1.0, 0.0]))
    assert (mean, lo, hi) == (40.0, 40.0, 40.0)
    # the 5 % point is the first value whose CDF reaches 0.05
    assert marginal_interval(v, np.array([0.04, 0.92, 0.04]))[1:] == (40.0, 40.0)
    assert marginal_interval(v, np.array([0.05, 0.85, 0.1]))[1:] == (20.0, 60.0)
