"""The registry-driven runs predict exactly what the pre-refactor code predicted.

``pinned_predictions.json`` holds every classifier's test-set predictions on the quick
grids (seed 0), recorded before the experiments moved into the registry; the same seed
must give the same predictions (and the same sequential-evidence curve).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

PINS = json.loads((Path(__file__).with_name("pinned_predictions.json")).read_text())


@pytest.mark.parametrize("name", ["radial-distance", "angle-texture"])
def test_same_predictions_as_before_the_refactor(quick_runs, name):
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
