"""Classification metrics of chapter 4: signed errors in physical units and kappa.

The thesis reports, per contact parameter, the mean and spread of the signed
classification error ``predicted - true`` in physical units (mm, mm/s;
tables 4.2-4.5 and 4.7). We add the exact-hit rate and Cohen's kappa (plain
for one parameter or for the joint class, weighted over ordered classes), as
fixed by the project's design.

All functions take 1-D arrays of true and predicted values of one parameter
(or 2-D ``(n_trials, n_targets)`` arrays for the joint class) and return
plain Python numbers, so their output serialises to JSON directly; an
undefined value (e.g. the spread of an empty sample) is ``None``, never NaN.
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from sklearn.metrics import confusion_matrix as _sk_confusion_matrix

__all__ = [
    "LABEL_DECIMALS",
    "confusion_matrix",
    "error_summary",
    "exact_hit_rate",
    "joint_kappa",
    "joint_labels",
    "kappa",
    "kappa_from_confusion",
    "parameter_scores",
    "signed_errors",
]

#: Class values are rounded to this many decimals before they are compared, so
#: that floating-point noise (``80.00000000001`` vs ``80.0``) never splits a class.
LABEL_DECIMALS = 6


def _as_1d(name: str, values: Any) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be 1-D (one value per trial), got shape {arr.shape}")
    return arr


def _pair(y_true: Any, y_pred: Any) -> tuple[np.ndarray, np.ndarray]:
    t = _as_1d("y_true", y_true)
    p = _as_1d("y_pred", y_pred)
    if t.shape != p.shape:
        raise ValueError(
            f"y_true and y_pred must have the same length, got {t.shape[0]} and {p.shape[0]}"
        )
    if not np.all(np.isfinite(t)):
        raise ValueError("y_true contains NaN or infinite values")
    return t, p


def _clean(x: float) -> float | None:
    """A finite float, or ``None`` for NaN/inf (JSON has no NaN)."""
    x = float(x)
    return x if math.isfinite(x) else None


def signed_errors(y_true: Any, y_pred: Any) -> np.ndarray:
    """Signed classification error ``y_pred - y_true`` per trial, in the parameter's units.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,)
        True and predicted values of one parameter (e.g. radial distance, mm).

    Returns
    -------
    numpy.ndarray of shape (n_trials,)
        The signed errors (positive: over-estimate).
    """
    t, p = _pair(y_true, y_pred)
    return p - t


def exact_hit_rate(y_true: Any, y_pred: Any, decimals: int = LABEL_DECIMALS) -> float | None:
    """Fraction of trials whose prediction equals the true class exactly.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,) or (n_trials, n_targets)
        True and predicted classes; for 2-D input a hit needs every column right
        (the joint class).
    decimals : int, default=LABEL_DECIMALS
        Values are compared after rounding to this many decimals.

    Returns
    -------
    float or None
        Hit rate in [0, 1]; ``None`` for no trials.
    """
    t = np.round(np.asarray(y_true, dtype=float), decimals)
    p = np.round(np.asarray(y_pred, dtype=float), decimals)
    if t.shape != p.shape:
        raise ValueError(f"y_true and y_pred must have the same shape, got {t.shape} and {p.shape}")
    if t.shape[0] == 0:
        return None
    hit = t == p
    if hit.ndim == 2:
        hit = hit.all(axis=1)
    return float(np.mean(hit))


def error_summary(y_true: Any, y_pred: Any, ddof: int = 1) -> dict[str, Any]:
    """Mean, standard deviation and exact-hit rate of the signed error of one parameter.

    The thesis' tables 4.2-4.5 and 4.7 label the spread "Std Err"; the values
    (e.g. 53.99 mm/s for the frequency classifier's speed) are the standard
    deviation of the per-trial errors, which is what ``std`` holds. ``sem`` is
    the standard error of the mean (``std / sqrt(n)``), for error bars.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,)
        True and predicted values of one parameter, in physical units.
    ddof : int, default=1
        Delta degrees of freedom of the standard deviation (1, as MATLAB's ``std``).

    Returns
    -------
    dict
        ``mean``, ``std``, ``sem``, ``mean_abs``, ``rmse`` (units of the
        parameter), ``exact_hit`` (fraction), ``n`` (trials). Undefined values
        (no trials, one trial for ``std``) are ``None``.
    """
    t, p = _pair(y_true, y_pred)
    n = int(t.shape[0])
    if n == 0:
        return {
            "mean": None,
            "std": None,
            "sem": None,
            "mean_abs": None,
            "rmse": None,
            "exact_hit": None,
            "n": 0,
        }
    if not np.all(np.isfinite(p)):
        raise ValueError("y_pred contains NaN or infinite values")
    err = p - t
    std = float(np.std(err, ddof=ddof)) if n > ddof else None
    return {
        "mean": _clean(np.mean(err)),
        "std": None if std is None else _clean(std),
        "sem": None if std is None else _clean(std / math.sqrt(n)),
        "mean_abs": _clean(np.mean(np.abs(err))),
        "rmse": _clean(np.sqrt(np.mean(err**2))),
        "exact_hit": exact_hit_rate(t, p),
        "n": n,
    }


def _kappa_from_labels(
    t: np.ndarray, p: np.ndarray, weights: Literal["linear", "quadratic"] | None
) -> float | None:
    if t.shape[0] == 0:
        return None
    labels = np.union1d(t, p)
    if labels.shape[0] == 1:
        # one class seen at all: agreement is perfect, chance agreement too; sklearn
        # returns NaN (0/0). Perfect agreement is what a user means here.
        return 1.0
    # integer codes in sorted order
    tc, pc = np.searchsorted(labels, t), np.searchsorted(labels, p)
    return _cohen_kappa(tc, pc, labels.shape[0], weights)


def _cohen_kappa(
    tc: np.ndarray,
    pc: np.ndarray,
    n_labels: int,
    weights: Literal["linear", "quadratic"] | None,
) -> float | None:
    """Cohen's kappa of integer codes in ``range(n_labels)``, ``None`` when undefined.

    The arithmetic of :func:`sklearn.metrics.cohen_kappa_score` with
    ``labels=range(n_labels)``, step by step, so the result is the same number to
    the last bit; but the plain kappa skips its ``n_labels x n_labels`` confusion
    and weight matrices (the joint classes of chapter 4 number ~2,600, and those
    matrices made the joint kappa the costliest step of the evaluation): the
    off-diagonal sum of the confusion matrix is the number of misses, and the
    weighted sum of the chance agreement is the sum of its matrix with the
    diagonal set to zero.
    """
    n_labels = int(n_labels)
    tc = np.asarray(tc, dtype=np.intp)
    pc = np.asarray(pc, dtype=np.intp)
    sum0 = np.bincount(pc, minlength=n_labels).astype(float)  # column sums (predicted)
    sum1 = np.bincount(tc, minlength=n_labels).astype(float)  # row sums (true)
    expected = np.outer(sum0, sum1)
    expected /= np.sum(sum0)
    if weights is None:
        numerator = float(np.count_nonzero(tc != pc))
        np.fill_diagonal(expected, 0.0)
        denominator = np.sum(expected)
    else:
        confusion = np.bincount(tc * n_labels + pc, minlength=n_labels * n_labels)
        confusion = confusion.reshape(n_labels, n_labels).astype(float)
        w_mat = np.zeros((n_labels, n_labels))
        w_mat += np.arange(n_labels)
        w_mat = np.abs(w_mat - w_mat.T) if weights == "linear" else (w_mat - w_mat.T) ** 2
        numerator = np.sum(w_mat * confusion)
        denominator = np.sum(w_mat * expected)
    if denominator == 0:
        return None
    return _clean(1 - numerator / denominator)


def kappa(
    y_true: Any,
    y_pred: Any,
    weights: Literal["linear", "quadratic"] | None = None,
    decimals: int = LABEL_DECIMALS,
) -> float | None:
    """Cohen's kappa of one parameter's classes, optionally weighted over ordered classes.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,)
        True and predicted values; each distinct value is one class.
    weights : {None, "linear", "quadratic"}, default=None
        ``None``: plain kappa (every disagreement counts the same). ``"linear"`` /
        ``"quadratic"``: weighted kappa, disagreement weighted by the (squared)
        distance between the *ranks* of the two classes in the sorted union of
        true and predicted values (on the thesis' evenly spaced grids this is
        proportional to the distance in mm or mm/s).
    decimals : int, default=LABEL_DECIMALS
        Values are rounded to this many decimals before they become classes.

    Returns
    -------
    float or None
        Kappa in [-1, 1]; 1.0 when a single class is seen and always predicted;
        ``None`` for no trials or when undefined.
    """
    if weights not in (None, "linear", "quadratic"):
        raise ValueError(f"weights must be None, 'linear' or 'quadratic', got {weights!r}")
    t, p = _pair(y_true, y_pred)
    if not np.all(np.isfinite(p)):
        raise ValueError("y_pred contains NaN or infinite values")
    return _kappa_from_labels(np.round(t, decimals), np.round(p, decimals), weights)


def joint_labels(
    y_true: Any, y_pred: Any, decimals: int = LABEL_DECIMALS
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Encode rows of several parameters as integer joint-class labels.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials, n_targets)
        True and predicted parameter rows.
    decimals : int, default=LABEL_DECIMALS
        Rounding applied before rows are compared.

    Returns
    -------
    true_codes, pred_codes : numpy.ndarray of shape (n_trials,)
        Index of each row in ``classes``.
    classes : numpy.ndarray of shape (n_classes, n_targets)
        Distinct rows of true and predicted values, sorted lexicographically.
    """
    t = np.round(np.asarray(y_true, dtype=float), decimals)
    p = np.round(np.asarray(y_pred, dtype=float), decimals)
    if t.ndim != 2 or p.shape != t.shape:
        raise ValueError(
            "y_true and y_pred must both be 2-D (n_trials, n_targets) of the same shape, got "
            f"{t.shape} and {p.shape}"
        )
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
        raise ValueError("joint labels need finite values in every column of y_true and y_pred")
    classes, codes = np.unique(np.vstack([t, p]), axis=0, return_inverse=True)
    codes = np.asarray(codes).reshape(-1)
    return codes[: t.shape[0]], codes[t.shape[0] :], classes


def joint_kappa(y_true: Any, y_pred: Any, decimals: int = LABEL_DECIMALS) -> float | None:
    """Cohen's kappa of the joint class (each distinct parameter row is one class).

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials, n_targets)
        True and predicted rows, e.g. ``[radial_distance_mm, speed_mm_s]``.
    decimals : int, default=LABEL_DECIMALS
        Rounding applied before rows are compared.

    Returns
    -------
    float or None
        Unweighted kappa over joint classes (they have no natural order).
    """
    tc, pc, _ = joint_labels(y_true, y_pred, decimals)
    return _kappa_from_labels(tc, pc, None)


def confusion_matrix(
    y_true: Any,
    y_pred: Any,
    labels: Any | None = None,
    decimals: int = LABEL_DECIMALS,
) -> tuple[np.ndarray, np.ndarray]:
    """Confusion matrix of one parameter (or of joint rows).

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,) or (n_trials, n_targets)
        True and predicted classes. 2-D input is encoded as joint classes.
    labels : array-like, optional
        Classes in the order of the rows/columns (1-D input only); defaults to
        the sorted union of true and predicted values.
    decimals : int, default=LABEL_DECIMALS
        Rounding applied before values are compared.

    Returns
    -------
    matrix : numpy.ndarray of shape (n_classes, n_classes)
        ``matrix[i, j]`` counts trials of true class ``i`` predicted as ``j``.
    labels : numpy.ndarray
        The classes, shape ``(n_classes,)`` or ``(n_classes, n_targets)``.
    """
    t = np.asarray(y_true, dtype=float)
    if t.ndim == 2:
        if labels is not None:
            raise ValueError("labels is only supported for 1-D y_true/y_pred")
        tc, pc, classes = joint_labels(y_true, y_pred, decimals)
        m = _sk_confusion_matrix(tc, pc, labels=np.arange(classes.shape[0]))
        return m, classes
    t, p = _pair(y_true, y_pred)
    t = np.round(t, decimals)
    p = np.round(p, decimals)
    lab = np.union1d(t, p) if labels is None else np.round(_as_1d("labels", labels), decimals)
    # integer codes (sklearn rejects non-integer floats); values outside ``labels`` -> -1
    order = np.argsort(lab, kind="stable")
    srt = lab[order]

    def codes(v: np.ndarray) -> np.ndarray:
        i = np.clip(np.searchsorted(srt, v), 0, srt.shape[0] - 1)
        return np.where(srt[i] == v, order[i], -1)

    m = _sk_confusion_matrix(codes(t), codes(p), labels=np.arange(lab.shape[0]))
    return m, lab


def kappa_from_confusion(matrix: Any, weights: str | None = None) -> float | None:
    """Cohen's kappa (thesis eq. 5.7) of a confusion matrix (rows true, columns predicted).

    Parameters
    ----------
    matrix : array-like of shape (k, k)
        Counts.
    weights : {None, "linear", "quadratic"}
        Disagreement weights ``|i - j|`` or ``(i - j)^2`` over ordered classes.

    Returns
    -------
    float or None
        ``(P_O - P_E) / (1 - P_E)`` (weighted: ``1 - sum w O / sum w E``);
        ``None`` for an empty matrix or when undefined. Agrees with :func:`kappa`
        on the matrix of the same predictions.
    """
    m = np.asarray(matrix, dtype=float)
    if m.ndim != 2 or m.shape[0] != m.shape[1]:
        raise ValueError(f"matrix must be square, got shape {m.shape}")
    n = m.sum()
    if n <= 0:
        return None
    i, j = np.indices(m.shape)
    if weights is None:
        w = (i != j).astype(float)
    elif weights == "linear":
        w = np.abs(i - j).astype(float)
    elif weights == "quadratic":
        w = ((i - j) ** 2).astype(float)
    else:
        raise ValueError(f"weights must be None, 'linear' or 'quadratic', got {weights!r}")
    expected = np.outer(m.sum(axis=1), m.sum(axis=0)) / n
    den = float(np.sum(w * expected))
    if den == 0:
        return 1.0 if float(np.sum(w * m)) == 0 else None
    return 1.0 - float(np.sum(w * m)) / den


def parameter_scores(y_true: Any, y_pred: Any, labels: Any | None = None) -> dict[str, Any]:
    """Every score of one parameter: :func:`error_summary` plus plain and weighted kappa.

    Parameters
    ----------
    y_true, y_pred : array-like of shape (n_trials,)
    labels : array-like, optional
        When given, also the confusion matrix over these classes (key ``confusion``:
        ``labels``, ``matrix``; rows true).

    Returns
    -------
    dict
        ``mean``, ``std``, ``sem``, ``mean_abs``, ``rmse``, ``exact_hit``, ``n``,
        ``kappa``, ``kappa_linear``, ``kappa_quadratic`` [, ``confusion``].
    """
    out = error_summary(y_true, y_pred)
    out["kappa"] = kappa(y_true, y_pred)
    out["kappa_linear"] = kappa(y_true, y_pred, weights="linear")
    out["kappa_quadratic"] = kappa(y_true, y_pred, weights="quadratic")
    if labels is not None:
        m, lab = confusion_matrix(y_true, y_pred, labels=labels)
        out["confusion"] = {"labels": lab.tolist(), "matrix": m.tolist()}
    return out
