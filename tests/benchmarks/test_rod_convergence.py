"""benchmarks/rod_convergence.py: its rod is the model's own, and its references are right."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vibrissa.whisker import RodModel, preset


@pytest.mark.parametrize("mass", ["lumped", "consistent"])
@pytest.mark.parametrize("n", [12, 28])
def test_the_kernels_options_are_the_models_own_rod(bench_script, n: int, mass: str) -> None:
    rc = bench_script("rod_convergence")
    g = preset("xy-robot")
    K, M, _ = rc.plane_matrices(g, n, mass, "node", "uniform")
    model = RodModel(g, n, mass=mass)
    f = np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real))[:3] / (2 * np.pi)
    assert np.allclose(f, model.natural_frequencies_hz[:3], rtol=1e-9)
    # the model's closed-form cone integrals are the benchmark's Gauss quadrature
    np.testing.assert_allclose(model.node_mass_matrix()[1:, 1:], M, rtol=1e-12, atol=0)


def test_the_default_rod_is_the_consistent_mass(bench_script) -> None:
    rc = bench_script("rod_convergence")
    g = preset("xy-robot")
    assert RodModel(g).mass_kind == "consistent"
    ref = rc.reference_frequencies_hz(g, rc.REFERENCE_ELEMENTS, 1)[0]
    f1 = RodModel(g).natural_frequencies_hz[0]
    assert abs(f1 / ref - 1.0) * 100 <= rc.FIRST_MODE_TOLERANCE_PCT


def test_the_static_reference_is_beam_theory_for_a_stiff_follicle(bench_script) -> None:
    """A uniform cantilever (no taper) on a near-rigid follicle: P L^3 / (3 E I)."""
    rc = bench_script("rod_convergence")
    g = preset("xy-robot")
    from dataclasses import replace

    uniform = replace(g, tip_radius_mm=g.base_radius_mm, follicle_stiffness_nm_per_rad=1e6)
    tip, rotation = rc.hermite_static(uniform, 50, 1e-4)
    ei = uniform.bending_stiffness_base_nm2
    assert tip == pytest.approx(1e-4 * uniform.length_m**3 / (3 * ei), rel=1e-4)
    assert abs(rotation) < 1e-6 * tip / uniform.length_m


def test_consistent_mass_converges_faster_and_the_json_says_so(bench_script, tmp_path) -> None:
    rc = bench_script("rod_convergence")
    out = tmp_path / "rc.json"
    assert rc.main(["--out", str(out)]) == 0
    res = json.loads(out.read_text())
    fewest = {
        (r["mass"], r["stiffness"], r["grading"]): r["fewest_elements"]
        for r in res["fewest_elements_within_tolerance"]
    }
    assert fewest[("consistent", "node", "uniform")] < fewest[("lumped", "node", "uniform")]
    for r in res["rows"]:
        assert abs(r["follicle_rotation_error_pct"]) < 1e-6  # statics: moment = force x arm
    # the dynamics run for node stiffness on uniform elements, and agree with the converged rod
    both = {
        (r["mass"], r["stiffness"], r["grading"]): r["fewest_elements_both"]
        for r in res["fewest_elements_within_tolerance"]
    }
    assert both[("consistent", "cell", "uniform")] == "not run"
    assert res["default_mass"] == "consistent"
    # statics at a point load: the error shrinks with the elements, and is largest
    # nearest the thick base, where a few elements span the most compliance
    lp = res["load_points"]
    near = [r["deflection_error_pct"][0] for r in lp["rows"]]
    assert all(abs(a) > abs(b) for a, b in zip(near, near[1:], strict=False))
    assert all(
        abs(r["deflection_error_pct"][0]) >= max(map(abs, r["deflection_error_pct"][2:]))
        for r in lp["rows"]
    )
    for mass in ("lumped", "centroid", "consistent"):
        assert both[(mass, "node", "uniform")] >= fewest[(mass, "node", "uniform")]
        rows = [
            r
            for r in res["rows"]
            if (r["mass"], r["stiffness"], r["grading"]) == (mass, "node", "uniform")
        ]
        assert all(abs(r["peak_moment_error_pct"]) < 2.0 for r in rows)


def test_the_lumped_dynamic_model_is_the_models_own(bench_script) -> None:
    rc = bench_script("rod_convergence")
    g = preset("xy-robot")
    lumped = RodModel(g, 12, mass="lumped")
    assert np.array_equal(rc.dynamic_model(g, 12, "lumped").mass, lumped.mass)
    assert not np.any(rc.dynamic_model(g, 12, "lumped").mass_off)
    centroid = rc.dynamic_model(g, 12, "centroid")
    assert not np.any(centroid.mass_off)
    assert centroid.mass.sum() == pytest.approx(lumped.mass.sum(), rel=1e-12)
    assert not np.allclose(centroid.mass, lumped.mass)  # mass moved toward the base
    consistent = rc.dynamic_model(g, 12, "consistent")
    assert consistent.mass_kind == "consistent"
    # the same total mass, whichever way it is put on the nodes
    total = consistent.node_mass_matrix().sum()
    assert total == pytest.approx(lumped.node_mass_matrix().sum(), rel=1e-12)
