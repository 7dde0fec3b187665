"""benchmarks/anatomy_physics.py accounts for every row of the standard trial and its
what-if band solver solves (no timing is asserted)."""

from __future__ import annotations

import json
import sys

import numpy as np


def test_phases_account_for_every_row_and_iteration(tmp_path, monkeypatch, bench_script):
    bench = bench_script("anatomy_physics")
    out = tmp_path / "anatomy.json"
    monkeypatch.setattr(sys, "argv", ["anatomy_physics.py", "--out", str(out), "--repeats", "1"])
    assert bench.main() == 0
    result = json.loads(out.read_text())
    ph = result["phases"]
    names = ("approach", "push", "retraction_contact", "after_release")
    assert sum(ph[n]["rows"] for n in names) == ph["rows"]
    assert sum(ph[n]["solved_steps"] for n in names) == ph["total"]["solved_steps"]
    assert sum(ph[n]["newton_iterations"] for n in names) == ph["total"]["newton_iterations"]
    for n in names:
        p = ph[n]
        covered = sum(int(k) * v for k, v in p["steps_by_length_dt"].items())
        # long steps may straddle a phase's first row; every other row is a step's or linear
        assert abs(covered + p["rows_linear_free_flight"] - p["rows"]) <= 8, n
    assert ph["push"]["rows_in_contact"] > 0.9 * ph["push"]["rows"]
    assert ph["after_release"]["rows_linear_free_flight"] > 0
    w = result["wall_split_ms"]
    assert w["run_dynamics_ms"] > 0 and w["modal_advance_ms"] > 0
    k = result["kernels"]
    assert k["contact_force_n"] > 0  # the kernels were timed in contact
    assert k["assemble_forces_and_matrix_us"] > 0 and k["band_backsolve_us"] > 0


def test_the_planar_what_if_solver_solves(bench_script):
    bench = bench_script("anatomy_physics")
    bw = bench.PLANAR_BW
    rng = np.random.default_rng(3)
    n = 40
    A = rng.uniform(-0.1, 0.1, (n, 2 * bw + 1))
    A[:, bw] = 5.0
    dense = np.zeros((n, n))
    for i in range(n):
        for j in range(max(0, i - bw), min(n, i + bw + 1)):
            dense[i, j] = A[i, bw + j - i]
    b = rng.standard_normal(n)
    F = A.copy()
    bench._factor_planar(F)
    x = b.copy()
    bench._backsolve_planar(F, x)
    np.testing.assert_allclose(x, np.linalg.solve(dense, b), rtol=1e-12, atol=1e-12)
