"""Sample rates (issue 13, finding 9): every estimator records the rate it was fitted at.

Each estimator of both chapters refuses data at another rate than it is built for
(at fit) or was fitted at (at predict/transform); ``from_dataset`` takes the rate
from a Dataset; ``sample_rate_fit_params`` follows the rate through a Pipeline.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from sklearn.base import clone
from sklearn.pipeline import Pipeline

from vibrissa import classify as vc
from vibrissa.classify import (
    check_sample_rate,
    dataset_sample_rate,
    fitted_sample_rate,
    sample_rate_fit_params,
)

FS4, FS5 = 1000.0, 4000.0
WHISKER = {
    "length_mm": 185.0,
    "base_radius_mm": 1.0,
    "youngs_modulus_gpa": 2.35,
    "follicle_stiffness_nm_per_rad": 0.1,
    "hall_gain_v": 12.0,
}


def _pulses(fs: float, n_t: int, y: np.ndarray, seed: int) -> np.ndarray:
    """A contact pulse per label row: amplitude from column 0, width from column 1."""
    rng = np.random.default_rng(seed)
    t = (np.arange(n_t) - n_t // 2) / fs
    amp = 20.0 / y[:, :1]
    width = 2.0 / y[:, 1:2]
    vib = np.sin(2 * np.pi * 150.0 * (1 + y[:, -1:]) * t)
    pulse = amp * np.exp(-0.5 * (t / width) ** 2) * (1 + 0.05 * vib)
    X = np.stack([2.5 + pulse, 2.5 + 0.1 * pulse], axis=1)
    return X + 0.002 * rng.standard_normal(X.shape)


def chapter4_data() -> tuple[np.ndarray, np.ndarray]:
    """Whole chapter-4 recordings (1,301 samples at 1 kHz): radius x speed, 3 repeats."""
    y = np.array([[r, v] for _ in range(3) for r in (90.0, 130.0, 170.0) for v in (50.0, 150.0)])
    return _pulses(FS4, 1301, y, 0), y


def chapter5_data() -> tuple[np.ndarray, np.ndarray]:
    """Chapter-5 trials (800 samples at 4 kHz): angle x speed x texture code, 2 repeats."""
    y = np.array(
        [
            [a, v, tex]
            for _ in range(2)
            for a in (20.0, 60.0)
            for v in (20.0, 80.0)
            for tex in (0.0, 1.0, 2.0)
        ]
    )
    return _pulses(FS5, 800, y, 1), y


def _chapter4() -> dict:
    clfs = {f"ch4 {k}": v for k, v in vc.chapter4_classifiers(FS4, WHISKER).items()}
    clfs["ch4 static_beam_fitted"].set_params(classifier__param_grid={"youngs_modulus_gpa": [2.35]})
    clfs.update(
        {
            "ch4 TimeTemplateClassifier": vc.TimeTemplateClassifier(),
            "ch4 FrequencyTemplateClassifier": vc.FrequencyTemplateClassifier(),
            "ch4 FeatureRegressionClassifier": vc.FeatureRegressionClassifier(),
            "ch4 StationaryNaiveBayes": vc.StationaryNaiveBayes(),
            "ch4 StaticBeamClassifier": vc.StaticBeamClassifier(
                whisker=WHISKER, sample_rate_hz=FS4
            ),
            "ch4 RecordingWindow": vc.RecordingWindow(),
        }
    )
    return clfs


def _chapter5() -> dict:
    clfs = {f"ch5 {k}": v for k, v in vc.chapter5_classifiers(FS5, notch_hz=13.0).items()}
    clfs["ch5 minirocket"].set_params(pool=4, n_dilations=3)
    clfs.update(
        {
            "ch5 SignalTransform": vc.SignalTransform("lowpass", downsample=4),
            "ch5 SequentialEvidenceClassifier": vc.SequentialEvidenceClassifier(
                vc.TimeTemplateClassifier(sample_rate_hz=FS5, cutoff_hz=None)
            ),
        }
    )
    return clfs


ESTIMATORS = {**_chapter4(), **_chapter5()}


def _case(key: str):
    est = clone(ESTIMATORS[key])
    X, y = chapter4_data() if key.startswith("ch4") else chapter5_data()
    return est, X, y, FS4 if key.startswith("ch4") else FS5


@pytest.mark.parametrize("key", sorted(ESTIMATORS))
def test_fit_at_another_rate_is_refused(key: str) -> None:
    est, X, y, fs = _case(key)
    other = 3 * fs
    both = rf"{fs:g} Hz, but the data are sampled at {other:g} Hz"
    with pytest.raises(ValueError, match=both):
        check_sample_rate(est, other)
    with pytest.raises(ValueError, match=both):
        est.fit(X, y, **sample_rate_fit_params(est, other))
    check_sample_rate(est, fs)  # the rate it is built for


@pytest.mark.parametrize("key", sorted(ESTIMATORS))
def test_predict_at_another_rate_is_refused(key: str) -> None:
    est, X, y, fs = _case(key)
    other = 3 * fs
    est.fit(X, y, **sample_rate_fit_params(est, fs))
    assert fitted_sample_rate(est) == fs
    fitted = rf"fitted on data sampled at {fs:g} Hz, but these data are sampled at {other:g} Hz"
    with pytest.raises(ValueError, match=fitted):
        check_sample_rate(est, other)
    if isinstance(est, Pipeline):
        return
    method = "transform" if isinstance(est, vc.RecordingWindow | vc.SignalTransform) else "predict"
    same = getattr(est, method)(X, sample_rate_hz=fs)
    np.testing.assert_array_equal(same, getattr(est, method)(X))
    with pytest.raises(ValueError, match=fitted):
        getattr(est, method)(X, sample_rate_hz=other)
    if method == "predict":
        with pytest.raises(ValueError, match=fitted):
            est.score(X, y, sample_rate_hz=other)
        with pytest.raises(ValueError, match=fitted):
            est.predict_proba(X, sample_rate_hz=other)


def test_a_pipeline_step_is_named_and_sees_the_downsampled_rate() -> None:
    X, y = chapter5_data()
    pipe = vc.chapter5_classifiers(FS5, notch_hz=13.0)["template_lowpass"]
    down = pipe.named_steps["signal"].downsample
    assert sample_rate_fit_params(pipe, FS5) == {
        "signal__sample_rate_hz": FS5,
        "template__sample_rate_hz": FS5 / down,
    }
    pipe.fit(X, y, **sample_rate_fit_params(pipe, FS5))
    assert pipe.named_steps["template"].sample_rate_hz_ == FS5 / down
    with pytest.raises(
        ValueError,
        match="step 'signal': SignalTransform was fitted on data "
        "sampled at 4000 Hz, but these data are sampled at 1000",
    ):
        check_sample_rate(pipe, 1000.0)
    # a classifier built for the rate before the downsampling is refused
    wrong = Pipeline(
        [
            ("signal", vc.SignalTransform("lowpass", FS5, downsample=20)),
            ("template", vc.TimeTemplateClassifier(sample_rate_hz=FS5)),
        ]
    )
    with pytest.raises(
        ValueError,
        match="step 'template': TimeTemplateClassifier is built for "
        "sample_rate_hz=4000 Hz, but the data are sampled at "
        "200 Hz",
    ):
        check_sample_rate(wrong, FS5)


def test_composite_refuses_parts_built_for_another_rate() -> None:
    X, y = chapter5_data()
    sf = vc.SpeedFirstClassifier(estimator=vc.StationaryNaiveBayes(sample_rate_hz=FS4))  # 4 kHz
    with pytest.raises(
        ValueError,
        match="SpeedFirstClassifier's estimator: StationaryNaiveBayes "
        "is built for sample_rate_hz=1000 Hz, but the data "
        "are sampled at 4000 Hz",
    ):
        sf.fit(X, y)
    lp_1khz = vc.SignalTransform("lowpass", sample_rate_hz=FS4)
    jl = vc.JointLikelihoodNaiveBayes(template_signal=lp_1khz)
    with pytest.raises(
        ValueError, match="template_signal: SignalTransform is built for sample_rate_hz=1000 Hz"
    ):
        jl.fit(X, y, sample_rate_hz=FS5)


@pytest.mark.parametrize(
    "est",
    [vc.StaticBeamClassifier(whisker=WHISKER), vc.MiniRocketClassifier(pool=4, n_dilations=3)],
)
def test_rate_independent_estimators_record_the_rate_they_are_given(est) -> None:
    X, y = chapter4_data()
    assert est.fit(X, y).sample_rate_hz_ is None
    est.predict(X, sample_rate_hz=123.0)  # fitted without a rate: any rate
    est.fit(X, y, sample_rate_hz=500.0)
    assert est.sample_rate_hz_ == 500.0 and est.sample_rate_hz is None
    np.testing.assert_array_equal(est.predict(X, sample_rate_hz=500.0), est.predict(X))
    with pytest.raises(
        ValueError, match="fitted on data sampled at 500 Hz, but these data are sampled at 1000 Hz"
    ):
        est.predict(X, sample_rate_hz=1000.0)


def test_sequential_records_the_rate_of_its_estimator() -> None:
    X, y = chapter5_data()
    inner = vc.TimeTemplateClassifier(sample_rate_hz=FS5, cutoff_hz=None).fit(X, y)
    seq = vc.SequentialEvidenceClassifier.from_fitted(inner)
    assert seq.sample_rate_hz_ == FS5
    seqs = np.arange(len(y))[:, None]
    seq.predict_sequences(X, seqs, sample_rate_hz=FS5)
    with pytest.raises(
        ValueError, match="fitted on data sampled at 4000 Hz, but these data are sampled at 1000 Hz"
    ):
        seq.predict_sequences(X, seqs, sample_rate_hz=FS4)
    with pytest.raises(ValueError, match="4000 Hz, but the data are sampled at 1000 Hz"):
        vc.SequentialEvidenceClassifier(vc.TimeTemplateClassifier(sample_rate_hz=FS5)).fit(
            X, y, sample_rate_hz=FS4
        )


# ------------------------------------------------------------------ from_dataset, params
#: Every public estimator built for a sample rate (found, so that a new one is covered).
RATED = [
    c
    for c in map(vc.__dict__.get, vc.__all__)
    if isinstance(c, type)
    and issubclass(c, vc.SampleRateMixin)
    and "sample_rate_hz" in getattr(c, "_get_param_names", list)()
]


def test_every_rate_aware_estimator_is_covered() -> None:
    assert {c.__name__ for c in RATED} >= {
        "TimeTemplateClassifier",
        "FrequencyTemplateClassifier",
        "FeatureRegressionClassifier",
        "StationaryNaiveBayes",
        "StaticBeamClassifier",
        "RecordingWindow",
        "SignalTransform",
        "FeaturePolynomialClassifier",
        "SpeedFirstClassifier",
        "JointLikelihoodNaiveBayes",
        "MiniRocketClassifier",
    }


def _dataset(rate: float | None) -> xr.Dataset:
    return xr.Dataset(attrs={} if rate is None else {"sample_rate_hz": rate})


@pytest.mark.parametrize("cls", RATED, ids=lambda c: c.__name__)
def test_from_dataset_takes_the_dataset_rate(cls) -> None:
    ds = _dataset(2500.0)
    est = cls.from_dataset(ds)
    assert est.sample_rate_hz == 2500.0 == dataset_sample_rate(ds)
    assert cls.from_dataset(ds, sample_rate_hz=2500.0).get_params() == est.get_params()
    with pytest.raises(
        ValueError,
        match=r"sample_rate_hz=1000\.0 differs from the dataset's "
        "rate, 2500 Hz",
    ):
        cls.from_dataset(ds, sample_rate_hz=1000.0)
    with pytest.raises(ValueError, match="no attribute 'sample_rate_hz'"):
        cls.from_dataset(_dataset(None))
    with pytest.raises(ValueError, match="must be positive"):
        cls.from_dataset(_dataset(-1.0))


def test_from_dataset_keeps_other_parameters_and_fits_at_the_dataset_rate() -> None:
    X, y = chapter4_data()
    ds = _dataset(FS4)
    est = vc.TimeTemplateClassifier.from_dataset(ds, cutoff_hz=50.0, distance="l1")
    assert (est.cutoff_hz, est.distance) == (50.0, "l1")
    assert est.fit(X, y, sample_rate_hz=dataset_sample_rate(ds)).sample_rate_hz_ == FS4
    with pytest.raises(TypeError, match="takes no sample rate of its own"):
        vc.SequentialEvidenceClassifier.from_dataset(ds, estimator=est)


@pytest.mark.parametrize("cls", RATED, ids=lambda c: c.__name__)
def test_clone_and_get_params_keep_the_rate(cls) -> None:
    est = cls.from_dataset(_dataset(2500.0))
    params = est.get_params()
    assert params["sample_rate_hz"] == 2500.0
    assert clone(est).get_params() == params
    assert cls(**params).get_params() == params
    assert est.set_params(sample_rate_hz=300.0).get_params()["sample_rate_hz"] == 300.0
    assert clone(est).sample_rate_hz == 300.0


def test_clone_of_a_fitted_estimator_forgets_the_fitted_rate() -> None:
    X, y = chapter4_data()
    est = vc.StationaryNaiveBayes().fit(X, y, sample_rate_hz=FS4)
    assert est.sample_rate_hz_ == FS4
    assert not hasattr(clone(est), "sample_rate_hz_")


def test_argmax_softmax_is_the_argmax_of_the_probabilities() -> None:
    from scipy.special import softmax

    from vibrissa.classify._base import argmax_softmax

    rng = np.random.default_rng(0)
    scores = rng.standard_normal((500, 40)) * rng.choice([1e-3, 1.0, 1e4], size=(500, 1))
    assert np.array_equal(argmax_softmax(scores), np.argmax(softmax(scores, axis=1), axis=1))
    # ties and near ties with the best class, before and after it: the softmax decides
    near = scores.copy()
    best = np.argmax(near, axis=1)
    rows = np.arange(0, 500, 3)
    for gap in (0.0, 1e-17, 1e-13, 1e-10):
        other = (best[rows] + 7) % 40
        near[rows, other] = near[rows, best[rows]] - gap
        assert np.array_equal(argmax_softmax(near), np.argmax(softmax(near, axis=1), axis=1))
    assert argmax_softmax(np.empty((0, 3))).shape == (0,)
    with_inf = np.array([[0.0, -np.inf, 1.0], [np.inf, 0.0, 0.0]])
    assert np.array_equal(argmax_softmax(with_inf), np.argmax(softmax(with_inf, axis=1), axis=1))
