"""The evaluation code predicts exactly what it predicted when the pins were recorded.

``pinned_predictions.json`` holds every classifier's test-set predictions on the quick
grids (seed 0): first recorded before the experiments moved into the registry (issue
12), re-recorded when the physics changed (issue 14: linear free flight and long steps
alter the simulated signals slightly). Refactors of the classifiers, protocols and
pipeline must give the same predictions (and the same sequential-evidence curve);
``scripts/check_pinned_predictions.py --record`` re-records them after a deliberate
change of the physics.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

PINS = json.loads((Path(__file__).with_name("pinned_predictions.json")).read_text())


@pytest.mark.parametrize("name", ["radial-distance", "angle-texture"])
def test_same_predictions_as_when_pinned(quick_runs, name):
    _, res = quick_runs[name]
    want = PINS[name]
    got = res["predictions"]
    assert set(got["classifiers"]) == set(want["classifiers"])
    for clf, pred in want["classifiers"].items():
        assert got["classifiers"][clf] == pred, clf
    truth = {k: v for k, v in want.items() if k not in ("classifiers", "dataset", "sequential")}
    for k, v in truth.items():
        assert got[k] == v, k
    if "sequential" in want:
        assert res["sequential"] == want["sequential"]
