"""Tests of `vibrissa whisker presets|info|static|push|ring|whisk`."""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.cli.whisker import build_geometry
from vibrissa.whisker.geometry import PRESETS

runner = CliRunner()


def run_json(*args: str) -> dict:
    res = runner.invoke(app, ["whisker", *args, "--json"])
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_presets_lists_all_with_parameters():
    items = run_json("presets")
    names = [d["name"] for d in items]
    for name in (
        "xy-robot",
        "scratchbot",
        "crunchbot",
        "biotact-g1-80",
        "biotact-g1-112",
        "biotact-g1-158",
    ):
        assert name in names
    keys = set(PRESETS["xy-robot"].to_dict())
    for d in items:
        assert set(d) == keys
        assert d == PRESETS[d["name"]].to_dict()


def test_presets_text():
    res = runner.invoke(app, ["whisker", "presets"])
    assert res.exit_code == 0
    assert "crunchbot" in res.stdout


def test_info_keys_and_values():
    d = run_json("info")
    for key in PRESETS["xy-robot"].to_dict():
        assert key in d
    for key in (
        "n_elements",
        "natural_frequencies_hz",
        "mass_kg",
        "hall_gain_v_per_tan",
        "damping_alpha_per_s",
        "damping_beta_shaft_s",
        "damping_beta_follicle_s",
    ):
        assert key in d
    assert d["name"] == "xy-robot"
    assert len(d["natural_frequencies_hz"]) == 3
    f = d["natural_frequencies_hz"]
    assert 0 < f[0] < f[1] < f[2]
    assert d["mass_kg"] == pytest.approx(PRESETS["xy-robot"].mass_kg)
    assert d["hall_gain_v_per_tan"] > 0


def test_info_overrides_preset():
    d = run_json("info", "--preset", "scratchbot", "--length-mm", "150", "--n-elements", "12")
    assert d["length_mm"] == 150.0
    assert d["base_radius_mm"] == PRESETS["scratchbot"].base_radius_mm
    assert d["youngs_modulus_gpa"] == PRESETS["scratchbot"].youngs_modulus_gpa
    assert d["name"] == "custom"
    assert d["n_elements"] == 12


def test_explicit_options_default_to_xy_robot():
    g = build_geometry(None, tip_radius_mm=0.5)
    xy = PRESETS["xy-robot"]
    assert g.tip_radius_mm == 0.5
    assert (g.length_mm, g.base_radius_mm, g.youngs_modulus_gpa) == (
        xy.length_mm,
        xy.base_radius_mm,
        xy.youngs_modulus_gpa,
    )
    assert build_geometry("crunchbot") is PRESETS["crunchbot"]


def test_info_text():
    res = runner.invoke(app, ["whisker", "info", "--preset", "biotact-g1-80"])
    assert res.exit_code == 0
    assert "natural_frequencies_hz" in res.stdout


STATIC_KEYS = {
    "base_moment_nm",
    "deflection_mm",
    "axial_shortening_mm",
    "base_angle_deg",
    "hall_x_v",
    "hall_y_v",
}
PUSH_KEYS = {
    "base_moment_nm",
    "base_force_n",
    "contact_arc_length_mm",
    "slipped_off",
    "hall_x_v",
    "hall_y_v",
}


def test_static_uniform_rigid_matches_beam_theory():
    F, L = 1e-4, 185.0
    d = run_json(
        "static",
        "--base-radius-mm",
        "1",
        "--tip-radius-mm",
        "1",
        "--rigid-follicle",
        "--force-n",
        str(F),
        "--at-mm",
        str(L),
    )
    assert STATIC_KEYS <= set(d)
    E = PRESETS["xy-robot"].youngs_modulus_gpa * 1e9
    EI = E * math.pi * (1e-3) ** 4 / 4
    expected_mm = F * (L * 1e-3) ** 3 / (3 * EI) * 1e3
    assert d["deflection_mm"] == pytest.approx(expected_mm, rel=0.02)
    assert d["base_moment_nm"] == pytest.approx(F * L * 1e-3, rel=0.01)
    assert d["hall_x_v"] == 2.5 and d["hall_y_v"] == 2.5
    assert d["base_angle_deg"] == 0.0


def test_static_midpoint_moment_and_compliant_hall():
    F, A = 1e-3, 100.0
    d = run_json("static", "--force-n", str(F), "--at-mm", str(A))
    assert d["base_moment_nm"] == pytest.approx(F * A * 1e-3, rel=0.02)
    assert d["hall_x_v"] > 2.5
    assert d["hall_y_v"] == pytest.approx(2.5)
    assert d["base_angle_deg"] > 0


def test_push_rigid_vs_compliant():
    rigid = run_json("push", "--at-mm", "100", "--displacement-mm", "10", "--rigid-follicle")
    assert PUSH_KEYS <= set(rigid)
    assert rigid["hall_x_v"] == 2.5 and rigid["hall_y_v"] == 2.5
    assert rigid["base_moment_nm"] > 0
    soft = run_json("push", "--at-mm", "100", "--displacement-mm", "10", "--friction", "0.3")
    assert PUSH_KEYS <= set(soft)
    assert soft["hall_x_v"] > 2.5
    assert soft["slipped_off"] is False
    assert soft["contact_arc_length_mm"] == pytest.approx(100, abs=5)


def test_calibration_push_reads_full_scale():
    d = run_json("push", "--at-mm", "150", "--displacement-mm", "60")
    assert d["hall_x_v"] == pytest.approx(4.75, abs=0.02)
    assert d["hall_y_v"] == pytest.approx(2.5, abs=0.02)


def test_ring_matches_configuration():
    d = run_json("ring")
    for key in ("frequency_hz", "damping_ratio", "configured_damping_ratio", "model_frequency_hz"):
        assert key in d
    assert d["configured_damping_ratio"] == PRESETS["xy-robot"].damping_ratio
    assert d["damping_ratio"] == pytest.approx(d["configured_damping_ratio"], rel=0.10)
    assert d["frequency_hz"] == pytest.approx(d["model_frequency_hz"], rel=0.05)


def test_ring_other_damping_and_rigid_follicle():
    d = run_json("ring", "--damping-ratio", "0.15", "--rigid-follicle", "--duration-s", "0.6")
    assert d["damping_ratio"] == pytest.approx(0.15, rel=0.10)
    assert d["frequency_hz"] == pytest.approx(d["model_frequency_hz"], rel=0.05)


def test_ring_text_summary():
    res = runner.invoke(app, ["whisker", "ring"])
    assert res.exit_code == 0
    out = res.stdout
    assert "xy-robot" in out and "Hz" in out and "damping" in out


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["info", "--length-mm", "-5"], "--length-mm"),
        (["info", "--tip-radius-mm", "2"], "--tip-radius-mm"),
        (["info", "--youngs-modulus-gpa", "0"], "--youngs-modulus-gpa"),
        (["info", "--length-mm", "nan"], "--length-mm"),
        (["info", "--preset", "no-such-whisker"], "--preset"),
        (["info", "--n-elements", "2"], "--n-elements"),
        (["info", "--damping-ratio", "1.5"], "--damping-ratio"),
        (["static", "--force-n", "0.01", "--at-mm", "200"], "--at-mm"),
        (["static", "--force-n", "nan", "--at-mm", "100"], "--force-n"),
        (["push", "--at-mm", "190", "--displacement-mm", "5"], "--at-mm"),
        (["push", "--at-mm", "100", "--displacement-mm", "-5"], "--displacement-mm"),
        (["push", "--at-mm", "100", "--displacement-mm", "5", "--friction", "-1"], "--friction"),
        (["ring", "--duration-s", "0"], "--duration-s"),
    ],
)
def test_bad_input_exits_2_with_one_line(args, needle):
    res = runner.invoke(app, ["whisker", *args, "--json"])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1
    assert needle in lines[0]
    assert res.stdout == ""


def test_help_mentions_units():
    for cmd in ("info", "static", "push", "ring"):
        res = runner.invoke(app, ["whisker", cmd, "--help"])
        assert res.exit_code == 0
    res = runner.invoke(app, ["whisker", "push", "--help"], terminal_width=200)
    assert "(mm)" in res.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["info", "--length-mm", "1e300"], "--length-mm must lie in [1, 2000] mm"),
        (["info", "--length-mm", "1e20"], "--length-mm must lie in [1, 2000] mm"),
        (["info", "--damping-ratio", "0.7"], "--damping-ratio must lie in [0, 0.5]"),
        (["ring", "--duration-s", "1e9"], "--duration-s must lie in [0, 600] s"),
    ],
)
def test_absurd_whisker_inputs_refused_in_one_line(args, message):
    """Issue 13, findings 3 and 8: tracebacks, 29 TiB allocations, inconsistent bounds."""
    res = CliRunner().invoke(app, ["whisker", *args])
    assert res.exit_code == 2, res.output
    assert message in res.output and "Traceback" not in res.output
    help_text = CliRunner().invoke(app, ["whisker", "info", "--help"]).output
    assert "0.99" not in help_text


# ----------------------------------------------------------------- issue 13, finding 7
@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["static", "--force-n", "1000", "--at-mm", "100"], "--force-n"),
        (["push", "--at-mm", "150", "--displacement-mm", "200"], "--displacement-mm"),
        (
            [
                "ring",
                "--youngs-modulus-gpa",
                "1200",
                "--density-kg-m3",
                "1",
                "--base-radius-mm",
                "0.001",
                "--tip-radius-mm",
                "0.001",
                "--length-mm",
                "1",
                "--tip-deflection-mm",
                "0.4",
            ],
            "--dt-ms",
        ),
    ],
)
def test_a_solver_that_does_not_converge_on_the_options_is_bad_input(args, option):
    """The old main exited 1, "simulation failed", as for a bug; the options are to blame."""
    res = runner.invoke(app, ["whisker", *args])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and res.stdout == ""
    assert lines[0].startswith("error: the solver did not converge on these parameters")
    assert option in lines[0]


def test_a_static_load_beyond_the_solvers_reach_says_how_far_it_got():
    res = runner.invoke(app, ["whisker", "static", "--force-n", "1000", "--at-mm", "100"])
    assert "did not converge beyond" in res.stderr and "N of --force-n=1000" in res.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["info", "--density-kg-m3", "1e300"],
            "--density-kg-m3 must lie in [1, 23000] kg/m^3 (aerogel to osmium), got 1e+300",
        ),
        (
            ["info", "--youngs-modulus-gpa", "1e-300"],
            "--youngs-modulus-gpa must lie in [0.001, 1200] GPa (soft rubber to diamond)",
        ),
        (
            ["info", "--base-radius-mm", "1e-300", "--tip-radius-mm", "1e-301"],
            "--base-radius-mm must lie in [0.001, 500] mm",
        ),
        (
            [
                "info",
                "--youngs-modulus-gpa",
                "1200",
                "--density-kg-m3",
                "1",
                "--base-radius-mm",
                "0.5",
                "--tip-radius-mm",
                "0.001",
                "--rigid-follicle",
            ],
            "is overdamped by the shaft's own material damping",
        ),
        (
            [
                "info",
                "--youngs-modulus-gpa",
                "0.01",
                "--base-radius-mm",
                "0.001",
                "--tip-radius-mm",
                "0.001",
                "--length-mm",
                "2000",
            ],
            "calibration push (60 mm at r = 150 mm) does not tilt the follicle",
        ),
        (
            ["push", "--at-mm", "150", "--displacement-mm", "60", "--pole-radius-mm", "1e6"],
            "--pole-radius-mm (1e+06) must be smaller than --at-mm (150)",
        ),
    ],
)
def test_whiskers_outside_physics_are_refused_in_one_line(args, message):
    """The old main gave tracebacks (IndexError, a 7-line overflow warning, LAPACK's
    "leading minor" message) or, for a 1 km pole, a base moment of 0 at 4.75 V."""
    res = runner.invoke(app, ["whisker", *args])
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], res.stderr


# ----------------------------------------------------------------- whisk (issue 15)
@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--frequency-hz", "0"], "--frequency-hz must be positive"),
        (["--frequency-hz", "-4"], "--frequency-hz must be positive"),
        (["--sigma-z", "-0.7"], "--sigma-z must be non-negative"),
        (["--tau-z-periods", "-1"], "--tau-z-periods must be positive"),
        (["--motor-bandwidth-hz", "0"], "--motor-bandwidth-hz must be positive"),
        (["--pole-at-mm", "100", "--pole-angle-deg", "0"], "inside the whisker's reach at rest"),
        (["--pole-at-mm", "100", "--pole-angle-deg", "-3"], "inside the whisker's reach at rest"),
        (["--pole-at-mm", "100", "--retracted-deg", "8"], "inside the whisker's reach at rest"),
        (["--pole-at-mm", "100", "--pole-angle-deg", "30"], "never reaches the pole"),
        (["--pole-at-mm", "500"], "--pole-at-mm must lie in"),
        (["--whisks", "0"], "--whisks"),
    ],
)
def test_whisk_bad_input_exits_2_in_one_line_before_any_simulation(args, needle, monkeypatch):
    import vibrissa.robots.whisking as whisking

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("simulated")

    monkeypatch.setattr(whisking, "run_whisking", boom)
    res = runner.invoke(app, ["whisker", "whisk", "--preset", "scratchbot", *args, "--json"])
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0]
    assert res.stdout == ""


def test_whisk_into_a_pole_and_in_air():
    air = run_json("whisk", "--preset", "scratchbot", "--frequency-hz", "2", "--whisks", "2")
    assert air["max_contact_force_n"] == 0.0 and air["whisks_touching"] == 0
    pole = run_json(
        "whisk",
        "--preset",
        "scratchbot",
        "--frequency-hz",
        "2",
        "--whisks",
        "2",
        "--pole-at-mm",
        "100",
    )
    assert pole["whisks_touching"] == 2 and pole["max_contact_force_n"] > 0
    assert pole["peak_deflection_v"] > 5 * air["peak_deflection_v"]
    rcp = run_json(
        "whisk",
        "--preset",
        "scratchbot",
        "--frequency-hz",
        "2",
        "--whisks",
        "2",
        "--pole-at-mm",
        "100",
        "--sigma-z",
        "0.7",
    )
    assert 0 < rcp["max_gating"] <= 1
    assert rcp["peak_deflection_v"] < pole["peak_deflection_v"]
