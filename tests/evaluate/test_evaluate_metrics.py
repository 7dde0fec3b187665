"""Tests of vibrissa.evaluate.metrics against hand-computed values."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.evaluate import metrics


def _from_confusion(m: np.ndarray, labels) -> tuple[np.ndarray, np.ndarray]:
    t, p = [], []
    for i, a in enumerate(labels):
        for j, b in enumerate(labels):
            t += [a] * int(m[i, j])
            p += [b] * int(m[i, j])
    return np.array(t, float), np.array(p, float)


def test_kappa_two_classes_by_hand() -> None:
    # po = 35/50 = 0.7, pe = (25*30 + 25*20) / 50**2 = 0.5, kappa = 0.2 / 0.5 = 0.4
    t, p = _from_confusion(np.array([[20, 5], [10, 15]]), [80.0, 81.0])
    assert metrics.kappa(t, p) == pytest.approx(0.4)
    m, lab = metrics.confusion_matrix(t, p)
    assert np.array_equal(m, [[20, 5], [10, 15]]) and np.array_equal(lab, [80.0, 81.0])


def test_weighted_kappa_three_ordered_classes_by_hand() -> None:
    m = np.array([[2, 1, 0], [0, 2, 1], [1, 0, 3]])
    t, p = _from_confusion(m, [36.0, 43.0, 50.0])
    # expected counts E = outer(rows, cols) / 10 with rows = cols = (3, 3, 4)
    # unweighted: po = 0.7, pe = 0.34 -> (0.7 - 0.34) / 0.66
    assert metrics.kappa(t, p) == pytest.approx(0.36 / 0.66)
    # linear: sum|i-j| O = 4, sum|i-j| E = 4.2 + 2 * 2.4 = 9.0
    assert metrics.kappa(t, p, weights="linear") == pytest.approx(1 - 4 / 9.0)
    # quadratic: sum (i-j)^2 O = 6, sum (i-j)^2 E = 4.2 + 4 * 2.4 = 13.8
    assert metrics.kappa(t, p, weights="quadratic") == pytest.approx(1 - 6 / 13.8)
    with pytest.raises(ValueError, match="weights"):
        metrics.kappa(t, p, weights="cubic")


def test_kappa_edge_cases() -> None:
    assert metrics.kappa([5.0, 5.0], [5.0, 5.0]) == 1.0  # one class, always right
    assert metrics.kappa([1.0, 2.0, 3.0], [1.0, 2.0, 3.0 + 1e-12]) == 1.0  # float noise
    assert metrics.kappa([], []) is None
    with pytest.raises(ValueError, match="same length"):
        metrics.kappa([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="NaN"):
        metrics.kappa([1.0, 2.0], [1.0, np.nan])


def test_error_summary_by_hand() -> None:
    t = np.array([80.0, 90.0, 100.0, 110.0])
    p = np.array([81.0, 90.0, 97.0, 110.0])  # errors +1, 0, -3, 0
    s = metrics.error_summary(t, p)
    assert s["mean"] == pytest.approx(-0.5)
    assert s["std"] == pytest.approx(np.sqrt((1.5**2 + 0.5**2 + 2.5**2 + 0.5**2) / 3))
    assert s["sem"] == pytest.approx(s["std"] / 2)
    assert s["mean_abs"] == pytest.approx(1.0)
    assert s["rmse"] == pytest.approx(np.sqrt(10 / 4))
    assert s["exact_hit"] == pytest.approx(0.5) and s["n"] == 4
    assert np.array_equal(metrics.signed_errors(t, p), [1.0, 0.0, -3.0, 0.0])
    one = metrics.error_summary([1.0], [2.0])
    assert one["mean"] == 1.0 and one["std"] is None
    assert metrics.error_summary([], [])["mean"] is None
    with pytest.raises(ValueError, match="1-D"):
        metrics.error_summary(np.zeros((2, 2)), np.zeros((2, 2)))


def test_joint_kappa_and_confusion() -> None:
    t = np.array([[80, 36], [80, 72], [90, 36], [90, 72]], float)
    p = np.array([[80, 36], [80, 36], [90, 36], [90, 72]], float)
    # joint classes A B C D; true A B C D, pred A A C D: po = 3/4,
    # pe = (1*2 + 1*0 + 1*1 + 1*1) / 16 = 0.25 -> kappa = 0.5 / 0.75
    assert metrics.joint_kappa(t, p) == pytest.approx(2 / 3)
    assert metrics.exact_hit_rate(t, p) == pytest.approx(0.75)
    m, classes = metrics.confusion_matrix(t, p)
    assert classes.shape == (4, 2) and m.sum() == 4 and np.trace(m) == 3
    tc, pc, cl = metrics.joint_labels(t, p)
    assert np.array_equal(cl[tc], t) and np.array_equal(cl[pc], p)
    with pytest.raises(ValueError, match="finite"):
        metrics.joint_kappa(t, np.where(p == 36, np.nan, p))
    m2, lab2 = metrics.confusion_matrix(t[:, 0], p[:, 0], labels=[90.0, 80.0])
    assert np.array_equal(lab2, [90.0, 80.0]) and np.array_equal(m2, [[2, 0], [0, 2]])


def test_non_integer_class_values() -> None:
    # thesis speeds are ~7.2 mm/s apart (36 ... 216): non-integer floats are classes too
    speeds = np.linspace(36.0, 216.0, 26)
    t = np.repeat(speeds, 2)
    p = t.copy()
    p[::2] = np.roll(speeds, 1)
    k = metrics.kappa(t, p)
    assert k == pytest.approx((0.5 - 1 / 26) / (1 - 1 / 26))
    assert metrics.kappa(t, p, weights="linear") < 1
    m, lab = metrics.confusion_matrix(t, p)
    assert m.shape == (26, 26) and np.trace(m) == 26 and np.allclose(lab, speeds)
    m2, _ = metrics.confusion_matrix(t, p, labels=speeds[::-1])
    assert np.array_equal(m2, m[::-1, ::-1])
    tj = np.column_stack([t, t / 3.0])
    assert metrics.joint_kappa(tj, np.column_stack([p, p / 3.0])) == pytest.approx(k)


@pytest.mark.parametrize("weights", [None, "linear", "quadratic"])
@pytest.mark.parametrize(("n_trials", "n_classes"), [(40, 3), (600, 250), (2000, 1500)])
def test_kappa_is_sklearns_to_the_last_bit(weights, n_trials, n_classes) -> None:
    # metrics computes Cohen's kappa itself (without sklearn's n_classes^2 matrices for
    # the plain kappa); the chapter-4 results must not move by one bit
    from sklearn.metrics import cohen_kappa_score

    rng = np.random.default_rng(n_classes)
    t = rng.integers(0, n_classes, n_trials).astype(float)
    p = np.where(rng.random(n_trials) < 0.6, t, rng.integers(0, n_classes, n_trials))
    labels = np.union1d(t, p)
    tc, pc = np.searchsorted(labels, t), np.searchsorted(labels, p)
    expect = cohen_kappa_score(tc, pc, labels=np.arange(labels.size), weights=weights)
    assert metrics.kappa(t, p.astype(float), weights=weights) == expect
    if weights is None:
        tj, pj = np.column_stack([t, t % 7]), np.column_stack([p, p % 7])
        codes_t, codes_p, classes = metrics.joint_labels(tj, pj)
        assert metrics.joint_kappa(tj, pj) == cohen_kappa_score(
            codes_t, codes_p, labels=np.arange(len(classes))
        )


def test_kappa_of_total_disagreement_by_hand() -> None:
    # true all 0, predicted all 1: observed = chance disagreement -> 0; swapped -> -1
    assert metrics.kappa([0.0, 0.0], [1.0, 1.0], weights="linear") == pytest.approx(0.0)
    assert metrics.kappa([0.0, 1.0], [1.0, 0.0]) == pytest.approx(-1.0)
