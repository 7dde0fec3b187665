"""The extra chapter-4 row: the static beam with the thesis author's oracle angle (issue 30)."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
import xarray as xr
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import FunctionTransformer

from vibrissa.classify import StaticBeamClassifier, TimeTemplateClassifier
from vibrissa.thesis.radial_distance import evaluation as ev
from vibrissa.thesis.radial_distance import figures as fg
from vibrissa.thesis.radial_distance import report as rp

WHISKER = {
    "length_mm": 185.0,
    "base_radius_mm": 1.0,
    "youngs_modulus_gpa": 2.35,
    "follicle_stiffness_nm_per_rad": 0.1,
    "hall_gain_v": 12.0,
    "hall_offset_v": 2.5,
}
RADII = tuple(np.arange(80.0, 181.0, 10.0))
SPEEDS = (36.0, 126.0, 216.0)


def beam_dataset(n_sets: int = 3, noise: float = 0.0, seed: int = 0) -> xr.Dataset:
    """Complete grids whose peak deflection is eq. 4.1 with theta = speed x 0.3 s / r."""
    rng = np.random.default_rng(seed)
    w = WHISKER
    c = 3.0 * w["youngs_modulus_gpa"] * 1e9 * np.pi * (w["base_radius_mm"] * 1e-3) ** 4 / 4.0
    L = w["length_mm"] * 1e-3
    sig, r_, s_, set_ = [], [], [], []
    for k in range(n_sets):
        for r in RADII:
            for s in SPEEDS:
                theta = s * 0.3 / r
                m = (
                    c
                    * theta
                    * (L - r * 1e-3)
                    / (r * 1e-3 * L)
                    * (1 + noise * rng.standard_normal())
                )
                x = np.full(30, 2.5)
                x[15] += w["hall_gain_v"] * np.tan(m / w["follicle_stiffness_nm_per_rad"])
                sig.append(x[None, :])
                r_.append(r)
                s_.append(s)
                set_.append(k + 1)
    return xr.Dataset(
        {"signal": (("trial", "channel", "time"), np.array(sig))},
        coords={
            "radial_distance_mm": ("trial", np.array(r_)),
            "speed_mm_s": ("trial", np.array(s_)),
            "set": ("trial", np.array(set_)),
        },
        attrs={"sample_rate_hz": 1000.0, "whisker": json.dumps(WHISKER)},
    )


def _classifiers() -> dict:
    return {
        "static_beam_measured": StaticBeamClassifier(whisker=WHISKER, sample_rate_hz=1000.0),
        "static_beam_fitted": Pipeline(
            [
                ("identity", FunctionTransformer()),
                (
                    "classifier",
                    StaticBeamClassifier(
                        whisker=WHISKER,
                        fit_parameters=True,
                        param_grid={"youngs_modulus_gpa": [1.5, 2.35], "length_mm": [185.0, 230]},
                        sample_rate_hz=1000.0,
                    ),
                ),
            ]
        ),
        "template": TimeTemplateClassifier(sample_rate_hz=1000.0),
    }


@pytest.fixture(scope="module")
def runs() -> tuple[dict, dict, dict]:
    ds = beam_dataset(noise=0.0)
    clfs = _classifiers()
    before = copy.deepcopy({k: v.get_params() for k, v in clfs.items()})
    base = ev.run_chapter4(
        ds, clfs, fractions=(), n_seeds=1, train_set=[2, 3], test_set=1, keep_predictions=True
    )
    oracle = ev.run_oracle_angle(ds, clfs, train_set=[2, 3], test_set=1)
    after = {k: v.get_params() for k, v in clfs.items()}
    assert repr(before) == repr(after)  # the classifiers passed in are not modified
    return base, oracle, clfs


def test_oracle_rows_recover_the_true_radius_the_fixed_speed_misses(runs) -> None:
    base, oracle, _ = runs
    assert set(oracle["classifiers"]) == {"static_beam_measured", "static_beam_fitted"}
    assert oracle["label"] == ev.ORACLE_ANGLE_LABEL and "oracle" in oracle["label"]
    assert oracle["split"]["train_set"] == [2, 3] and oracle["split"]["test_set"] == 1
    for name, entry in oracle["classifiers"].items():
        assert entry["radius_only"] and entry["speed_mm_s"] is None
        assert entry["radius_mm"]["exact_hit"] == 1.0, name
        assert entry["radius_mm"]["std"] == 0.0 and entry["abs_error_mm"]["mean"] == 0.0
        assert base["classifiers"][name]["radius_mm"]["std"] > 5.0  # one speed cannot
    fp = oracle["classifiers"]["static_beam_fitted"]["fitted_parameters"]
    assert fp["youngs_modulus_gpa"] == 2.35 and fp["length_mm"] == 185.0
    json.dumps(oracle, allow_nan=False)


def test_oracle_row_leaves_the_chapter4_rows_unchanged(runs) -> None:
    base, _, clfs = runs
    again = ev.run_chapter4(
        beam_dataset(noise=0.0),
        clfs,
        fractions=(),
        n_seeds=1,
        train_set=[2, 3],
        test_set=1,
        keep_predictions=True,
    )
    assert again["predictions"] == base["predictions"]
    for name in clfs:
        a, b = base["classifiers"][name], again["classifiers"][name]
        assert a["radius_mm"] == b["radius_mm"] and a["fitted_parameters"] == b["fitted_parameters"]


def test_oracle_scores_refuse_a_classifier_without_an_angle() -> None:
    ds = beam_dataset(n_sets=2)
    X, y = ev.dataset_arrays(ds)
    with pytest.raises(TypeError, match="StaticBeamClassifier"):
        ev.oracle_angle_scores("template", TimeTemplateClassifier(), X, y, X, y)


def _with_oracle(base: dict, oracle: dict) -> dict:
    res = copy.deepcopy(base)
    res["oracle_angle"] = copy.deepcopy(oracle)
    return res


def test_report_row_and_gap_sentence_come_from_the_results(runs) -> None:
    base, oracle, _ = runs
    res = _with_oracle(base, oracle)
    res["classifiers"]["static_beam_measured"]["radius_mm"]["std"] = 18.0
    res["oracle_angle"]["classifiers"]["static_beam_measured"]["radius_mm"]["std"] = 13.4
    g = rp.oracle_angle_gap(res, "static_beam_measured")
    assert g["thesis_std_mm"] == 8.8
    assert g["explained"] == pytest.approx((18.0 - 13.4) / (18.0 - 8.8))
    md = rp.markdown_report(res)
    table47 = md.split("## Table 4.7")[1].split("##")[0]
    assert f"static_beam_measured, {ev.ORACLE_ANGLE_LABEL} | ours (extra row)" in table47
    assert "explains 50 % of the gap of 9.20 mm" in md
    # another run, another sentence: nothing is typed in
    res["oracle_angle"]["classifiers"]["static_beam_measured"]["radius_mm"]["std"] = 20.0
    md = rp.markdown_report(res)
    assert "closes none of the gap of 9.20 mm" in md and "explains 50 %" not in md
    res["oracle_angle"]["classifiers"]["static_beam_measured"]["radius_mm"]["std"] = 5.0
    assert "closes the whole gap" in rp.markdown_report(res)
    # without the section the report is as before
    assert ev.ORACLE_ANGLE_LABEL not in rp.markdown_report(base)
    assert rp.oracle_angle_gap(base, "static_beam_measured") is None


def test_oracle_speed_plot_draws_both_angles(runs) -> None:
    base, oracle, _ = runs
    ax = fg.oracle_angle_speed_plot(_with_oracle(base, oracle), "static_beam_measured")
    assert len(ax.lines) >= 2 and len(ax.get_legend().get_texts()) == 2
    with pytest.raises(ValueError, match="no oracle-angle row"):
        fg.oracle_angle_speed_plot(base, "static_beam_measured")
