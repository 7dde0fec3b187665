"""Compare the quick-grid predictions of this checkout with the pinned ones.

Usage (from the repository root, ~40 s)::

    .venv/bin/python scripts/check_pinned_predictions.py [--record]

Prints ``OK`` when both quick reproductions (seed 0; chapter 4 with one reduced-set
repeat) predict exactly what ``tests/reproduce/pinned_predictions.json`` holds, else
the classifiers that differ and how many of their test predictions changed. The test
``tests/reproduce/test_pinned_predictions.py`` checks the same.

The pins guard the evaluation code: a refactor of the classifiers, the protocols or
the pipeline must not change a single prediction. They depend on the simulated data
too, so a deliberate change of the physics re-records them with ``--record`` (which
writes the file atomically and notes the commit it was recorded at), in the same
commit as the physics change, saying so in its message.
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

from vibrissa._atomic import atomic_write_text
from vibrissa.reproduce import run_experiment

PINS = pathlib.Path("tests/reproduce/pinned_predictions.json")

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument(
    "--record", action="store_true", help="write this checkout's predictions as the new pins"
)
args = parser.parse_args()

pins = json.loads(PINS.read_text())
bad = []
new = {}
with tempfile.TemporaryDirectory() as d:
    for name, opts in (("radial-distance", {"n_seeds": 1}), ("angle-texture", {})):
        res = run_experiment(
            name, pathlib.Path(d) / name, quick=True, seed=0, figures=False, **opts
        )
        got = dict(res["predictions"])
        if "sequential" in res:
            got["sequential"] = res["sequential"]
        new[name] = got
        want = pins[name]
        for k, v in want["classifiers"].items():
            mine = res["predictions"]["classifiers"].get(k)
            if json.dumps(mine, sort_keys=True) != json.dumps(v, sort_keys=True):
                changed = "?"
                if isinstance(mine, dict) and isinstance(v, dict):
                    changed = sum(
                        sum(a != b for a, b in zip(mine[t], v[t], strict=False))
                        for t in v
                        if t in mine and isinstance(v[t], list)
                    )
                bad.append(f"{name}: {k} ({changed} predictions differ)")
        if "sequential" in want and res["sequential"] != want["sequential"]:
            bad.append(f"{name}: sequential")
if args.record:
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    new["_about"] = (
        "Every classifier's test-set predictions on the quick grids (seed 0; chapter 4 "
        f"with --n-seeds 1), recorded by scripts/check_pinned_predictions.py --record at "
        f"commit {commit} plus its working tree. Refactors of the evaluation must keep "
        "them exactly; a deliberate change of the physics re-records them."
    )
    atomic_write_text(PINS, json.dumps(new, indent=1, sort_keys=True) + "\n")
    print(f"recorded {PINS}" + ("" if not bad else " (changed: " + ", ".join(bad) + ")"))
    sys.exit(0)
print("OK" if not bad else "MISMATCH: " + ", ".join(bad))
sys.exit(1 if bad else 0)
