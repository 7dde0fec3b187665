"""The evaluation code predicts exactly what it predicted when the pins were recorded.

``pinned_predictions.json`` holds every classifier's test-set predictions on the quick
grids (seed 0): first recorded before the experiments moved into the registry (issue
12), re-recorded when the physics changed. Refactors of the classifiers, protocols and
pipeline must give the same predictions (and the same sequential-evidence curve).

The simulated data depend on the machine too (chapter 5's stick-slip texture contacts
turn a last-bit difference of a CPU-specific NumPy or BLAS kernel into other signals),
so each pin names the data and the machine it was made from, and
``scripts/check_pinned_predictions.py`` decides (:func:`verdict`): equal to a pin, pass;
the same data predicted otherwise, or other data on a pinned kind of machine, fail; a
kind of machine with no pin, skip, saying which (``--record`` adds its pins).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location(
    "check_pinned_predictions", ROOT / "scripts" / "check_pinned_predictions.py"
)
assert _spec is not None and _spec.loader is not None
pinning = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pinning)

PINS = json.loads(pinning.PINS.read_text())["pins"]


@pytest.mark.parametrize("name", sorted(pinning.EXPERIMENTS))
def test_same_predictions_as_when_pinned(quick_runs, name):
    _, res = quick_runs[name]
    status, why = pinning.verdict(
        PINS[name], pinning.predictions(res), pinning.data_digest(res), pinning.machine_kind()
    )
    if status == "skip":
        pytest.skip(why)
    assert status == "pass", why


def _pin(preds, data="d1", machine=None, commit="c1"):
    return {
        "recorded": {"commit": commit, "data": data, "machine": machine},
        "predictions": preds,
    }


PRED = {
    "classifiers": {"a": {"y_pred": [1, 2, 3]}, "b": {"y_pred": [0, 0, 1]}},
    "y_true": [1, 2, 3],
}
HERE = {"cpu": "here", "numpy_simd": ["X86_V3"], "blas": ["openblas Haswell"]}
THERE = {"cpu": "there", "numpy_simd": ["X86_V3", "X86_V4"], "blas": ["openblas SkylakeX"]}


def _moved(preds, clf="a", k=0):
    out = json.loads(json.dumps(preds))
    out["classifiers"][clf]["y_pred"][k] += 1
    return out


def test_verdict_passes_an_exact_match_of_any_pin():
    pins = [_pin(_moved(PRED), "d0", THERE), _pin(PRED, "d1", HERE)]
    assert pinning.verdict(pins, PRED, "d9", HERE)[0] == "pass"
    assert pinning.verdict(pins, PRED, "d9", {"cpu": "new"} | HERE)[0] == "pass"


def test_verdict_fails_other_predictions_from_pinned_data():
    status, why = pinning.verdict([_pin(PRED, "d1", THERE)], _moved(PRED, "b", 2), "d1", HERE)
    assert status == "fail" and "evaluation changed" in why and "b (1 predictions differ)" in why


def test_verdict_fails_other_data_on_a_pinned_kind_of_machine():
    status, why = pinning.verdict([_pin(PRED, "d1", HERE)], _moved(PRED), "d2", HERE)
    assert status == "fail" and "--physics-changed" in why


def test_verdict_skips_a_kind_of_machine_without_pins():
    status, why = pinning.verdict([_pin(PRED, "d1", THERE)], _moved(PRED), "d2", HERE)
    assert status == "skip" and "here" in why and "there" in why and "d2" in why


def test_verdict_skips_when_only_unnamed_machines_are_pinned():
    status, why = pinning.verdict([_pin(PRED, None, None)], _moved(PRED), "d2", HERE)
    assert status == "skip" and "an unnamed machine (at c1)" in why


def test_verdict_names_a_new_or_missing_key():
    extra = PRED | {"sequential": [0.5]}
    status, why = pinning.verdict([_pin(PRED, "d1", HERE)], extra, "d1", HERE)
    assert status == "fail" and "sequential" in why


def test_machine_kind_and_data_digest_of_a_quick_run(quick_runs):
    kind = pinning.machine_kind()
    assert set(kind) == {"cpu", "numpy_simd", "blas"} and kind["cpu"]
    _, res = quick_runs["radial-distance"]
    digest = pinning.data_digest(res)
    assert len(digest) == 16 and digest == pinning.data_digest(res)
    _, other = quick_runs["angle-texture"]
    assert pinning.data_digest(other) != digest
