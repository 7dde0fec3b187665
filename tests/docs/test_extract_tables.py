"""``render_docs.py extract``: the run files keep every table of chapters 4 and 5 and identify.

Synthetic results dicts in the shape of ``results.json`` (a few classes each).
"""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("render_docs", ROOT / "scripts" / "render_docs.py")
render_docs = importlib.util.module_from_spec(_spec)
sys.modules["render_docs"] = render_docs
_spec.loader.exec_module(render_docs)


def _scores(mean, std):
    return {"mean": mean, "std": std, "sem": std / 3, "mean_abs": abs(mean), "n": 9, "kappa": 0.5}


def _ch4_entry(std, beam=False):
    return {
        "radius_mm": _scores(0.123456, std),
        "speed_mm_s": None if beam else _scores(-1.0, 2 * std),
        "joint": None if beam else {"exact_hit": 0.5, "kappa": 0.4},
        "classify_seconds": 0.0123456,
        "fit_seconds": 1.0,
        "n_test": 9,
        "n_train": 9,
        "fitted_parameters": {"youngs_modulus_gpa": 1.5, "length_mm": 230.0} if beam else {},
        "radius_error_by_speed": [
            {"speed_mm_s": v, "mean": 0.0, "std": s, "n": 3}
            for v, s in ((36.0, 9.0), (126.0, 4.0), (216.0, 11.0))
        ]
        if beam
        else [],
    }


def _chapter4_results():
    clfs = {
        "static_beam_measured": _ch4_entry(8.8, beam=True),
        "static_beam_fitted": _ch4_entry(10.4, beam=True),
        "feature": _ch4_entry(7.84),
        "template": _ch4_entry(4.92),
    }
    fractions = {
        f: {
            "feature": _ch4_entry(s) | {"per_seed": [{"seed": [0, 0]}]},
            "template": _ch4_entry(5.0),
            "static_beam_measured": None,
        }
        for f, s in (("0.4", 7.70), ("0.05", 10.49))
    }
    return {
        "meta": {"dataset": {"n_trials": 36, "reused": False}, "wall_seconds": {"generate": 2.0}},
        "classifiers": clfs,
        "training_fractions": fractions,
        "predictions": {
            "radius_mm_true": [80.0, 81.0, 82.0],
            "speed_mm_s_true": [36.0, 36.0, 43.2],
            "classifiers": {
                "template": {"radius_mm": [80.0, 82.0, 82.0], "speed_mm_s": [36.0, 43.2, 43.2]},
                "static_beam_measured": {"radius_mm": [81.0, 81.0, 81.0], "speed_mm_s": None},
            },
        },
    }


def test_chapter4_keeps_tables_4_1_to_4_7_and_the_old_keys():
    out = render_docs.extract_chapter4(_chapter4_results())
    assert out["classifiers"]["template"]["radius_mm"] == {"mean": 0.123456, "std": 4.92}
    t = out["tables"]
    assert t["table_4_1"]["fitted"] == {"youngs_modulus_gpa": 1.5, "length_mm": 230.0}
    assert t["table_4_6"]["template"]["classify_seconds"] == 0.01235
    assert t["table_4_7"]["feature"]["speed_mm_s"]["std"] == 15.68
    curves = t["training_curves"]["feature"]
    assert set(curves) == {"1", "0.4", "0.05"} and "per_seed" not in curves["0.4"]
    assert curves["0.05"]["radius_mm"]["std"] == 10.49
    assert "0.4" not in t["training_curves"]["static_beam_measured"]
    hist = t["error_histograms"]
    assert hist["template"]["radius_mm"] == {"error": [0.0, 1.0], "count": [2, 1]}
    assert hist["template"]["speed_mm_s"] == {"error": [0.0, 7.2], "count": [2, 1]}
    assert hist["static_beam_measured"]["speed_mm_s"] is None
    d = out["derived"]
    assert d["static_beam_measured"]["std_at_median_speed"] == 4.0
    assert d["static_beam_measured"]["std_at_extreme_speed"] == 11.0
    red = d["reduced_training"]
    assert red["smallest_fraction"] == "0.05"
    assert red["worst_radius_std_ratio_smallest"] == round(10.49 / 7.84, 3)
    assert red["feature_best_radius_fraction"] == 0.4


def _confusion(matrix):
    return {"labels": [0.0, 1.0, 2.0, 3.0], "matrix": matrix}


def test_chapter5_keeps_tables_confusions_and_figure_5_15():
    m = [[9, 1, 0, 0], [0, 5, 3, 2], [1, 3, 4, 2], [0, 2, 3, 5]]
    entry = {
        "kappa": {"angle": 0.3, "speed": 0.2, "texture": 0.21, "texture_alone": None},
        "weighted_kappa": {"angle": {"linear": 0.4, "quadratic": 0.5}},
        "errors": {"angle_deg": {**_scores(0.1, 14.81234), "kappa_linear": 0.4}},
        "confusion": {"texture": _confusion(m), "angle": None},
        "joint": {"exact_hit": 0.1, "kappa": 0.05},
        "classify_seconds": 1.0,
        "fit_seconds": 2.0,
    }
    clfs = {
        name: entry | {"kappa": entry["kappa"] | {"angle": k}}
        for name, k in (
            ("template_lowpass", 0.30),
            ("frequency", 0.44),
            ("feature", 0.11),
            ("naive_bayes_velocity", 0.39),
        )
    }
    out = render_docs.extract_chapter5({"meta": {}, "classifiers": clfs})
    t = out["tables"]
    assert t["figure_5_15"]["angle"] == [
        "frequency",
        "naive_bayes_velocity",
        "template_lowpass",
        "feature",
    ]
    assert t["classifiers"]["feature"]["errors"]["angle_deg"]["std"] == 14.81
    assert "kappa_linear" not in t["classifiers"]["feature"]["errors"]["angle_deg"]
    assert t["confusion"]["feature"]["texture"]["matrix"] == m
    assert t["confusion"]["feature"]["angle"] is None
    g = out["derived"]["texture_groups"]["feature"]
    # smooth vs rough: [[9, 1], [1, 29]]; sandpapers: the lower-right 3 x 3 block
    po, pe = 38 / 40, (10 * 10 + 30 * 30) / 40**2
    assert math.isclose(g["smooth_vs_rough_kappa"], (po - pe) / (1 - pe), rel_tol=1e-3)
    po, pe = 14 / 29, (10 * 10 + 9 * 10 + 10 * 9) / 29**2
    assert math.isclose(g["among_sandpapers_kappa"], (po - pe) / (1 - pe), rel_tol=1e-3)
    assert out["derived"]["thesis_methods"] == 4  # the old keys stay


def test_identify_keeps_every_value_tolerance_and_verdict():
    report = {
        "n_trials": 35,
        "quick": True,
        "observables": {
            "resonance_hz": {
                "key": "resonance_hz",
                "value": 30.0123456,
                "thesis_value": 30.0,
                "unit": "Hz",
                "tolerance": "within 10 %",
                "within": True,
                "detail": {"chapter5_fft_peak_hz": 16.0, "modes": [30.01234, 86.4]},
            },
            "tip_zone_mm": {"value": 15.0, "tolerance": "at most 10 mm", "within": False},
        },
    }
    out = render_docs.extract_identify(report)
    assert out["met"] == ["`resonance_hz`"] and out["n_within"] == 1
    o = out["observables"]["resonance_hz"]
    assert o["value"] == 30.01 and o["within"] is True and o["tolerance"] == "within 10 %"
    assert o["detail"] == {"chapter5_fft_peak_hz": 16.0, "modes": [30.01, 86.4]}
    assert out["observables"]["tip_zone_mm"]["within"] is False
    json.dumps(out)


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e12, max_value=1e12))
def test_sig4_keeps_four_significant_digits(x):
    y = render_docs.sig4(x)
    assert abs(y - x) <= 5e-4 * abs(x) + 1e-300
    assert render_docs.sig4({"a": [x, 3, None, True]}) == {"a": [y, 3, None, True]}


def test_sig4_turns_non_finite_into_none():
    assert render_docs.sig4([math.nan, math.inf]) == [None, None]


def test_thesis_timing_keeps_every_reproduction_and_the_budget():
    run = {
        "workers": 2,
        "machine": {"cores": 2, "cpu": "some CPU"},
        "runs": {
            "scratchbot": {
                "wall_seconds": 11.4,
                "stages_seconds": {"generate": 6.0, "evaluate": 0.2},
                "n_trials": 540,
                "load_average_at_start": 0.5,
            },
            "biotact-g1": {
                "wall_seconds": 700.0,
                "stages_seconds": {"generate": 680.0, "evaluate": 20.0},
                "n_trials": 1620,
                "load_average_at_start": 1.0,
            },
        },
        "total_seconds": 711.4,
        "budget_seconds": 600.0,
        "complete": True,
        "within_budget": False,
        "meta": {"created_utc": "2026-11-27T20:00:00+00:00"},
    }
    out = render_docs.extract_thesis(run)
    lines = out["table"].splitlines()
    assert len(lines) == 2 + 2
    assert lines[2].startswith("| `scratchbot` | 540 | 11 | 6 | 0 |")
    assert lines[3].startswith("| `biotact-g1` | 1620 | 700 | 680 | 20 |")
    assert out["total_minutes"] == 711.4 / 60 and out["budget_minutes"] == 10.0
    assert out["within_budget"] is False and out["cores"] == 2


def test_closed_loop_profiles_give_each_stage_per_loop():
    out = render_docs.extract_closed_loops(ROOT / "benchmarks" / "results")
    g1 = out["biotact_g1"]
    assert set(g1) == {"before", "stepper", "after"}
    for when in g1.values():
        assert when["wall_seconds"] > 0 and when["solver_seconds"] > 0
        assert when["created_utc"] and when["cpu"]
    # the stepper's and the compiled loop's profiles were made on one machine
    assert g1["stepper"]["cpu"] == g1["after"]["cpu"] != "not recorded"


def test_consistent_mass_energy_rows_by_case_and_elements():
    run = {
        "settings": {"rho_inf": 0.5, "dt_s": 2.5e-4, "steps": 400},
        "rows": [
            {
                "case": "consistent",
                "n_elements": 12,
                "first_step_pct": -0.003,
                "max_pct": -0.003,
                "last_pct": -1.1,
            },
            {
                "case": "lumped energy",
                "n_elements": 12,
                "first_step_pct": 0.8,
                "max_pct": 3.8,
                "last_pct": -0.5,
            },
        ],
    }
    out = render_docs.extract_consistent_mass_energy(run)
    assert out["consistent"]["e12"]["max_pct"] == -0.003
    assert out["lumped_energy"]["e12"] == {"first_step_pct": 0.8, "max_pct": 3.8, "last_pct": -0.5}
    assert out["settings"]["steps"] == 400
