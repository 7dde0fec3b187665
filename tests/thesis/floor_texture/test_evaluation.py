"""The Roomba evaluation (thesis 6.2.1-6.2.2) on hand-made recordings, and the thesis' tables."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from vibrissa.thesis.floor_texture.evaluation import (
    condition_windows,
    confusion_matrix,
    mean_correct,
    run_floor_texture,
    run_floor_texture_seeds,
    signal_levels,
)
from vibrissa.thesis.floor_texture.report import markdown_floor_texture
from vibrissa.thesis.floor_texture.values import THESIS

FLOORS = THESIS["floors"]
FS = 2000.0


def test_the_transcribed_tables_give_the_thesis_mean_correct():
    for c, cm in THESIS["confusion"].items():
        m = np.asarray(cm)
        assert np.all(m.sum(axis=1) == 80)  # 4 trials x 20 test windows per floor
        assert mean_correct(m) == pytest.approx(THESIS["mean_correct"][c], abs=0.005)
    # the column percentages printed under table 6.2: vinyl 79 %, smooth carpet 33 %
    cw = np.asarray(THESIS["confusion"]["clockwise"])
    assert cw[1, 1] / 80 == pytest.approx(0.79, abs=0.005)
    assert cw[2, 2] / 80 == pytest.approx(0.33, abs=0.01)


def test_confusion_counts_rows_true():
    cm = confusion_matrix(np.array([0, 0, 1, 2]), np.array([0, 1, 1, 1]), 3)
    np.testing.assert_array_equal(cm, [[1, 1, 0], [0, 1, 0], [0, 1, 0]])
    assert mean_correct(cm) == pytest.approx((0.5 + 1 + 0) / 3)
    assert mean_correct(np.zeros((2, 2))) is None


def _dataset(n_trials: int = 2, quiet: int = 5, seconds: float = 4.0) -> xr.Dataset:
    """Each floor rings at its own frequency; the first ``quiet`` packets are at rest."""
    rng = np.random.default_rng(0)
    n = int(seconds * FS)
    t = np.arange(n) / FS
    sig, floor, cond = [], [], []
    for c in ("clockwise", "anticlockwise", "spot"):
        for k, f in enumerate(FLOORS):
            for _ in range(n_trials):
                x = 2.5 + 0.05 * np.sin(2 * np.pi * (20 + 40 * k) * t + rng.uniform(0, 6))
                x = x + rng.normal(0, 0.01, n)
                x[: quiet * 160] = 2.5
                sig.append(np.vstack([x, np.full(n, 2.5)]))
                floor.append(f)
                cond.append(c)
    return xr.Dataset(
        {"signal": (("trial", "channel", "time"), np.asarray(sig))},
        coords={"floor": ("trial", floor), "condition": ("trial", cond), "channel": ["x", "y"]},
        attrs={"sample_rate_hz": FS},
    )


def test_windows_follow_the_protocol():
    ds = _dataset()
    d = condition_windows(ds, "clockwise", FLOORS)
    # 4 s = 50 packets, 5 quiet: 45 kept = 7200 samples = 9 windows: 5 train, 4 test
    assert d["packets"]["vinyl"] == [2 * 45, 2 * 50]
    assert d["windows"]["vinyl"] == [2 * 5, 2 * 4]
    assert d["X_train"].shape == (4 * 10, 2, 800) and d["X_test"].shape == (4 * 8, 2, 800)


def test_distinct_spectra_are_told_apart_in_every_condition_and_across():
    res = run_floor_texture(_dataset())
    for c in ("clockwise", "anticlockwise", "spot"):
        assert res["mean_correct"][c] == 1.0
        np.testing.assert_array_equal(res["confusion"][c], np.diag([8] * 4))
        assert res["naive_bayes"]["mean_correct"][c] is not None
    assert res["cross_condition"]["cw_on_ccw"] == 1.0
    assert res["cross_condition"]["ccw_on_cw"] == 1.0
    spectra = res["templates"]["clockwise"]["spectra"]
    f = np.asarray(res["templates"]["clockwise"]["frequency_hz"])
    for k, floor in enumerate(FLOORS):
        assert f[int(np.argmax(np.asarray(spectra[floor])[0][1:])) + 1] == 20 + 40 * k
    text = markdown_floor_texture(res, {}, None)
    assert "table 6.1" in text and "72 %" in text and "100 %" in text


def test_sessions_are_evaluated_one_by_one_and_reported_with_their_spread():
    one = _dataset(n_trials=1)
    two = xr.concat([one, one], dim="trial")
    two = two.assign_coords(seed=("trial", [7] * one.sizes["trial"] + [8] * one.sizes["trial"]))
    res = run_floor_texture_seeds(two)
    assert res["meta"]["seeds"] == [7, 8] and res["meta"]["n_seeds"] == 2
    # the claims ledger's paths hold numbers: the means over the sessions
    for c in ("clockwise", "anticlockwise", "spot"):
        assert res["mean_correct"][c] == 1.0
        leaf = res["spread"]["mean_correct"][c]
        assert leaf["values"] == [1.0, 1.0] and leaf["std"] == 0.0 and leaf["n"] == 2
    for k in ("cw_on_ccw", "ccw_on_cw"):
        assert res["cross_condition"][k] == 1.0
        assert res["spread"]["cross_condition"][k]["n"] == 2
    assert "templates" not in res["spread"] and "clockwise" in res["templates"]
    assert res["per_floor_correct"]["clockwise"]["vinyl"] == 1.0
    text = markdown_floor_texture(res, {}, None)
    assert "100 ± 0 %" in text and "seeds 7, 8" in text
    # one session: the same figures as the plain evaluation, no spread to speak of
    single = run_floor_texture_seeds(one)
    assert single["mean_correct"] == run_floor_texture(one)["mean_correct"]
    assert single["meta"]["n_seeds"] == 1


def test_signal_levels_weigh_what_the_templates_weigh():
    t = np.arange(800) / FS
    quiet = 2.5 + 0.01 * np.sin(2 * np.pi * 100 * t)
    loud = 2.5 + 0.1 * np.sin(2 * np.pi * 100 * t)
    X = np.stack([np.vstack([quiet, loud])] * 3)
    lv = signal_levels(X, FS)
    assert lv["rms_v"] == pytest.approx([0.01 / np.sqrt(2), 0.1 / np.sqrt(2)], rel=1e-3)
    assert lv["centroid_hz"] == pytest.approx([100.0, 100.0], abs=1.0)
    assert signal_levels(np.zeros((0, 2, 800)), FS)["rms_v"] is None


def test_a_baseline_adds_a_before_column_to_the_mean_correct_and_cross_condition_tables():
    """Issue 33, item 5: ``--baseline`` was accepted and ignored by this report."""
    res = run_floor_texture(_dataset())
    before = json.loads(json.dumps(res, default=lambda o: np.asarray(o).tolist()))
    before["mean_correct"] = {c: 0.25 for c in before["mean_correct"]}
    before["cross_condition"]["cw_on_ccw"] = 0.5
    before["meta"]["label"] = "docs/runs/old.json"
    text = markdown_floor_texture(res, {}, before)
    assert "*Before* is docs/runs/old.json (`--baseline`)." in text
    mean = text[text.index("## Mean correct") : text.index("## Cross-condition")]
    assert "| before |" in mean and mean.count("25 %") == 3
    cross = text[text.index("## Cross-condition") :]
    assert "| before |" in cross.splitlines()[2] and "50 %" in cross
    assert "before" not in markdown_floor_texture(res, {}, None)
