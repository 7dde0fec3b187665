"""FSM outcome sums and the map-error ordering over runs (issue 31)."""

from __future__ import annotations

import pytest

from vibrissa.slam.log import fsm_outcome_counts
from vibrissa.thesis.crunchbot_slam.evaluation import ordering_over_runs, sum_outcomes


def test_outcomes_are_summed_key_by_key() -> None:
    a = fsm_outcome_counts(["FWD_1", "HIT_1", "FWD_2", "HIT_2", "BACK", "TURN"])
    b = fsm_outcome_counts(["FWD_1", "HIT_1", "FWD_2", "ABORT", "BACK", "TURN"])
    total = sum_outcomes([a, b, b])
    assert total["runs"] == 3
    assert total["fwd2_ends"] == {"hit_2": 1, "abort": 2}
    assert total["abort_after"] == {"FWD_1": 0, "FWD_2": 2, "TURN": 0}
    assert total["turn"] == 3


def test_ordering_on_the_means_and_run_by_run() -> None:
    per_run = {
        "grid": {"template": [0.1, 0.3], "geometric": [0.2, 0.2], "blob": [0.3, 0.1]},
        "arena": {"template": [0.1, 0.1], "geometric": [0.2, 0.2], "blob": [0.3, 0.3]},
    }

    def err(rows: dict) -> dict:
        return {m: {"mean": sum(v) / len(v)} for m, v in rows.items()}

    grid = {**err(per_run["grid"]), "empty": 0.15, "random": 0.5}
    arena = {**err(per_run["arena"]), "empty": 0.25, "random": 0.5}
    out = ordering_over_runs(per_run, grid, arena)
    assert out["runs_template_lt_geometric_lt_blob"] == pytest.approx(0.5)
    assert out["arena"]["template_lt_geometric_lt_blob"] is True
    assert out["arena"]["order"] == ["template", "geometric", "blob"]
    assert out["beats_empty"]["grid"]["template"] == {"mean_below": False, "runs_below": 0.5}
    assert out["beats_empty"]["arena"]["blob"]["runs_below"] == 0.0
    assert out["beats_random"]["grid"]["blob"]["mean_below"] is True
    assert "arena" not in ordering_over_runs(per_run, grid, {})
