"""Each chapter-4 method's arithmetic against small hand-computed cases, and the
thesis presets' settings (docs/methods.md)."""

import numpy as np
import pytest
from sklearn.base import clone

from vibrissa.classify import (
    CHAPTER4_ONE_SET,
    FeatureRegressionClassifier,
    FrequencyTemplateClassifier,
    RecordingWindow,
    StationaryNaiveBayes,
    TimeTemplateClassifier,
    chapter4_classifiers,
)
from vibrissa.classify._feature import moving_average_shrinking

# ----------------------------------------------------------------- naive Bayes


def test_naive_bayes_log_likelihood_and_decision_by_hand():
    # 4 bins of width 1 over (0, 4); class A has values in bins 0,0,1,2; B in 2,3,3,3
    X = np.array([[0.5, 0.5, 1.5, 2.5], [2.5, 3.5, 3.5, 3.5]])[:, None, :]
    y = np.array([0, 1])
    floor = 1e-3
    nb = StationaryNaiveBayes(
        signal="raw", n_bins=4, value_range=(0.0, 4.0), smoothing_sigma=0.0, likelihood_floor=floor
    ).fit(X, y)
    la = np.log([0.5, 0.25, 0.25, floor])
    lb = np.log([floor, floor, 0.25, 0.75])
    assert np.allclose(nb.log_likelihood_[0, 0], la)
    assert np.allclose(nb.log_likelihood_[1, 0], lb)
    # test trial: values in bins 0, 2, 3, 3
    t = np.array([[[0.2, 2.2, 3.9, 3.1]]])
    scores = nb._joint_scores(t)
    assert scores[0, 0] == pytest.approx(la[0] + la[2] + 2 * la[3])  # -15.9
    assert scores[0, 1] == pytest.approx(lb[0] + lb[2] + 2 * lb[3])  # -8.87
    assert nb.predict(t)[0] == 1


def test_naive_bayes_smoothing_sigma_one_truncated_by_hand():
    # one count in bin 2 of 5; Gaussian sigma 1 truncated at 1 bin, renormalised
    X = np.array([[2.5], [0.5]])[:, None, :]
    nb = StationaryNaiveBayes(
        signal="raw",
        n_bins=5,
        value_range=(0.0, 5.0),
        smoothing_sigma=1.0,
        smoothing_radius_bins=1,
        likelihood_floor=1e-12,
    ).fit(X, [0, 1])
    w = np.exp(-0.5)
    expect = np.array([0, w, 1, w, 0]) / (1 + 2 * w)
    got = np.exp(nb.log_likelihood_[0, 0])
    assert np.allclose(got[1:4], expect[1:4])
    assert got[0] == pytest.approx(1e-12) and got[4] == pytest.approx(1e-12)


# ----------------------------------------------------------------- templates


def test_l1_template_distance_by_hand():
    T = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])[:, None, :]
    tt = TimeTemplateClassifier(cutoff_hz=None, distance="l1").fit(T, [10, 20])
    x = np.array([[[0.0, 0.0, 2.0]]])  # L1: 2 to class 10, 4 to class 20 (SSE: 4 vs 3)
    assert tt.predict(x)[0] == 10
    sse = TimeTemplateClassifier(cutoff_hz=None, distance="sse").fit(T, [10, 20])
    assert sse.predict(x)[0] == 20
    with pytest.raises(ValueError, match="distance"):
        TimeTemplateClassifier(distance="cosine").fit(T, [10, 20])


def test_abs_real_two_sided_spectrum_by_hand():
    n = 8
    t = np.arange(n)
    x = 1.0 + np.cos(2 * np.pi * t / n) + np.sin(2 * np.pi * 2 * t / n)
    f = FrequencyTemplateClassifier(
        sample_rate_hz=8.0, cutoff_hz=None, spectrum="abs_real", one_sided=False, zero_dc=True
    )
    spec = f._features(x[None, None, :])[0]
    # DFT: DC 8 (zeroed), cos -> Re 4 at k = 1 and 7, sin -> purely imaginary at k = 2, 6
    expect = np.zeros(n)
    expect[[1, 7]] = 4.0
    assert np.allclose(spec, expect)


# ----------------------------------------------------------------- feature


def test_matlab_smooth_span_five_by_hand():
    x = np.array([0.0, 0.0, 10.0, 0.0, 0.0, 0.0])
    got = moving_average_shrinking(x, 5)
    assert np.allclose(got, [0.0, 10 / 3, 2.0, 2.0, 0.0, 0.0])


def test_feature_training_width_floor_replaces_with_previous():
    fc = FeatureRegressionClassifier(min_duration_s=0.35)
    f2 = np.array([0.40, 0.30, 0.20, 0.50])
    labels = np.array([[1.0, 1.0], [2.0, 1.0], [3.0, 1.0], [4.0, 1.0]])
    assert fc._training_durations(f2, labels).tolist() == [0.40, 0.40, 0.40, 0.50]
    # order is by label (last column slowest), not by position
    shuffled = fc._training_durations(f2[::-1], labels[::-1])
    assert shuffled.tolist() == [0.50, 0.40, 0.40, 0.40]


# ----------------------------------------------------------------- windows


def _recording(onset: int, n: int = 1301) -> np.ndarray:
    x = np.full((2, n), 2.5)
    ramp = np.arange(n - onset) * 0.01
    x[0, onset:] += np.minimum(ramp + 0.101, 1.0)
    return x


def test_onset_window_puts_the_onset_at_its_100th_sample():
    X = np.stack([_recording(300), _recording(420)])
    w = RecordingWindow().fit(X).transform(X)
    assert w.shape == (2, 1, 750)
    for trial in w:
        above = np.flatnonzero(trial[0] - 2.5 > 0.1)
        assert above[0] == 99


def test_velocity_window_is_filtered_before_it_is_cut():
    X = np.stack([_recording(300)])
    rw = RecordingWindow(signal="velocity").fit(X)
    from vibrissa import signal as vsig

    full = vsig.causal_gaussian_velocity(X[:, :1], 1000.0)
    assert np.allclose(rw.transform(X)[0, 0], full[0, 0, 201:951])


def test_window_outside_the_recording_warns():
    # an onset 50 samples into the recording: the window starts 49 samples before it
    X = np.stack([_recording(50)])
    with pytest.warns(RuntimeWarning, match="outside"):
        RecordingWindow().fit(X).transform(X)


def test_recordings_shorter_than_the_window_are_refused():
    short = np.stack([_recording(50, n=300)])
    with pytest.raises(ValueError, match="300 samples, shorter than the window of 750"):
        RecordingWindow().fit(short)
    rw = RecordingWindow().fit(np.stack([_recording(300)]))
    with pytest.raises(ValueError, match="300 samples, shorter than the window of 750"):
        rw.transform(short)


def test_longer_recordings_give_the_same_window():
    X = np.stack([_recording(300), _recording(420)])
    rw = RecordingWindow().fit(X)
    longer = np.concatenate([X, np.repeat(X[..., -1:], 500, axis=-1)], axis=-1)
    np.testing.assert_array_equal(rw.transform(longer), rw.transform(X))
    with pytest.raises(ValueError, match="1 channels, but RecordingWindow is expecting 2"):
        rw.transform(X[:, :1])


# ----------------------------------------------------------------- presets


def test_thesis_presets_hold_the_authors_settings():
    clfs = chapter4_classifiers(1000.0, {"length_mm": 185.0})
    nb = clfs["naive_bayes_velocity"]
    assert nb.named_steps["window"].signal == "velocity"
    assert nb.named_steps["window"].velocity_sigma_samples == 15.0
    p = nb.named_steps["naive_bayes"].get_params()
    assert p["n_bins"] == 500 and p["value_range"] == (-100.0, 100.0)
    assert p["smoothing_sigma"] == 1.0 and p["smoothing_radius_bins"] == 10
    tmpl = clfs["template"]
    assert tmpl.named_steps["window"].lowpass_order == 10
    assert tmpl.named_steps["classifier"].distance == "l1"
    fr = clfs["frequency"].named_steps
    assert (fr["window"].offset_samples, fr["window"].n_samples) == (401, 250)
    assert fr["classifier"].spectrum == "abs_real" and fr["classifier"].zero_dc
    assert clfs["feature"].named_steps["classifier"].degree == 4
    assert set(CHAPTER4_ONE_SET) == {"template", "frequency", "feature"}
    for est in clfs.values():
        clone(est)
    with pytest.raises(ValueError, match="preset"):
        chapter4_classifiers(1000.0, {}, preset="matlab")


def test_thesis_presets_scale_their_windows_with_the_sample_rate():
    clfs = chapter4_classifiers(4000.0, {"length_mm": 185.0})
    w = clfs["naive_bayes_velocity"].named_steps["window"]
    assert (w.offset_samples, w.n_samples) == (-396, 3000)
    assert clfs["naive_bayes_velocity"].named_steps["naive_bayes"].value_range == (-400.0, 400.0)


def test_thesis_presets_fit_predict_pickle_on_recordings():
    import pickle

    rng = np.random.default_rng(0)
    whisker = {
        "length_mm": 185.0,
        "base_radius_mm": 1.0,
        "youngs_modulus_gpa": 2.35,
        "follicle_stiffness_nm_per_rad": 0.1,
        "hall_gain_v": 12.0,
    }
    X, y = [], []
    for _rep in range(3):
        for r in (90.0, 130.0, 170.0):
            for v in (50.0, 150.0):
                t = np.arange(1301) / 1000.0
                width = 0.2 * 100.0 / v
                pulse = (200.0 / r) * np.exp(-0.5 * ((t - 0.6) / width) ** 2)
                x = 2.5 + pulse + 0.002 * rng.standard_normal(t.size)
                X.append(np.stack([x, 2.5 + 0.1 * pulse]))
                y.append([r, v])
    X, y = np.array(X), np.array(y)
    for name, est in chapter4_classifiers(1000.0, whisker).items():
        if name == "static_beam_fitted":
            est.set_params(classifier__param_grid={"youngs_modulus_gpa": [2.35]})
        est.fit(X, y)
        pred = est.predict(X)
        assert pred.shape == y.shape, name
        again = pickle.loads(pickle.dumps(est)).predict(X)
        np.testing.assert_array_equal(pred, again)
