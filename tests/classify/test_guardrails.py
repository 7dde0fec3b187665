"""Issue 13, finding 9: bad inputs refused, estimators usable in scikit-learn."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.utils import get_tags

from vibrissa.classify import (
    FrequencyTemplateClassifier,
    MiniRocketClassifier,
    SequentialEvidenceClassifier,
    SignalTransform,
    SpeedFirstClassifier,
    StationaryNaiveBayes,
    TimeTemplateClassifier,
)


def _trials(seed: int = 0):
    rng = np.random.default_rng(seed)
    y = np.array([[r, s] for r in (50.0, 100.0) for s in (36.0, 43.2)] * 6)
    t = np.arange(80)
    X = rng.normal(0, 0.05, size=(len(y), 2, 80)) + (y[:, 0] / 50)[:, None, None] * np.sin(
        t * y[:, 1][:, None, None] / 200
    )
    return X, y


@pytest.mark.parametrize(
    "est",
    [
        TimeTemplateClassifier(),
        FrequencyTemplateClassifier(),
        StationaryNaiveBayes(signal="velocity"),
        MiniRocketClassifier(pool=2),
    ],
)
def test_overflowing_inputs_refused(est) -> None:
    X, y = _trials()
    with pytest.raises(ValueError, match=r"as large as .*e\+300"):
        est.fit(X * 1e300, y)
    est.fit(X, y)
    with pytest.raises(ValueError, match="as large as"):
        est.predict(X * 1e300)
    with pytest.raises(ValueError, match="infinity|NaN"):
        est.predict(np.where(X > 0, np.inf, X))


def test_signal_transform_refuses_overflow_and_other_shapes() -> None:
    X, _ = _trials()
    with pytest.raises(ValueError, match="as large as"):
        SignalTransform("velocity").fit(X * 1e300)
    st = SignalTransform("lowpass").fit(X)
    assert st.n_features_in_ == 160 and st.n_channels_ == 2 and st.n_timepoints_ == 80
    with pytest.raises(ValueError, match="timepoints"):
        st.transform(X[..., :60])
    with pytest.raises(ValueError, match="channels"):
        st.transform(X[:, :1])


def test_minirocket_is_classifier_and_transformer() -> None:
    X, y = _trials()
    # check_estimator raised "seems to be a Transformer" (it has transform, no tags)
    tags = get_tags(MiniRocketClassifier())
    assert tags.estimator_type == "classifier" and tags.transformer_tags is not None
    m = MiniRocketClassifier(pool=2)
    F = m.fit_transform(X, y)
    np.testing.assert_allclose(F, m.transform(X))
    assert m.pool_ == 2
    short = MiniRocketClassifier(pool=8).fit(X[..., :20], y)  # < 9 * pool samples
    assert short.pool_ == 2 and short.predict(X[..., :20]).shape == y.shape


def test_speed_first_takes_1d_speeds() -> None:
    X, y = _trials()
    m = SpeedFirstClassifier(
        speed_estimator=TimeTemplateClassifier(cutoff_hz=None),
        estimator=TimeTemplateClassifier(cutoff_hz=None),
        sample_rate_hz=1000.0,
    ).fit(X, y[:, 1])
    assert m.classes_.ndim == 1 and set(m.predict(X)) <= {36.0, 43.2}


def test_sequential_without_target_column_accumulates_joint_rows() -> None:
    X, y = _trials()
    s = SequentialEvidenceClassifier(TimeTemplateClassifier(cutoff_hz=None), target_column=None)
    s.fit(X, y)
    assert s.classes_.shape == (4, 2) and s.predict(X).shape == y.shape
    assert s.n_features_in_ == 160
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        SequentialEvidenceClassifier(TimeTemplateClassifier()).predict(X)


def test_mixed_object_labels_are_joint_classes() -> None:
    X, y = _trials()
    yo = np.empty(y.shape, dtype=object)
    yo[:, 0] = y[:, 0]
    yo[:, 1] = np.where(y[:, 1] > 40, "p80", "p600")
    m = TimeTemplateClassifier(cutoff_hz=None).fit(X, yo)
    assert m.classes_.shape == (4, 2) and m.classes_[0, 1] == "p600"
    assert m.score(X, yo) == 1.0
