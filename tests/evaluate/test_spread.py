"""Tests of the mean and spread of per-seed results."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from vibrissa.evaluate.spread import seed_spread, spread_leaf


def test_nested_results() -> None:
    seeds = [
        {"a": 1, "b": {"c": [1.0, 2.0]}, "name": "x", "ok": True},
        {"a": 3, "b": {"c": [3.0, math.nan]}, "name": "x", "ok": False},
    ]
    mean, spread = seed_spread(seeds)
    assert mean == {"a": 2.0, "b": {"c": [2.0, 2.0]}, "name": "x", "ok": True}
    assert spread["a"]["values"] == [1.0, 3.0]
    assert spread["a"]["std"] == pytest.approx(math.sqrt(2))
    assert spread["b"]["c"][1]["n"] == 1 and spread["b"]["c"][1]["values"] == [2.0, None]
    assert "name" not in spread and "ok" not in spread  # only numbers have a spread


def test_missing_everywhere_and_empty() -> None:
    leaf = spread_leaf([None, math.nan])
    assert leaf["n"] == 0 and leaf["mean"] is None and leaf["std"] is None
    with pytest.raises(ValueError, match="at least one seed"):
        seed_spread([])


@given(st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=12))
def test_leaf_agrees_with_numpy(values: list[float]) -> None:
    leaf = spread_leaf(values)
    assert leaf["mean"] == pytest.approx(np.mean(values), rel=1e-9, abs=1e-6)
    assert leaf["min"] == min(values) and leaf["max"] == max(values)
    if len(values) > 1:
        assert leaf["std"] == pytest.approx(np.std(values, ddof=1), rel=1e-6, abs=1e-6)
