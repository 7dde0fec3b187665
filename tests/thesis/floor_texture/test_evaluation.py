"""The Roomba evaluation (thesis 6.2.1-6.2.2) on hand-made recordings, and the thesis' tables."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from vibrissa.thesis.floor_texture.evaluation import (
    condition_windows,
    confusion_matrix,
    mean_correct,
    run_floor_texture,
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
