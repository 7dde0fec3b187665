"""Tests of scripts/compare_results.py: two results trees compared key for key."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "compare_results.py"
spec = importlib.util.spec_from_file_location("compare_results", SCRIPT)
compare_results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_results)


def _tree(root: Path, results: dict) -> Path:
    (root / "radial-distance").mkdir(parents=True)
    (root / "radial-distance" / "results.json").write_text(json.dumps(results))
    return root


RESULTS = {
    "meta": {"wall_seconds": {"total": 3.0}, "seed": 0, "command": "vibrissa x"},
    "classifiers": {
        "template": {"radius_mm": {"mean": 0.4, "std": 4.9}, "fit_seconds": 1.0, "seconds": 2.0}
    },
}


def test_equal_results_with_other_timings_compare_equal(tmp_path):
    other = json.loads(json.dumps(RESULTS))
    other["meta"]["wall_seconds"]["total"] = 9.0
    other["meta"]["command"] = "vibrissa y"
    other["classifiers"]["template"]["fit_seconds"] = 7.0
    other["classifiers"]["template"]["seconds"] = 8.0
    a, b = _tree(tmp_path / "a", RESULTS), _tree(tmp_path / "b", other)
    assert compare_results.compare_trees(a, b) == (1, [])
    assert compare_results.main([str(a), str(b)]) == 0


def test_a_changed_number_a_missing_key_and_a_missing_file_are_named(tmp_path):
    other = json.loads(json.dumps(RESULTS))
    other["classifiers"]["template"]["radius_mm"]["std"] = 5.0
    other["meta"]["extra"] = 1
    a, b = _tree(tmp_path / "a", RESULTS), _tree(tmp_path / "b", other)
    (a / "scratchbot").mkdir()
    (a / "scratchbot" / "results.json").write_text("{}")
    n, lines = compare_results.compare_trees(a, b)
    assert n == 1
    assert "scratchbot/results.json: missing after" in lines
    assert any(".classifiers.template.radius_mm.std: 4.9 != 5.0" in x for x in lines)
    assert any(".meta.extra: only after" in x for x in lines)
    assert compare_results.main([str(a), str(b)]) == 1
    assert compare_results.compare_trees(a, b, rtol=0.05)[1] == [x for x in lines if "std" not in x]
