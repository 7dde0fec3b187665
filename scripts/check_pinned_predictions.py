"""Compare the quick-grid predictions of this checkout with the pinned ones.

Usage (from the repository root, ~40 s)::

    .venv/bin/python scripts/check_pinned_predictions.py

Prints ``OK`` when both quick reproductions (seed 0; chapter 4 with one reduced-set
repeat) predict exactly what ``tests/reproduce/pinned_predictions.json`` holds (recorded
before the issue-12 refactor), else the classifiers that differ. The test
``tests/reproduce/test_pinned_predictions.py`` checks the same.
"""

import json
import pathlib
import sys
import tempfile

from vibrissa.reproduce import run_experiment

pins = json.loads(pathlib.Path("tests/reproduce/pinned_predictions.json").read_text())
bad = []
with tempfile.TemporaryDirectory() as d:
    for name, opts in (("radial-distance", {"n_seeds": 1}), ("angle-texture", {})):
        res = run_experiment(name, pathlib.Path(d) / name, quick=True, seed=0, figures=False,
                             **opts)
        want = pins[name]
        for k, v in want["classifiers"].items():
            if json.dumps(res["predictions"]["classifiers"].get(k), sort_keys=True) != \
                    json.dumps(v, sort_keys=True):
                bad.append(f"{name}: {k}")
        if "sequential" in want and res["sequential"] != want["sequential"]:
            bad.append(f"{name}: sequential")
print("OK" if not bad else "MISMATCH: " + ", ".join(bad))
sys.exit(1 if bad else 0)
