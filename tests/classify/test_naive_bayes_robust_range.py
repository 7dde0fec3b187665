"""The 'robust' histogram range of StationaryNaiveBayes (beyond the thesis)."""

import numpy as np
import pytest

from vibrissa.classify import StationaryNaiveBayes


def heavy_tailed(seed=0):
    rng = np.random.default_rng(seed)
    n, t = 40, 200
    y = np.repeat([0.0, 1.0], n // 2)
    X = rng.normal(0.0, 0.01, (n, 1, t)) + 0.02 * y[:, None, None]
    X[0, 0, 0] = 50.0  # one rare, extreme sample (e.g. a snap-back) in the training data
    return X, y


def test_robust_range_ignores_rare_extremes():
    X, y = heavy_tailed()
    full = StationaryNaiveBayes(signal="raw", smoothing_sigma=0, value_range=None).fit(X, y)
    robust = StationaryNaiveBayes(signal="raw", smoothing_sigma=0, value_range="robust").fit(X, y)
    # the full data range puts all ordinary samples into one or two of 100 bins
    assert full.bin_edges_[0, -1] == pytest.approx(50.0)
    assert robust.bin_edges_[0, -1] < 0.2
    Xt, yt = heavy_tailed(seed=1)
    Xt[0, 0, 0] = 0.0
    acc_full = np.mean(full.predict(Xt) == yt)
    acc_robust = np.mean(robust.predict(Xt) == yt)
    assert acc_robust == 1.0
    assert acc_full < acc_robust


def test_bad_value_range_string():
    X, y = heavy_tailed()
    with pytest.raises(ValueError, match="value_range"):
        StationaryNaiveBayes(value_range="wide").fit(X, y)
