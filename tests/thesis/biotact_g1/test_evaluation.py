"""Thesis 6.4.4 hit rates against training whisks, on synthetic G1 datasets."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.thesis.biotact_g1.evaluation import (
    FWHM_PER_SIGMA,
    evaluate_g1_sessions,
    g1_classifiers,
    hit_rate_curves,
    whisk_statistics,
)
from vibrissa.thesis.biotact_g1.protocol import BiotactProtocol


def _dataset(n_whisks: int = 4, separable: bool = True, seed: int = 0, n_seeds: int = 1):
    p = BiotactProtocol(
        textures=("plastic", "p180"), distances_mm=(5.0, 15.0), n_whisks=n_whisks, n_seeds=n_seeds
    )
    rng = np.random.default_rng(seed)
    specs = p.trials()
    n, m = len(specs), p.n_samples
    sig = 2.5 + 0.01 * rng.standard_normal((n, 12, m))
    if separable:
        for k, s in enumerate(specs):
            sig[k, 0::2] -= 0.05 * s.distance_mm  # distance: the x deflection
            sig[k, 1::2] += 0.2 * (s.texture == "p180")  # texture: the y channels
    results = {
        "signal": sig,
        "angle_deg": np.zeros((n, 2, m)),
        "gating": np.zeros((n, 2, m)),
        "force_n": np.zeros((n, 6, m)),
        "saturated": np.zeros(n, dtype=bool),
        "dt_s": np.full(n, 2.5e-4),
    }
    results["force_n"][:, :, 100:300] = 0.01
    return p.build_dataset(results)


def test_curves_follow_the_validation_scheme_of_6_4_4():
    res = hit_rate_curves(_dataset(n_whisks=4))
    hit = res["hit_rate"]
    assert list(hit) == ["unmodulated", "rcp7", "rcp9"]
    for s in hit:
        assert set(hit[s]) == {"naive_bayes", "template"}
        for c in hit[s]:
            assert set(hit[s][c]) == {"joint", "texture", "distance"}
            for t, rates in hit[s][c].items():
                assert len(rates) == 8
                # trained on whisks 1..n of every class, validated on the other 4 - n
                assert rates[:3] == [1.0, 1.0, 1.0], (s, c, t)
                assert rates[3:] == [None] * 5
        # four classes: (4 - n) validation whisks each
        assert res["n_validation"][s] == [12, 8, 4, 0, 0, 0, 0, 0]


def test_without_class_information_the_hit_rate_is_near_chance():
    res = hit_rate_curves(_dataset(n_whisks=12, separable=False))
    rates = [r for s in res["hit_rate"].values() for c in s.values() for r in c["joint"]]
    assert np.mean(rates) < 0.5  # four classes: chance is 0.25


def test_naive_bayes_reads_the_gaussian_width_as_its_fwhm():
    nb = g1_classifiers(2000.0)["naive_bayes"]()
    assert nb.smoothing_sigma == pytest.approx(5.0 / 2.3548, rel=1e-4)
    assert FWHM_PER_SIGMA == pytest.approx(2.35482, rel=1e-5)
    assert nb.n_bins == 100 and nb.value_range is None and nb.signal == "raw"
    tpl = g1_classifiers(2000.0)["template"]()
    assert tpl.templates == "mean" and tpl.distance == "sse" and tpl.cutoff_hz is None


def test_whisk_statistics_per_strategy():
    st = whisk_statistics(_dataset())
    assert list(st) == ["unmodulated", "rcp7", "rcp9"]
    for v in st.values():
        assert v["contact_time_s"] == pytest.approx(200 / 2000.0)
        assert v["max_z"] == 0.0 and v["saturated_whisks"] == 0
        assert v["peak_deflection_v"] > 0


def test_naive_bayes_alone_with_robust_bins():
    res = hit_rate_curves(_dataset(n_whisks=3), classifiers=("naive_bayes",), value_range="robust")
    for curves in res["hit_rate"].values():
        assert list(curves) == ["naive_bayes"]
        assert curves["naive_bayes"]["joint"][:2] == [1.0, 1.0]


def test_sessions_give_the_mean_and_the_spread_of_every_figure():
    ds = _dataset(n_whisks=4, n_seeds=3)
    # the last session carries no class information: its hit rates fall to chance
    last = np.asarray(ds["session_seed"].values) == 2
    ds["signal"].values[last] = 2.5 + 0.01 * np.random.default_rng(5).standard_normal(
        ds["signal"].values[last].shape
    )
    res = evaluate_g1_sessions(ds)
    assert res["meta"]["n_seeds"] == 3 and res["meta"]["seeds"] == [0, 1, 2]
    assert res["meta"]["n_trials"] == 3 * 3 * 4 * 4
    leaf = res["spread"]["hit_rate"]["rcp7"]["naive_bayes"]["joint"][0]
    assert leaf["n"] == 3 and leaf["values"][:2] == [1.0, 1.0] and leaf["values"][2] < 1.0
    assert res["hit_rate"]["rcp7"]["naive_bayes"]["joint"][0] == pytest.approx(leaf["mean"])
    assert res["hit_rate"]["rcp7"]["naive_bayes"]["joint"][3] is None  # nothing to validate
    # the ledger's keys: numbers are the means over the sessions
    chk = res["checks"]
    for key in ("rcp7_nb_joint_mean_1_2", "unmodulated_nb_joint_mean_1_2"):
        assert chk[key] == pytest.approx(res["spread"]["checks"][key]["mean"])
    # a boolean holds only if it holds in every session; its fraction beside it
    frac = chk["rcp7_beats_unmodulated_nb_joint_1_2_whisks_fraction"]
    per = res["spread"]["checks"]["rcp7_beats_unmodulated_nb_joint_1_2_whisks"]["values"]
    assert frac == pytest.approx(np.mean(per))
    assert chk["rcp7_beats_unmodulated_nb_joint_1_2_whisks"] == (frac == 1.0)
    assert set(res["spread"]["whisks"]["rcp9"]) >= {"peak_spread", "contact_time_s"}
