"""Compare the quick-grid predictions of this checkout with the pinned ones.

Usage (from the repository root, ~40 s)::

    .venv/bin/python scripts/check_pinned_predictions.py [--record [--physics-changed]]

Prints ``OK`` when both quick reproductions (seed 0; chapter 4 with one reduced-set
repeat) predict exactly what ``tests/reproduce/pinned_predictions.json`` holds, else
the classifiers that differ and how many of their test predictions changed. The test
``tests/reproduce/test_pinned_predictions.py`` checks the same, on the test session's
quick runs.

The pins guard the evaluation code: a refactor of the classifiers, the protocols or
the pipeline must not change a single prediction. They depend on the simulated data
too, and the data depend on the machine as well as on the physics: the texture
contacts of chapter 5 stick and slip, so a last-bit difference in NumPy's or the BLAS's
CPU-specific kernels grows into other signals (the angle-texture quick grid simulated
on an AMD EPYC changed 1-17 of every classifier's 72-216 test predictions against the
pins recorded on the Intel Xeons before; the chapter-4 grid's did not change). So each
experiment keeps a list of pins, each naming the digest of the data it was made from
(:func:`data_digest`) and the kind of machine that simulated them
(:func:`machine_kind`):

- the run matches a pin exactly: pass;
- a pin was made from the same data: the evaluation changed; fail, naming the
  classifiers;
- a pin was made on this kind of machine, from other data: the physics changed; fail,
  asking for ``--record --physics-changed`` in the commit that changed it;
- otherwise this kind of machine has no pin: the check cannot tell (skip, naming it);
  ``--record`` adds this machine's pins beside the others.

``--record`` writes atomically and notes the commit; ``--physics-changed`` drops the
pins of every other machine (they no longer describe this code's data).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import pathlib
import platform
import subprocess
import sys
import tempfile
from typing import Any

ROOT = pathlib.Path(__file__).resolve().parents[1]
PINS = ROOT / "tests" / "reproduce" / "pinned_predictions.json"
sys.path.insert(0, str(ROOT / "benchmarks"))

from _machine import machine  # noqa: E402  (the benchmarks' record of the CPU model)

#: The pinned quick runs and their options (chapter 4: one repeat of each reduced set).
EXPERIMENTS = {"radial-distance": {"n_seeds": 1}, "angle-texture": {}}


def machine_kind() -> dict[str, Any]:
    """What decides the simulated bits besides the code: CPU, NumPy's SIMD, the BLAS kernel."""
    import numpy  # noqa: F401  (loads the BLAS that threadpoolctl reports)
    import threadpoolctl

    cpu = machine()["cpu"] or platform.machine()
    try:  # NumPy's own record of the SIMD levels it dispatches to (what show_runtime prints)
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:  # pragma: no cover - NumPy 1.x
        from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    # the BLAS only: an OpenMP runtime that some other import loaded (scikit-learn's, under
    # pytest) is no property of the machine and made the same machine look like another
    blas = sorted(
        {
            f"{i.get('internal_api')} {i.get('architecture')}"
            for i in threadpoolctl.threadpool_info()
            if i.get("user_api") == "blas"
        }
    )
    simd = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    return {"cpu": cpu, "numpy_simd": simd, "blas": blas}


def data_digest(results: dict[str, Any]) -> str:
    """SHA-256 (16 hex digits) of the values of every variable of a run's dataset.

    Read from the per-variable hashes the dataset file stores beside its checksum
    (``vibrissa_checksum_parts``), values only: attributes such as the version are left
    out, so the digest changes exactly when the simulated numbers do.
    """
    import xarray as xr

    path = pathlib.Path(results["meta"]["dataset"]["path"])
    with xr.open_dataset(path) as ds:
        parts = json.loads(ds.attrs["vibrissa_checksum_parts"])
    blob = json.dumps(parts["variables"], sort_keys=True).encode()
    return hashlib.sha256(blob).hexdigest()[:16]


def predictions(results: dict[str, Any]) -> dict[str, Any]:
    """What is pinned of a run: its ``predictions`` block, and ``sequential`` if it has one."""
    got = dict(results["predictions"])
    if "sequential" in results:
        got["sequential"] = results["sequential"]
    return got


def _differences(got: dict[str, Any], want: dict[str, Any]) -> list[str]:
    """What differs between two pinned blocks: classifiers (with how many predictions), keys."""
    out = []
    for clf, pred in want["classifiers"].items():
        mine = got["classifiers"].get(clf)
        if json.dumps(mine, sort_keys=True) != json.dumps(pred, sort_keys=True):
            changed: Any = "?"
            if isinstance(mine, dict) and isinstance(pred, dict):
                changed = sum(
                    sum(a != b for a, b in zip(mine[t], pred[t], strict=False))
                    for t in pred
                    if t in mine and isinstance(pred[t], list)
                )
            out.append(f"{clf} ({changed} predictions differ)")
    out += [f"{c} (not pinned)" for c in sorted(set(got["classifiers"]) - set(want["classifiers"]))]
    for k in sorted((set(want) | set(got)) - {"classifiers"}):
        if json.dumps(got.get(k), sort_keys=True) != json.dumps(want.get(k), sort_keys=True):
            out.append(k)
    return out


def verdict(
    pins: list[dict[str, Any]], got: dict[str, Any], digest: str, machine: dict[str, Any]
) -> tuple[str, str]:
    """``("pass" | "fail" | "skip", why)`` for a run's predictions against its pins."""
    for pin in pins:
        if not _differences(got, pin["predictions"]):
            return "pass", f"equal to the pin recorded at {pin['recorded']['commit']}"
    for pin in pins:
        if pin["recorded"].get("data") == digest:
            diff = ", ".join(_differences(got, pin["predictions"]))
            return "fail", (
                f"the evaluation changed: on the data pinned at {pin['recorded']['commit']} "
                f"(digest {digest}) it now predicts otherwise: {diff}"
            )
    for pin in pins:
        if pin["recorded"].get("machine") == machine:
            return "fail", (
                f"the simulated data changed (digest {digest}, pinned "
                f"{pin['recorded'].get('data')} on this kind of machine): a deliberate change "
                "of the physics re-records the pins with scripts/check_pinned_predictions.py "
                "--record --physics-changed"
            )
    kinds = "; ".join(
        (p["recorded"].get("machine") or {}).get("cpu", "an unnamed machine")
        + f" (at {p['recorded']['commit']})"
        for p in pins
    )
    return "skip", (
        f"no pin for this kind of machine ({machine['cpu']}, NumPy SIMD up to "
        f"{(machine['numpy_simd'] or ['none'])[-1]}, {', '.join(machine['blas'])}; data digest "
        f"{digest}): pinned on {kinds}. Record its pins with "
        "scripts/check_pinned_predictions.py --record"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--record", action="store_true", help="add this machine's predictions to the pins"
    )
    parser.add_argument(
        "--physics-changed",
        action="store_true",
        help="with --record: drop every other machine's pins (the data changed)",
    )
    args = parser.parse_args(argv)
    if args.physics_changed and not args.record:
        parser.error("--physics-changed needs --record")

    from vibrissa._atomic import atomic_write_text
    from vibrissa.reproduce import run_experiment

    pins = json.loads(PINS.read_text())
    machine = machine_kind()
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=PINS.parent
    ).stdout.strip()
    dirty = subprocess.run(
        ["git", "status", "--porcelain"], capture_output=True, text=True, cwd=PINS.parent
    ).stdout.strip()
    commit += "+" if dirty else ""  # its working tree had changes
    bad = []
    with tempfile.TemporaryDirectory() as d:
        for name, opts in EXPERIMENTS.items():
            res = run_experiment(
                name, pathlib.Path(d) / name, quick=True, seed=0, figures=False, **opts
            )
            got, digest = predictions(res), data_digest(res)
            status, why = verdict(pins["pins"][name], got, digest, machine)
            print(f"{name}: {status}: {why}")
            if status != "pass":
                bad.append(name)
            if args.record:
                keep = [] if args.physics_changed else pins["pins"][name]
                keep = [p for p in keep if p["recorded"].get("machine") != machine]
                recorded = {"commit": commit, "machine": machine, "data": digest}
                pins["pins"][name] = [*keep, {"recorded": recorded, "predictions": got}]
    if args.record:
        atomic_write_text(PINS, json.dumps(pins, indent=1, sort_keys=True) + "\n")
        print(f"recorded {PINS}")
        return 0
    print("OK" if not bad else "NOT CONFIRMED: " + ", ".join(bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
