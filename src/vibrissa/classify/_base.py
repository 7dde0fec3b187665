"""Shared input validation and joint-label encoding for the trial classifiers.

Every classifier in :mod:`vibrissa.classify` takes trials ``X`` of shape
``(n_trials, n_channels, n_timepoints)`` (time last; a 2-D ``(n_trials,
n_timepoints)`` array is one channel) and labels ``y`` either 1-D or of shape
``(n_trials, n_targets)``, e.g. columns ``[radial_distance_mm, speed_mm_s]``.
Each distinct row of ``y`` is one *joint class* (thesis 4.3.3: "each template
corresponds to a speed-radial distance pair ... simultaneous classification of
both"); ``classes_`` holds the distinct rows and ``predict`` returns rows.

Subclasses implement ``_fit(X, y_index)`` and ``_joint_scores(X)``; the latter
returns one score per (trial, class), larger is better, on a log-probability
scale: ``predict_proba`` is their softmax and ``predict`` its argmax, so the two
always agree.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import softmax
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.validation import check_array, check_is_fitted, validate_data

__all__ = [
    "MAX_ABS_INPUT",
    "EstimatorTags",
    "TrialClassifier",
    "check_magnitude",
    "estimator_tags",
    "nearest_values",
    "target_column",
]

#: Largest magnitude of an input sample the estimators accept. Signals are volts (or
#: volts per second after a derivative); squared errors, filters and derivatives of
#: values beyond this overflow float64 (1e300 squared is inf), which used to give an
#: overflow warning and the same class for every trial instead of an error.
MAX_ABS_INPUT = 1e100


def check_magnitude(X: np.ndarray, name: str = "X") -> np.ndarray:
    """Refuse inputs whose magnitude would overflow the estimators' arithmetic.

    Parameters
    ----------
    X : ndarray
        Finite, validated float input.
    name : str, default="X"
        Name of the input in the message.

    Returns
    -------
    ndarray
        ``X`` itself.

    Raises
    ------
    ValueError
        If any ``|X|`` exceeds :data:`MAX_ABS_INPUT`, naming the largest value.
    """
    if X.size:
        largest = float(np.max(np.abs(X)))
        if not largest <= MAX_ABS_INPUT:
            raise ValueError(
                f"{name} has values as large as {largest:.3g} in magnitude; the classifiers "
                f"accept |{name}| <= {MAX_ABS_INPUT:.0e} (larger values overflow their "
                "arithmetic); rescale the signals (e.g. to volts)"
            )
    return X


@dataclass(frozen=True)
class EstimatorTags:
    """What a vibrissa estimator can do, beyond scikit-learn's own tags.

    Attributes
    ----------
    estimated_targets : tuple of int or None
        Columns of ``y`` the estimator estimates; its predictions in the other
        columns are NaN. ``None``: every column (the default). The static beam
        equation estimates radial distance only (thesis 4.3.1): ``(0,)``.
    """

    estimated_targets: tuple[int, ...] | None = None

    def estimates_only(self, *columns: int) -> bool:
        """True when the estimator estimates exactly these columns of ``y``."""
        return self.estimated_targets is not None and tuple(self.estimated_targets) == columns


def estimator_tags(estimator: Any) -> EstimatorTags:
    """The :class:`EstimatorTags` of an estimator (of a Pipeline: of its final step).

    An estimator declares its tags with a method ``__vibrissa_tags__()`` returning
    :class:`EstimatorTags`; one without it gets the defaults.
    """
    est = estimator
    while hasattr(est, "steps"):
        est = est.steps[-1][1]
    declare = getattr(est, "__vibrissa_tags__", None)
    return declare() if callable(declare) else EstimatorTags()


def target_column(y: np.ndarray, column: int, name: str) -> np.ndarray:
    """Column ``column`` of a 2-D label array (or the 1-D array itself), as float."""
    col = y if y.ndim == 1 else y[:, column]
    try:
        return np.asarray(col, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numeric, got values like {col[:3]!r}") from None


def nearest_values(values: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Index into sorted ``grid`` of the entry nearest to each of ``values`` (ties: lower)."""
    grid = np.asarray(grid, dtype=float)
    if grid.size == 1:
        return np.zeros(np.shape(values), dtype=np.intp)
    mid = 0.5 * (grid[1:] + grid[:-1])
    return np.searchsorted(mid, values, side="left")


class TrialClassifier(ClassifierMixin, BaseEstimator):
    """Base class: validation of trials and joint encoding of multi-target labels.

    Fitted attributes set by :meth:`fit`
    ------------------------------------
    classes_ : ndarray of shape (n_classes,) or (n_classes, n_targets)
        The distinct labels (rows of a 2-D ``y``), sorted.
    n_channels_, n_timepoints_ : int
        Shape of one training trial.
    n_features_in_ : int
        ``n_channels_ * n_timepoints_`` (equals the column count of a 2-D ``X``).
    """

    # -- validation ------------------------------------------------------------------
    def _check_X(self, X: Any, *, reset: bool) -> np.ndarray:
        """Validate ``X`` and return it as a float64 array (n_trials, n_channels, n_timepoints)."""
        name = type(self).__name__
        if isinstance(X, list | tuple):
            try:
                X = np.asarray(X)
            except ValueError:
                raise ValueError(
                    f"X must be a rectangular array of trials; {name} does not accept "
                    "recordings of unequal length"
                ) from None
        ndim = getattr(X, "ndim", None)
        if ndim == 3:
            arr = check_array(
                X, allow_nd=True, dtype=np.float64, ensure_all_finite=True, input_name="X"
            )
            n_ch, n_t = arr.shape[1], arr.shape[2]
            if n_ch < 1 or n_t < 1:
                raise ValueError(f"X has an empty channel or time axis: shape {arr.shape}")
            if reset:
                # n_features_in_ and feature names refer to the 2-D case only.
                if hasattr(self, "feature_names_in_"):
                    del self.feature_names_in_
                self.n_features_in_ = n_ch * n_t
        else:
            fitted_2d = not reset and getattr(self, "n_channels_", 1) == 1
            if not reset and not fitted_2d:
                raise ValueError(
                    f"X is 2-D (one channel), but {name} was fitted on "
                    f"{self.n_channels_} channels; pass an array of shape "
                    f"(n_trials, {self.n_channels_}, {self.n_timepoints_})"
                )
            arr = validate_data(self, X, reset=reset, dtype=np.float64, ensure_all_finite=True)
            arr = arr[:, None, :]
            n_ch, n_t = 1, arr.shape[2]
        if reset:
            self.n_channels_ = n_ch
            self.n_timepoints_ = n_t
        else:
            if n_ch != self.n_channels_:
                raise ValueError(
                    f"X has {n_ch} channels, but {name} is expecting "
                    f"{self.n_channels_} channels as input"
                )
            if n_t != self.n_timepoints_:
                raise ValueError(
                    f"X has {n_t} timepoints, but {name} is expecting "
                    f"{self.n_timepoints_} timepoints as input"
                )
        return check_magnitude(arr)

    def _encode_y(self, y: Any, n_trials: int) -> np.ndarray:
        """Set ``classes_`` from ``y`` and return each trial's class index."""
        if y is None:
            raise ValueError(
                f"{type(self).__name__} requires y to be passed, but the target y is None"
            )
        y_arr = np.asarray(y)
        if y_arr.ndim not in (1, 2) or (y_arr.ndim == 2 and y_arr.shape[1] == 0):
            raise ValueError(
                f"y must have shape (n_trials,) or (n_trials, n_targets), got {y_arr.shape}"
            )
        if y_arr.shape[0] != n_trials:
            raise ValueError(
                f"X and y have inconsistent numbers of trials: {n_trials} and {y_arr.shape[0]}"
            )
        if y_arr.dtype.kind in "fc" and not np.all(np.isfinite(y_arr)):
            raise ValueError("y contains NaN or infinite values")
        if y_arr.dtype.kind == "O":
            y_arr = y_arr.astype(str) if all(isinstance(v, str) for v in y_arr.ravel()) else y_arr
        if y_arr.ndim == 1:
            classes, y_idx = np.unique(y_arr, return_inverse=True)
        elif y_arr.dtype.kind == "O":
            # mixed columns (numbers and strings, see vibrissa.data.as_arrays): each
            # column is sorted on its own, rows in lexicographic order of the columns
            codes = np.column_stack(
                [np.unique(y_arr[:, k], return_inverse=True)[1].ravel()
                 for k in range(y_arr.shape[1])])
            _, first, y_idx = np.unique(codes, axis=0, return_index=True, return_inverse=True)
            classes = y_arr[first]
        else:
            classes, y_idx = np.unique(y_arr, axis=0, return_inverse=True)
        if len(classes) < 2:
            raise ValueError(
                f"y has a single class ({classes[0]!r}); {type(self).__name__} needs at "
                "least 2 classes. Classifier can't train when only one class is present."
            )
        self.classes_ = classes
        return np.asarray(y_idx).ravel()

    # -- the estimator API -----------------------------------------------------------
    def fit(self, X: Any, y: Any) -> TrialClassifier:
        """Fit the classifier on training trials.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
            Training trials, time last; finite values only.
        y : array-like of shape (n_trials,) or (n_trials, n_targets)
            Labels; each distinct row is one joint class.

        Returns
        -------
        self
        """
        X3 = self._check_X(X, reset=True)
        y_idx = self._encode_y(y, X3.shape[0])
        self._fit(X3, y, y_idx)
        return self

    def predict_proba(self, X: Any) -> np.ndarray:
        """Class probabilities, columns ordered as ``classes_``.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)

        Returns
        -------
        ndarray of shape (n_trials, n_classes)
            Softmax of the classifier's joint scores; rows sum to 1.
        """
        check_is_fitted(self)
        X3 = self._check_X(X, reset=False)
        return softmax(self._joint_scores(X3), axis=1)

    def predict(self, X: Any) -> np.ndarray:
        """Most probable joint class of each trial.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)

        Returns
        -------
        ndarray of shape (n_trials,) or (n_trials, n_targets)
            Rows of ``classes_`` (the argmax of :meth:`predict_proba`).
        """
        proba = self.predict_proba(X)
        return self.classes_[np.argmax(proba, axis=1)]

    def score(self, X: Any, y: Any, sample_weight: Any = None) -> float:
        """Joint accuracy: fraction of trials whose whole label row is predicted exactly.

        Target columns that the classifier does not predict (NaN in ``classes_``,
        e.g. speed for :class:`StaticBeamClassifier`) are ignored.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        y : array-like of shape (n_trials,) or (n_trials, n_targets)
        sample_weight : array-like of shape (n_trials,), optional

        Returns
        -------
        float
        """
        pred = self.predict(X)
        y_arr = np.asarray(y)
        if y_arr.shape != pred.shape:
            raise ValueError(f"y has shape {y_arr.shape}, predictions have shape {pred.shape}")
        equal = pred == y_arr
        if pred.dtype.kind == "f":
            equal |= np.isnan(pred)
        if equal.ndim == 2:
            equal = equal.all(axis=1)
        return float(np.average(equal, weights=sample_weight))

    def __sklearn_tags__(self):  # noqa: D105
        tags = super().__sklearn_tags__()
        tags.target_tags.multi_output = True
        tags.target_tags.single_output = True
        return tags

    # -- to implement ----------------------------------------------------------------
    def _fit(self, X: np.ndarray, y: Any, y_idx: np.ndarray) -> None:  # pragma: no cover
        raise NotImplementedError

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError
