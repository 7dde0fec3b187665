"""Chapter-5 classifiers on small synthetic trials whose answers are known."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.pipeline import Pipeline

from vibrissa.classify import (
    TEXTURE_CODES,
    FeaturePolynomialClassifier,
    JointLikelihoodNaiveBayes,
    SequentialEvidenceClassifier,
    SignalTransform,
    SpeedFirstClassifier,
    StationaryNaiveBayes,
    accumulate_evidence,
    chapter5_classifiers,
    chapter5_features,
    decode_texture,
    draw_sequences,
    encode_texture,
    resonance_hz,
)
from vibrissa.classify._chapter5 import joint_log_scores

FS = 4000.0
N_T = 800


def make_ch5(reps: int = 2, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Peak-aligned pulses: amplitude ~ speed, rise ~ angle, a texture-coded vibration."""
    rng = np.random.default_rng(seed)
    t = (np.arange(N_T) - N_T // 2) / FS
    X, y = [], []
    for _ in range(reps):
        for a in (20.0, 60.0):
            for v in (20.0, 80.0):
                for tex in (0, 1, 2):
                    amp = 0.005 * v
                    rise = 0.01 + 0.0005 * a
                    pulse = np.where(
                        t < 0, np.exp(-0.5 * (t / rise) ** 2), np.exp(-0.5 * (t / 0.02) ** 2)
                    )
                    vib = 0.02 * amp * np.sin(2 * np.pi * (150 + 150 * tex) * t) * pulse
                    x = 2.5 + amp * pulse + vib
                    X.append(np.stack([x, 2.5 + 0.1 * vib]))
                    y.append((a, v, tex))
    X = np.asarray(X) + 2e-4 * rng.standard_normal((len(X), 2, N_T))
    return X, np.asarray(y, dtype=float)


@pytest.fixture(scope="module")
def data():
    return make_ch5(reps=2, seed=0), make_ch5(reps=1, seed=1)


def _estimators() -> dict:
    clfs = chapter5_classifiers(FS, notch_hz=13.0)
    clfs["minirocket"].set_params(pool=4, n_dilations=3)
    return clfs


def test_texture_codes_roundtrip():
    assert list(TEXTURE_CODES) == ["aluminium", "p600", "p180", "p80"]
    names = np.array(["p80", "aluminium", "p180"])
    assert encode_texture(names).tolist() == [3, 0, 2]
    assert decode_texture([3.0, 0.0, 2.0]).tolist() == names.tolist()
    with pytest.raises(ValueError, match="unknown texture"):
        encode_texture(["velvet"])


def test_resonance_from_whisker_json():
    assert resonance_hz('{"natural_frequencies_hz": [13.1, 46.3]}') == pytest.approx(13.1)
    with pytest.raises(ValueError, match="natural_frequencies_hz"):
        resonance_hz({})


def test_modulation_features_of_known_spectrum():
    n = 4000  # 1 Hz bins at 4 kHz
    t = np.arange(n) / FS
    x = (
        2.5
        + 0.3 * np.sin(2 * np.pi * 100 * t)
        + 0.1 * np.sin(2 * np.pi * 3 * t)
        + 0.2 * np.sin(2 * np.pi * 1500 * t)
    )
    X = np.stack([x, x])[None]
    f = chapter5_features(X, FS, notch_hz=None, rest_v=2.5)[0]
    assert f[2] == pytest.approx(100.0)  # f3: the 3 Hz and 1.5 kHz lines are outside the band
    assert f[3] == pytest.approx(0.3 * n / 2, rel=1e-6)  # f4
    assert f[4] == pytest.approx(0.3 * n / 2, rel=1e-6)  # f5: one exact line in 6 Hz-1 kHz
    # f1 peak magnitude and f2 slope to peak
    assert f[0] == pytest.approx(np.max(np.abs(x - 2.5)))
    assert f[1] > 0


def test_feature_polynomial_recovers_speed(data):
    (X, y), (Xt, yt) = data
    clf = FeaturePolynomialClassifier(sample_rate_hz=FS, notch_hz=13.0).fit(X, y)
    assert np.all(clf.predict(Xt)[:, 1] == yt[:, 1])
    est = clf.predict_targets(Xt)
    assert est.shape == (len(Xt), 3)


def test_every_estimator_clones_pickles_and_agrees(data):
    (X, y), (Xt, _) = data
    for name, est in _estimators().items():
        c = clone(est).fit(X, y)
        p = c.predict(Xt)
        assert p.shape == (len(Xt), 3), name
        c2 = pickle.loads(pickle.dumps(c))
        np.testing.assert_array_equal(c2.predict(Xt), p)
        proba = c.predict_proba(Xt)
        np.testing.assert_allclose(proba.sum(axis=1), 1.0, atol=1e-9)
        np.testing.assert_array_equal(c.classes_[np.argmax(proba, axis=1)], p, err_msg=name)


def test_speed_first_restriction_is_exact(data):
    (X, y), (Xt, _) = data
    nb = StationaryNaiveBayes(signal="velocity", sample_rate_hz=FS)
    sp = FeaturePolynomialClassifier(sample_rate_hz=FS, features=(("f1",),), degree=2)
    clf = SpeedFirstClassifier(speed_estimator=sp, estimator=nb).fit(X, y)
    v = clf.predict_speed(Xt)
    pred = clf.predict(Xt)
    np.testing.assert_array_equal(pred[:, 1], v)
    # brute force: the best naive Bayes class among those of the predicted speed
    full = clone(nb).fit(X, y)
    scores = joint_log_scores(full, Xt)
    for i in range(len(Xt)):
        allowed = np.flatnonzero(full.classes_[:, 1] == v[i])
        best = allowed[np.argmax(scores[i, allowed])]
        np.testing.assert_array_equal(pred[i], full.classes_[best])


def test_speed_first_single_speed_is_fixed(data):
    (X, y), _ = data
    m = y[:, 1] == 20.0
    clf = SpeedFirstClassifier().fit(X[m], y[m])
    assert clf.speed_estimator_ is None
    assert np.all(clf.predict(X[m])[:, 1] == 20.0)


def test_joint_likelihood_equals_brute_force(data):
    (X, y), (Xt, _) = data
    X, y, Xt = X[:, :, :200], y, Xt[:3, :, :200]
    ts = SignalTransform("lowpass", sample_rate_hz=FS, downsample=10)
    clf = JointLikelihoodNaiveBayes(template_signal=ts, sample_rate_hz=FS, template_weight=0.5).fit(
        X, y
    )
    h = clf.histogram_
    from vibrissa import signal as vsig

    Vt = vsig.velocity(Xt, FS, sigma_samples=h.derivative_sigma_samples)
    St = clf.template_signal_.transform(Xt)
    S = clf.template_signal_.transform(X)
    yi = np.unique(y, axis=0, return_inverse=True)[1].ravel()
    brute = np.zeros((len(Xt), len(clf.classes_)))
    for i in range(len(Xt)):
        for c in range(len(clf.classes_)):
            ll = 0.0
            for ch in range(X.shape[1]):
                edges = h.bin_edges_[ch]
                nb = len(edges) - 1
                for val in Vt[i, ch]:
                    b = int(
                        np.clip(np.floor((val - edges[0]) / (edges[-1] - edges[0]) * nb), 0, nb - 1)
                    )
                    ll += h.log_likelihood_[c, ch, b]
            # Gaussian template likelihood with the pooled within-class variance
            resid = np.concatenate(
                [S[yi == k] - S[yi == k].mean(axis=0) for k in range(len(clf.classes_))]
            )
            var = (resid**2).sum(axis=(0, 2)) / ((len(S) - len(clf.classes_)) * S.shape[2])
            mean = S[yi == c].mean(axis=0)
            tl = np.sum(
                -0.5 * np.log(2 * np.pi * var)[:, None] - 0.5 * (St[i] - mean) ** 2 / var[:, None]
            )
            brute[i, c] = ll + 0.5 * tl
    np.testing.assert_allclose(clf._joint_scores(Xt), brute, rtol=1e-8, atol=1e-6)


def test_sequential_accumulation_improves_accuracy():
    rng = np.random.default_rng(0)
    n, k, c = 400, 10, 4
    truth = rng.integers(0, c, n)
    # independent noisy contacts: the true class gets a small mean advantage
    logits = rng.normal(0, 1, (n, k, c))
    logits[np.arange(n), :, truth] += 0.6
    lp = logits - np.log(np.exp(logits).sum(axis=2, keepdims=True))
    acc = [np.mean(accumulate_evidence(lp[:, :m], threshold=1.0)[0] == truth) for m in (1, 3, 10)]
    assert acc[0] < acc[1] < acc[2]
    assert acc[2] > 0.8
    d, used, post = accumulate_evidence(lp, threshold=0.9)
    assert used.min() >= 1 and used.max() <= k
    np.testing.assert_allclose(post.sum(axis=1), 1.0)


def test_sequential_classifier_on_trials(data):
    (X, y), (Xt, yt) = data
    seq = SequentialEvidenceClassifier(
        StationaryNaiveBayes(signal="velocity", sample_rate_hz=FS), threshold=0.999
    ).fit(X, y)
    np.testing.assert_array_equal(seq.classes_, [0.0, 1.0, 2.0])
    s = draw_sequences(yt[:, 2], 3, seed=0)
    assert s.shape == (len(yt), 3)
    assert np.all(yt[s, 2] == yt[:, 2][:, None])
    pred, used = seq.predict_sequences(Xt, s)
    assert pred.shape == used.shape == (len(yt),)
    p1 = seq.predict_proba(Xt)
    np.testing.assert_array_equal(seq.classes_[np.argmax(p1, axis=1)], seq.predict(Xt))


@pytest.mark.parametrize(
    "name",
    [
        "template_lowpass",
        "feature",
        "combined",
        "joint_likelihood_nb",
        "minirocket",
        "naive_bayes_acceleration",
    ],
)
def test_bad_input_errors(data, name):
    (X, y), _ = data
    est = clone(_estimators()[name])
    with pytest.raises((NotFittedError, AttributeError)):
        est.predict(X)
    with pytest.raises(ValueError):
        clone(est).fit(X, np.tile(y[:1], (len(y), 1)))  # a single class
    bad = X.copy()
    bad[0, 0, 5] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        clone(est).fit(bad, y)
    fitted = clone(est).fit(X, y)
    with pytest.raises(ValueError, match="channels"):
        fitted.predict(X[:, :1])
    with pytest.raises(ValueError, match="timepoints"):
        fitted.predict(X[:, :, :-40])


def test_signal_transform_is_a_pipeline_step(data):
    (X, y), _ = data
    st = SignalTransform("highpass", sample_rate_hz=FS, notch_hz=13.0)
    out = st.fit(X).transform(X)
    assert out.shape == X.shape
    assert abs(out.mean()) < 1e-3  # the 2.5 V rest level is gone
    with pytest.raises(ValueError, match="kind"):
        SignalTransform("bandstop").fit(X)
    pipe = _estimators()["template_highpass"]
    assert isinstance(pipe, Pipeline)


def test_minirocket_heads_and_parameters(data):
    """Both heads learn the synthetic targets; posteriors are normalised; bad settings named."""
    from vibrissa.classify import MiniRocketClassifier

    (X, y), (Xt, yt) = data
    for head in ("logistic", "ridge"):
        m = MiniRocketClassifier(pool=4, n_dilations=3, head=head).fit(X, y)
        p = m.predict_proba(Xt)
        np.testing.assert_allclose(p.sum(axis=1), 1.0)
        pred = m.predict(Xt)
        # speed (amplitude x4) is easy for random-kernel PPV features
        assert np.mean(pred[:, 1] == yt[:, 1]) >= 0.9, head
        assert type(m.heads_[1]).__name__ == (
            "LogisticRegression" if head == "logistic" else "RidgeClassifierCV"
        )
    for col in (2, 1):  # 3 textures (multinomial), 2 speeds (binary)
        m = MiniRocketClassifier(pool=4, n_dilations=3).fit(X, y[:, col])
        np.testing.assert_allclose(
            m.predict_proba(Xt), m.heads_[0].predict_proba(m.transform(Xt)), atol=1e-6
        )
    for bad, match in (
        (dict(head="svm"), "head"),
        (dict(C=0.0), "C"),
        (dict(C=float("nan")), "C"),
        (dict(C=True), "C"),
    ):
        with pytest.raises(ValueError, match=match):
            MiniRocketClassifier(pool=4, n_dilations=3, **bad).fit(X, y)


def test_sequential_from_fitted_equals_fit(data):
    (X, y), (Xt, yt) = data
    base = StationaryNaiveBayes(signal="raw", sample_rate_hz=FS)
    fitted = clone(base).fit(X, y)
    a = SequentialEvidenceClassifier(base, threshold=0.95).fit(X, y)
    b = SequentialEvidenceClassifier.from_fitted(fitted, threshold=0.95)
    assert b.estimator_ is fitted
    np.testing.assert_array_equal(a.classes_, b.classes_)
    np.testing.assert_allclose(a.contact_log_proba(Xt), b.contact_log_proba(Xt))
    with pytest.raises(NotFittedError):
        SequentialEvidenceClassifier.from_fitted(clone(base))
    with pytest.raises(ValueError, match="min_probability"):
        SequentialEvidenceClassifier.from_fitted(fitted, min_probability=1.0)
