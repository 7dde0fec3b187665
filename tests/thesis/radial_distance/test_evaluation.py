"""Tests of chapter 4's evaluation: splits, subsets, the chapter-4 run and its JSON."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from sklearn.base import BaseEstimator, ClassifierMixin

from vibrissa.classify import TimeTemplateClassifier
from vibrissa.thesis.radial_distance import evaluation as protocol

RADII = (80.0, 90.0, 100.0, 110.0)
SPEEDS = (36.0, 72.0, 108.0)


def make_grid_dataset(
    n_sets: int = 4,
    radii=RADII,
    speeds=SPEEDS,
    n_time: int = 40,
    noise: float = 0.0,
    seed=0,
    t_peak: float = 0.02,
) -> xr.Dataset:
    """Tiny chapter-4-like dataset: each set one complete radius x speed grid."""
    rng = np.random.default_rng(seed)
    t = np.arange(n_time) / 1000.0 + 0.02 - t_peak
    sig, r_, s_, set_ = [], [], [], []
    for k in range(n_sets):
        for r in radii:
            for s in speeds:
                amp = 100.0 / r
                width = 0.004 * 72.0 / s
                pulse = amp * np.exp(-0.5 * ((t - 0.02) / width) ** 2)
                x = 2.5 + pulse + noise * rng.standard_normal(n_time)
                y = 2.5 + 0.2 * pulse
                sig.append(np.stack([x, y]))
                r_.append(r)
                s_.append(s)
                set_.append(k)
    return xr.Dataset(
        {"signal": (("trial", "channel", "time"), np.array(sig), {"units": "V"})},
        coords={
            "channel": ["x", "y"],
            "time": t - 0.02,
            "radial_distance_mm": ("trial", np.array(r_)),
            "speed_mm_s": ("trial", np.array(s_)),
            "set": ("trial", np.array(set_)),
        },
        attrs={"sample_rate_hz": 1000.0, "whisker": "{}"},
    )


class Centroid(ClassifierMixin, BaseEstimator):
    """Stand-in: nearest centroid of flattened trials over joint classes."""

    def fit(self, X, y):
        X = np.asarray(X).reshape(len(X), -1)
        self.classes_, idx = np.unique(np.asarray(y, dtype=float), axis=0, return_inverse=True)
        idx = np.asarray(idx).reshape(-1)
        self.centroids_ = np.stack([X[idx == i].mean(axis=0) for i in range(len(self.classes_))])
        return self

    def predict(self, X):
        X = np.asarray(X).reshape(len(X), -1)
        d = ((X[:, None, :] - self.centroids_[None]) ** 2).sum(-1)
        return self.classes_[np.argmin(d, axis=1)]


class Constant(ClassifierMixin, BaseEstimator):
    """Stand-in: always the given row."""

    def __init__(self, row=(100.0, 72.0)):
        self.row = row

    def fit(self, X, y):
        self.row_ = np.asarray(self.row, dtype=float)
        return self

    def predict(self, X):
        return np.tile(self.row_, (len(X), 1))


class RadiusOnly(Centroid):
    """Stand-in for the static beam: radius right, speed NaN."""

    def predict(self, X):
        p = super().predict(X).copy()
        p[:, 1] = np.nan
        return p


def _without_times(x):
    """A result without its wall times (the only values that differ between runs)."""
    if isinstance(x, dict):
        return {k: _without_times(v) for k, v in x.items() if not k.endswith("_seconds")}
    if isinstance(x, list):
        return [_without_times(v) for v in x]
    return x


@pytest.fixture(scope="module")
def ds() -> xr.Dataset:
    return make_grid_dataset()


def test_split_assigns_distinct_complete_sets(ds) -> None:
    for seed in range(10):
        sp = protocol.split_sets(ds, seed)
        assert sp.train_set != sp.test_set
        assert not set(sp.train_index) & set(sp.test_index)
        for idx, name in ((sp.train_index, sp.train_set), (sp.test_index, sp.test_set)):
            assert np.all(ds["set"].values[idx] == name)
            assert len(idx) == len(RADII) * len(SPEEDS)
            r, v = ds["radial_distance_mm"].values[idx], ds["speed_mm_s"].values[idx]
            combos = set(zip(r, v, strict=True))
            assert len(combos) == len(RADII) * len(SPEEDS)
    assert protocol.split_sets(ds, 3).to_dict() == protocol.split_sets(ds, 3).to_dict()
    seen = {
        (protocol.split_sets(ds, s).train_set, protocol.split_sets(ds, s).test_set)
        for s in range(40)
    }
    assert len(seen) > 3  # the assignment really is drawn


def test_split_explicit_and_bad(ds) -> None:
    sp = protocol.split_sets(ds, train_set=2, test_set=0)
    assert (sp.train_set, sp.test_set, sp.seed) == (2, 0, None)
    with pytest.raises(ValueError, match="differ"):
        protocol.split_sets(ds, train_set=1, test_set=1)
    with pytest.raises(ValueError, match="not a set"):
        protocol.split_sets(ds, train_set=1, test_set=9)
    with pytest.raises(ValueError, match="both"):
        protocol.split_sets(ds, train_set=1)


def test_subsample_deterministic_nested_and_sized() -> None:
    n = 2626
    a = protocol.subsample_indices(n, 0.8, 7)
    assert np.array_equal(a, protocol.subsample_indices(n, 0.8, 7))
    assert not np.array_equal(a, protocol.subsample_indices(n, 0.8, 8))
    assert len(a) == round(0.8 * n) and len(np.unique(a)) == len(a)
    assert a.min() >= 0 and a.max() < n
    assert len(protocol.subsample_indices(n, 0.05, 7)) == round(0.05 * n)
    assert set(protocol.subsample_indices(n, 0.05, 7)) <= set(a)  # heads of one permutation
    assert len(protocol.subsample_indices(n, 1.0, 1)) == n
    assert len(protocol.subsample_indices(10, 0.01, 1)) == 1
    for bad in (0.0, -0.1, 1.5, float("nan"), "x"):
        with pytest.raises(ValueError, match="fraction"):
            protocol.subsample_indices(n, bad, 0)
    assert protocol.fraction_key(0.8) == "0.8" and protocol.fraction_key(0.05) == "0.05"


def test_bad_datasets_raise_clear_errors(ds) -> None:
    with pytest.raises(ValueError, match="speed_mm_s"):
        protocol.check_dataset(ds.drop_vars("speed_mm_s"))
    with pytest.raises(ValueError, match="'set'"):
        protocol.check_dataset(ds.drop_vars("set"))
    with pytest.raises(ValueError, match="at least 2 recorded sets"):
        protocol.check_dataset(make_grid_dataset(n_sets=1))
    with pytest.raises(ValueError, match="signal"):
        protocol.check_dataset(ds.drop_vars("signal"))
    incomplete = ds.isel(trial=np.arange(1, ds.sizes["trial"]))
    with pytest.raises(ValueError, match="not a complete grid"):
        protocol.check_dataset(incomplete)
    protocol.check_dataset(incomplete, require_complete=False)
    with pytest.raises(TypeError):
        protocol.check_dataset(np.zeros(3))


def test_run_chapter4_perfect_constant_and_radius_only(ds) -> None:
    calls = []
    res = protocol.run_chapter4(
        ds,
        {"perfect": Centroid(), "constant": Constant(), "static_beam_stand_in": RadiusOnly()},
        fractions=(1.0, 0.5),
        n_seeds=2,
        seed=1,
        progress=lambda d, t, msg: calls.append((d, t, msg)),
    )
    json.dumps(res, allow_nan=False)  # serialises, no NaN
    assert calls[-1][0] == calls[-1][1] == 3 * (1 + 2 * 2)
    p = res["classifiers"]["perfect"]
    for par in ("radius_mm", "speed_mm_s"):
        assert p[par]["mean"] == 0 and p[par]["std"] == 0
        assert p[par]["exact_hit"] == 1 and p[par]["kappa"] == 1
    assert p["joint"] == {"exact_hit": 1.0, "kappa": 1.0}
    assert p["classify_seconds"] >= 0 and p["fit_seconds"] >= 0
    c = res["classifiers"]["constant"]
    r_err = np.array(RADII) - 100.0
    assert c["radius_mm"]["mean"] == pytest.approx(-r_err.mean())
    assert c["radius_mm"]["std"] == pytest.approx(np.std(np.repeat(r_err, 3), ddof=1))
    assert c["radius_mm"]["exact_hit"] == pytest.approx(1 / len(RADII))
    assert c["radius_mm"]["kappa"] == pytest.approx(0.0)
    assert c["speed_mm_s"]["exact_hit"] == pytest.approx(1 / 3)
    s = res["classifiers"]["static_beam_stand_in"]
    assert s["speed_mm_s"] is None and s["joint"] is None and s["radius_only"]
    assert [e["speed_mm_s"] for e in s["radius_error_by_speed"]] == list(SPEEDS)
    assert all(e["mean"] == 0 and e["n"] == len(RADII) for e in s["radius_error_by_speed"])
    # contract keys
    assert set(res["training_fractions"]) == {"1.0", "0.5"}
    for frac in res["training_fractions"].values():
        assert set(frac) == {"perfect", "constant", "static_beam_stand_in"}
        for name, entry in frac.items():
            assert set(entry["radius_mm"]) >= {"mean", "std"}
            assert "classify_seconds" in entry and len(entry["per_seed"]) == 2
            assert (entry["speed_mm_s"] is None) == (name == "static_beam_stand_in")
    half = res["training_fractions"]["0.5"]["perfect"]
    assert half["n_train"] == 6
    assert [r["seed"] for r in half["per_seed"]] == [[1, 0], [1, 1]]
    full = res["training_fractions"]["1.0"]["perfect"]
    assert full["radius_mm"]["mean"] == 0 and full["radius_mm"]["kappa"] == 1
    sp = res["meta"]["split"]
    assert sp["train_set"] != sp["test_set"] and sp["n_test"] == 12
    pr = res["predictions"]
    assert len(pr["radius_mm_true"]) == 12
    assert pr["classifiers"]["static_beam_stand_in"]["speed_mm_s"] is None


def test_run_chapter4_deterministic_and_validates(ds) -> None:
    kw = {"fractions": (0.5,), "n_seeds": 2, "seed": 4}
    a = protocol.run_chapter4(ds, {"c": Centroid()}, **kw)
    b = protocol.run_chapter4(ds, {"c": Centroid()}, **kw)
    assert _without_times(a) == _without_times(b)
    for bad in ((0.0,), (1.2,), (0.5, 0.5)):
        with pytest.raises(ValueError, match="fraction"):
            protocol.run_chapter4(ds, {"c": Centroid()}, fractions=bad)
    with pytest.raises(ValueError, match="n_seeds"):
        protocol.run_chapter4(ds, {"c": Centroid()}, n_seeds=0)
    with pytest.raises(ValueError, match="classifiers"):
        protocol.run_chapter4(ds, {})
    with pytest.raises(ValueError, match="at least 2"):
        protocol.run_chapter4(make_grid_dataset(n_sets=1), {"c": Centroid()})


def test_fit_failure_names_classifier(ds) -> None:
    class Broken(Centroid):
        def fit(self, X, y):
            raise ValueError("boom")

    with pytest.raises(ValueError, match="'broken' failed to fit: boom"):
        protocol.run_chapter4(ds, {"broken": Broken()}, fractions=())


def test_rich_progress_is_advanced(ds) -> None:
    from rich.progress import Progress

    with Progress(disable=True) as prog:
        protocol.run_chapter4(ds, {"c": Centroid()}, fractions=(0.5,), n_seeds=1, progress=prog)
        task = prog.tasks[0]
        assert task.completed == task.total == 2


# ------------------------------------------------------- the author's split (issue 10)
class CountTrials(Centroid):
    """Centroid that records how many trials it was fitted on."""

    def fit(self, X, y):
        self.n_fit_ = len(X)
        return super().fit(X, y)


def test_pooled_training_sets_and_per_classifier_sets(ds) -> None:
    split = protocol.split_sets(ds, train_set=[1, 2, 3], test_set=0)
    assert split.train_set == [1, 2, 3] and split.test_set == 0
    assert len(split.train_index) == 3 * len(RADII) * len(SPEEDS)
    assert not set(split.train_index) & set(split.test_index)
    with pytest.raises(ValueError, match="also a training set"):
        protocol.split_sets(ds, train_set=[0, 1], test_set=0)
    with pytest.raises(ValueError, match="repeats"):
        protocol.split_sets(ds, train_set=[1, 1], test_set=0)
    res = protocol.run_chapter4(
        ds,
        {"pooled": CountTrials(), "one": CountTrials()},
        fractions=(0.5,),
        n_seeds=2,
        train_set=[1, 2, 3],
        test_set=0,
        classifier_train_sets={"one": [2]},
    )
    n_grid = len(RADII) * len(SPEEDS)
    assert res["classifiers"]["pooled"]["n_train"] == 3 * n_grid
    assert res["classifiers"]["one"]["n_train"] == n_grid
    assert res["classifiers"]["one"]["train_sets"] == [2]
    # a reduced set keeps whole classes: all three trials of each kept class
    half = res["training_fractions"]["0.5"]
    assert half["pooled"]["n_train"] == 3 * round(0.5 * n_grid)
    assert half["one"]["n_train"] == round(0.5 * n_grid)
    with pytest.raises(ValueError, match="subset"):
        protocol.run_chapter4(
            ds,
            {"one": Centroid()},
            fractions=(),
            train_set=[1, 2],
            test_set=0,
            classifier_train_sets={"one": [3]},
        )
    with pytest.raises(ValueError, match="unknown"):
        protocol.run_chapter4(
            ds,
            {"one": Centroid()},
            fractions=(),
            train_set=[1, 2],
            test_set=0,
            classifier_train_sets={"two": [1]},
        )


def test_subsample_combinations_keeps_the_same_classes_for_one_and_three_sets() -> None:
    y1 = np.array([[r, s] for s in SPEEDS for r in RADII], dtype=float)
    y3 = np.concatenate([y1, y1, y1])
    a = protocol.subsample_combinations(y1, 0.5, [0, 1])
    b = protocol.subsample_combinations(y3, 0.5, [0, 1])
    kept1 = {tuple(r) for r in y1[a]}
    kept3 = {tuple(r) for r in y3[b]}
    assert kept1 == kept3 and len(b) == 3 * len(a)


# ------------------------------------------------------- sample rates (issue 13, finding 9)
def test_classifiers_built_for_another_rate_are_refused_before_any_fit(ds) -> None:
    from vibrissa.classify import chapter4_classifiers

    ds4k = ds.assign_attrs(sample_rate_hz=4000.0)
    steps = []
    # the evaluation does not adapt classifiers to the dataset: one built for 1 kHz
    # is refused on 4 kHz data, before any classifier (even a stand-in) is fitted
    clfs = {"c": Centroid(), **chapter4_classifiers(1000.0, {})}
    with pytest.raises(
        ValueError,
        match="classifier 'static_beam_measured' does not fit the "
        "dataset: step 'window': RecordingWindow is built for "
        "sample_rate_hz=1000 Hz, but the data are sampled at "
        "4000 Hz",
    ):
        protocol.run_chapter4(ds4k, clfs, fractions=(), progress=lambda *a: steps.append(a))
    assert steps == []
    with pytest.raises(
        ValueError,
        match="classifier 'template' does not fit the dataset: "
        "TimeTemplateClassifier is built for "
        "sample_rate_hz=1000 Hz, but the data are sampled "
        "at 4000 Hz",
    ):
        protocol.run_chapter4(ds4k, {"template": TimeTemplateClassifier()}, fractions=())


def test_classifiers_built_from_the_dataset_run_at_its_rate(ds) -> None:
    ds4k = ds.assign_attrs(sample_rate_hz=4000.0)
    clf = TimeTemplateClassifier.from_dataset(ds4k, cutoff_hz=400.0)
    res = protocol.run_chapter4(ds4k, {"template": clf}, fractions=(0.5,), n_seeds=1)
    assert res["meta"]["sample_rate_hz"] == 4000.0
    assert res["classifiers"]["template"]["radius_mm"]["exact_hit"] == 1.0
    with pytest.raises(ValueError, match="no attribute 'sample_rate_hz'"):
        protocol.run_chapter4(ds.drop_attrs(), {"template": clf}, fractions=())


# ------------------------------------------------------- workers and shared windows (issue 14)
WHISKER = {
    "length_mm": 185.0,
    "base_radius_mm": 1.0,
    "youngs_modulus_gpa": 2.35,
    "follicle_stiffness_nm_per_rad": 0.1,
    "hall_gain_v": 12.0,
    "hall_offset_v": 2.5,
}


def test_thesis_presets_give_the_same_results_with_any_workers(monkeypatch) -> None:
    from vibrissa.classify import CHAPTER4_ONE_SET, chapter4_classifiers

    # recordings as long as the simulated ones (1.3 s, contact 0.6 s in), with noise
    ds = make_grid_dataset(n_time=1301, t_peak=0.6, noise=0.003, seed=2)
    clfs = chapter4_classifiers(1000.0, WHISKER)
    kw = {
        "fractions": (0.5, 0.25),
        "n_seeds": 2,
        "seed": 1,
        "train_set": [1, 2, 3],
        "test_set": 0,
        "classifier_train_sets": {k: [2] for k in CHAPTER4_ONE_SET},
    }
    one = protocol.run_chapter4(ds, clfs, workers=1, **kw)
    two = protocol.run_chapter4(ds, clfs, workers=2, **kw)
    assert _without_times(one) == _without_times(two)
    assert set(one["training_fractions"]["0.25"]) == set(clfs)
    # the reduced sets' fits on the shared windows are the whole pipelines' fits
    key, window, rest = protocol.window_head(clfs["template"])
    assert key.startswith("window:") and rest is clfs["template"].steps[1][1]
    assert protocol.window_head(clfs["template"])[0] != protocol.window_head(clfs["frequency"])[0]
    assert (
        protocol.window_head(clfs["feature"])[0] == protocol.window_head(clfs["naive_bayes_raw"])[0]
    )
    monkeypatch.setattr(protocol, "window_head", lambda est: (None, None, None))
    whole = protocol.run_chapter4(ds, clfs, workers=1, **kw)
    assert _without_times(whole) == _without_times(one)


def test_workers_is_checked(ds) -> None:
    with pytest.raises(ValueError, match="workers must be a positive integer"):
        protocol.run_chapter4(ds, {"c": Centroid()}, fractions=(), workers=0)
