"""benchmarks/bench_peers.py: the MuJoCo whisker, its accuracy search and the command line.

MuJoCo is an optional extra (``pip install -e '.[peers]'``): the tests that need it
skip without it. No timing is asserted.
"""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from vibrissa.whisker import WhiskerGeometry, preset

ROOT = Path(__file__).resolve().parents[2]


def _load(name: str, path: Path):
    """Import a script (not a package module) by its path."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(name, module)
    spec.loader.exec_module(module)
    return module


bench_peers = _load("bench_peers", ROOT / "benchmarks" / "bench_peers.py")
render_docs = _load("render_docs", ROOT / "scripts" / "render_docs.py")

#: A uniform rod (no taper), for comparisons with closed-form beam theory.
UNIFORM = WhiskerGeometry(length_mm=185.0, base_radius_mm=1.0, tip_radius_mm=1.0)


@pytest.fixture
def mujoco():
    return pytest.importorskip("mujoco")


# ---------------------------------------------------------------------- the reference beam
def test_reference_is_the_clamped_cantilever_for_a_rigid_follicle():
    rigid = UNIFORM.replace(follicle_stiffness_nm_per_rad=1e9, follicle_inertia_kg_m2=1e-15)
    rho_a = rigid.density_kg_m3 * math.pi * (1e-3) ** 2
    beta_l = np.array([1.875104069, 4.694091133, 7.854757438])
    analytic = (
        beta_l**2
        / (2 * math.pi * rigid.length_m**2)
        * math.sqrt(rigid.bending_stiffness_base_nm2 / rho_a)
    )
    np.testing.assert_allclose(bench_peers.reference_frequencies_hz(rigid), analytic, rtol=1e-6)


def test_reference_is_converged_and_lowered_by_the_follicle():
    g = preset("xy-robot")
    f = bench_peers.reference_frequencies_hz(g)
    coarse = bench_peers.reference_frequencies_hz(g, n_elements=50)
    np.testing.assert_allclose(coarse, f, rtol=1e-6)
    clamped = g.replace(follicle_stiffness_nm_per_rad=1e9)
    assert np.all(f < bench_peers.reference_frequencies_hz(clamped))


# ---------------------------------------------------------------------- the MuJoCo whisker
def _settled_tip_deflection(mujoco, geometry, n_links, force_n):
    """Tip deflection (m) of the MuJoCo chain settled under a constant tip force along x."""
    w = bench_peers.MujocoWhisker(mujoco, geometry, n_links, 1e-4, damping_ratio=0.0)
    m, d = w.model, w.data
    stiff = m.jnt_stiffness[m.dof_jntid]
    m.dof_damping[:] = 0.02 * stiff  # heavy damping: settles within a second
    w.reset()
    last = m.body(f"link{n_links - 1}").id
    length = w.design.edges_m[-1] - w.design.edges_m[-2]
    force = np.array([force_n, 0.0, 0.0])
    for _ in range(40):  # 2 s, the force following the tip
        mujoco.mj_forward(m, d)
        tip = d.xpos[last] + d.xmat[last].reshape(3, 3)[:, 2] * length
        d.xfrc_applied[last, :3] = force
        d.xfrc_applied[last, 3:] = np.cross(tip - d.xipos[last], force)
        mujoco.mj_step(m, d, 500)
    mujoco.mj_forward(m, d)
    return float((d.xpos[last] + d.xmat[last].reshape(3, 3)[:, 2] * length)[0])


def test_static_tip_stiffness_matches_beam_theory_for_a_uniform_rod(mujoco):
    g = UNIFORM
    force = 1e-4  # N: about 0.2 mm at the tip, linear
    L, d = g.length_m, g.follicle_depth_mm * 1e-3
    beam = force * (
        L**3 / (3 * g.bending_stiffness_base_nm2) + (L + d) ** 2 / g.follicle_stiffness_nm_per_rad
    )
    deflection = _settled_tip_deflection(mujoco, g, 10, force)
    assert deflection == pytest.approx(beam, rel=0.02)


def test_first_mode_converges_toward_the_reference(mujoco):
    g = preset("xy-robot")
    ref = bench_peers.reference_first_mode_hz(g)
    errors = []
    for n in (4, 8, 16):
        dt = 0.5 * bench_peers.MujocoWhisker(mujoco, g, n, 1e-4).stability_limit_s()
        w = bench_peers.MujocoWhisker(mujoco, g, n, dt)
        f, _, stable = bench_peers.ring_down(w, 1.0)
        assert stable
        # the ring-down reads the frequency of MuJoCo's linearisation as semi-implicit
        # Euler turns it: 2 sin(w' dt / 2) = w dt
        w_lin = 2 * math.pi * w.linear_frequencies_hz()[0]
        assert f == pytest.approx(math.asin(w_lin * dt / 2) / (math.pi * dt), rel=1e-5)
        errors.append(abs(f / ref - 1))
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 2e-4


def test_follicle_damper_gives_the_first_mode_its_damping_ratio(mujoco):
    g = preset("xy-robot")
    w = bench_peers.MujocoWhisker(mujoco, g, 8, 1e-4)
    _, zeta, stable = bench_peers.ring_down(w, 1.5, damped=True)
    assert stable
    assert zeta == pytest.approx(g.damping_ratio, rel=0.02)


def test_a_step_beyond_the_stability_limit_is_unstable(mujoco):
    g = preset("xy-robot")
    limit = bench_peers.MujocoWhisker(mujoco, g, 8, 1e-4).stability_limit_s()
    with bench_peers.one_core(mujoco):
        _, _, ok = bench_peers.ring_down(bench_peers.MujocoWhisker(mujoco, g, 8, 0.9 * limit), 0.5)
        _, _, bad = bench_peers.ring_down(bench_peers.MujocoWhisker(mujoco, g, 8, 1.1 * limit), 0.5)
    assert ok and not bad


def test_the_planar_chain_is_the_spatial_one_without_its_x_hinges(mujoco):
    g = preset("xy-robot")
    spatial = bench_peers.MujocoWhisker(mujoco, g, 8, 1e-4)
    planar = bench_peers.MujocoWhisker(mujoco, g, 8, 1e-4, planar=True)
    names = {planar.model.joint(i).name for i in range(planar.model.njnt)}
    assert planar.model.nv == spatial.model.nv - 9  # the follicle's and 8 shaft x hinges
    assert not any(n.startswith(("bend_x", "follicle_x")) for n in names)
    # in the plane it is the same chain: mass matrix, springs and dampers
    for a, b in zip(planar.plane_matrices(), spatial.plane_matrices(), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-300)
    assert planar.follicle_damping == pytest.approx(spatial.follicle_damping, rel=1e-9)
    path = bench_peers.pole_path(0.4)
    flat = bench_peers.contact_run(planar, 0.4, path)
    full = bench_peers.contact_run(spatial, 0.4, path)
    assert flat[1] and full[1]
    assert flat[0] == pytest.approx(full[0], rel=1e-3)  # the contact stays in the plane


# ---------------------------------------------------------------------- the command line
def test_quick_json_has_the_comparison(mujoco, tmp_path, capsys):
    out = tmp_path / "results" / "peers.json"
    assert bench_peers.main(["--quick", "--json", "--duration-s", "0.2", "--out", str(out)]) == 0
    result = json.loads(capsys.readouterr().out)
    for key in (
        "vibrissa_rtf",
        "mujoco_rtf",
        "ratio",
        "mujoco_links",
        "mujoco_dt_s",
        "mujoco_first_mode_error_pct",
        "reference_first_mode_hz",
        "mujoco_first_mode_hz",
        "vibrissa_peak_follicle_moment_nm",
        "mujoco_peak_follicle_moment_nm",
        "mujoco_peak_moment_error_pct",
        "mujoco_version",
        "search",
        "machine",
        "mujoco_planar_rtf",
        "ratio_planar",
        "mujoco_planar_peak_follicle_moment_nm",
        "reference_peak_follicle_moment_nm",
        "vibrissa_peak_moment_error_pct",
        "vibrissa_search",
        "vibrissa_default_first_mode_error_pct",
        "vibrissa_default_peak_moment_error_pct",
    ):
        assert key in result, key
    # both simulators held to the same tolerances, each at its cheapest accepted setting
    tol_f, tol_m = bench_peers.FIRST_MODE_TOLERANCE_PCT, bench_peers.MOMENT_TOLERANCE_PCT
    assert abs(result["vibrissa_first_mode_error_pct"]) <= tol_f
    assert abs(result["vibrissa_peak_moment_error_pct"]) <= tol_m
    ours = [row for row in result["vibrissa_search"] if row["accepted"]]
    assert len(ours) == 1 and ours[0]["n_elements"] == result["vibrissa_n_elements"]
    fewer = [r for r in result["vibrissa_search"] if r["n_elements"] < ours[0]["n_elements"]]
    assert all(
        abs(r["first_mode_error_pct"]) > tol_f
        or r["peak_moment_error_pct"] is None
        or abs(r["peak_moment_error_pct"]) > tol_m
        for r in fewer
    )
    assert result["ratio"] == pytest.approx(result["vibrissa_rtf"] / result["mujoco_rtf"])
    assert result["ratio_planar"] == pytest.approx(
        result["vibrissa_rtf"] / result["mujoco_planar_rtf"]
    )
    assert abs(result["mujoco_planar_peak_moment_error_pct"]) <= bench_peers.MOMENT_TOLERANCE_PCT
    assert abs(result["mujoco_first_mode_error_pct"]) <= bench_peers.FIRST_MODE_TOLERANCE_PCT
    assert abs(result["mujoco_peak_moment_error_pct"]) <= bench_peers.MOMENT_TOLERANCE_PCT
    accepted = [row for row in result["search"] if row["accepted"]]
    assert len(accepted) == 1 and accepted[0]["links"] == result["mujoco_links"]
    assert result["duration_s"] == 0.2 and result["quick"]
    assert json.loads(out.read_text()) == result
    # what docs/peers.md quotes from it
    quoted = render_docs.extract_peers(result)
    assert quoted["ratio"] == result["ratio"]
    assert quoted["mujoco_dt_us"] == pytest.approx(result["mujoco_dt_s"] * 1e6)
    assert quoted["vibrissa_search_table"].count("accepted") == 1
    table = quoted["search_table"].splitlines()
    assert len(table) == 2 + len({row["links"] for row in result["search"]})
    assert table[-1].startswith(f"| {result['mujoco_links']} |") and "accepted" in table[-1]


def test_our_search_takes_the_fewest_elements_within_both_tolerances():
    g = preset("xy-robot")
    ref_hz = bench_peers.reference_first_mode_hz(g)
    # a peak reference our rod meets at any resolution: the first mode decides alone
    # (the default rod, with its consistent mass: first mode -0.10 % at 6 elements,
    # -0.056 % at 8; benchmarks/results/rod_convergence.json)
    found = bench_peers.our_search(g, 0.2, ref_hz, 1.0, elements=(6, 8, 12))
    assert found["accepted"] is None  # 1 N m is far from the contact's mN m
    peak = found["rows"][-1]["peak_follicle_moment_nm"]
    found = bench_peers.our_search(g, 0.2, ref_hz, peak, elements=(6, 8, 12))
    assert [r["n_elements"] for r in found["rows"]] == [6, 8]
    assert found["rows"][0]["peak_follicle_moment_nm"] is None  # first mode -0.10 % off
    assert found["accepted"]["n_elements"] == 8


@pytest.mark.parametrize(
    "argv, name",
    [
        (["--repeats", "0"], "--repeats"),
        (["--repeats", "two"], "--repeats"),
        (["--duration-s", "nan"], "--duration-s"),
        (["--duration-s", "0.001"], "--duration-s"),
        (["--frobnicate"], "--frobnicate"),
    ],
)
def test_bad_arguments_exit_2_in_one_line(argv, name, capsys):
    with pytest.raises(SystemExit) as exc:
        bench_peers.main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error:") and name in err


def test_out_naming_a_directory_is_refused_before_any_work(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        bench_peers.main(["--out", str(tmp_path)])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out" in err
    assert list(tmp_path.iterdir()) == []


def test_without_mujoco_it_says_how_to_install_it(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco raises ImportError
    assert bench_peers.main(["--quick"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "pip install -e '.[peers]'" in err
