"""The registered floor-texture experiment's sessions option and summary (thesis 6.2)."""

from __future__ import annotations

import pytest

from vibrissa.reproduce.registry import get_experiment
from vibrissa.thesis.floor_texture.experiment import QUICK_MAX_SEEDS, sessions
from vibrissa.thesis.floor_texture.report import percent_pm


def test_n_seeds_sets_the_sessions_and_quick_runs_at_most_two():
    exp = get_experiment("floor-texture")
    option = {o.name: o for o in exp.options}["n_seeds"]
    assert option.default == 5
    assert exp.protocol_for(False, 4, {"n_seeds": 5}).seeds == [4, 5, 6, 7, 8]
    assert exp.protocol_for(True, 0, {"n_seeds": 5}).n_seeds == QUICK_MAX_SEEDS == 2
    assert sessions(True, 1) == 1 and sessions(False, 7) == 7
    assert exp.protocol(True, 0).n_seeds == 1  # the listing counts one session
    with pytest.raises(ValueError, match="--n-seeds must be an integer >= 1"):
        option.check(0)


def test_the_summary_carries_the_spread():
    spread = {"mean_correct": {"clockwise": {"std": 0.05}}, "cross_condition": {}}
    results = {
        "meta": {"n_seeds": 5},
        "confusion": {},
        "mean_correct": {"clockwise": 0.7},
        "cross_condition": {"cw_on_ccw": 0.3, "ccw_on_cw": 0.9},
        "naive_bayes": {"mean_correct": {"clockwise": 0.8}},
        "spread": spread,
    }
    s = get_experiment("floor-texture").summary(results)
    assert s["n_seeds"] == 5 and s["std"]["mean_correct"]["clockwise"] == 0.05
    assert s["std"]["cross_condition"]["cw_on_ccw"] is None
    assert percent_pm(0.7, 0.05) == "70 ± 5 %" and percent_pm(0.7) == "70 %"
