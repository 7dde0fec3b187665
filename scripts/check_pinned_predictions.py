"""Compare quick-grid predictions of the current checkout with the pinned ones.
Run from a checkout root with its venv: python /tmp/pin/check.py  (uses a fresh temp dir)."""
import json, sys, tempfile, pathlib
import numpy as np
pins = json.load(open(pathlib.Path("tests/reproduce/pinned_predictions.json")))
try:
    from vibrissa.evaluate.reproduce import reproduce_radial_distance
    from vibrissa.evaluate.chapter5 import reproduce_angle_texture
except ImportError:
    from vibrissa.reproduce import run_experiment
    reproduce_radial_distance = lambda d, **k: run_experiment("radial-distance", d, **k)
    reproduce_angle_texture = lambda d, **k: run_experiment("angle-texture", d, **k)
d = tempfile.mkdtemp()
r4 = reproduce_radial_distance(d + "/ch4", quick=True, seed=0, n_seeds=1, figures=False)
r5 = reproduce_angle_texture(d + "/ch5", quick=True, seed=0, figures=False)
bad = 0
for name, res in (("radial-distance", r4), ("angle-texture", r5)):
    got, want = res["predictions"], pins[name]
    for k, v in want["classifiers"].items():
        g = got["classifiers"][k]
        same = json.dumps(g, sort_keys=True) == json.dumps(v, sort_keys=True)
        if not same:
            bad += 1; print("DIFF", name, k)
print("sequential", r5["sequential"] == pins["angle-texture"]["sequential"])
print("OK" if bad == 0 and r5["sequential"] == pins["angle-texture"]["sequential"] else "MISMATCH")
