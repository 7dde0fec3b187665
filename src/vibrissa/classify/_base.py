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

Sample rates
------------
Every estimator of :mod:`vibrissa.classify` records the sample rate it was fitted
at (:class:`SampleRateMixin`): ``fit(X, y, sample_rate_hz=fs)`` refuses data at
another rate than the estimator was built for, stores ``sample_rate_hz_``, and
``predict``/``predict_proba``/``score``/``transform`` refuse ``sample_rate_hz=`` of
another rate. ``Estimator.from_dataset(ds, **params)`` builds an estimator for the
rate of a Dataset (its attribute ``sample_rate_hz``). For a
:class:`~sklearn.pipeline.Pipeline` (or any estimator),
:func:`sample_rate_fit_params` gives the fit parameters that pass the rate to every
step (following the rate through steps that downsample) and
:func:`check_sample_rate` refuses one whose steps were built or fitted for another.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import softmax
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.pipeline import Pipeline
from sklearn.utils.validation import check_array, check_is_fitted, validate_data

from vibrissa._validate import positive

__all__ = [
    "MAX_ABS_INPUT",
    "RATE_RTOL",
    "EstimatorTags",
    "SampleRateMixin",
    "TrialClassifier",
    "check_magnitude",
    "check_sample_rate",
    "dataset_sample_rate",
    "estimator_tags",
    "fitted_sample_rate",
    "nearest_values",
    "sample_rate_fit_params",
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
        # max |X| without a temporary |X| (NaN in X gives NaN either way)
        largest = float(max(np.max(X), -np.min(X)))
        if not largest <= MAX_ABS_INPUT:
            raise ValueError(
                f"{name} has values as large as {largest:.3g} in magnitude; the classifiers "
                f"accept |{name}| <= {MAX_ABS_INPUT:.0e} (larger values overflow their "
                "arithmetic); rescale the signals (e.g. to volts)"
            )
    return X


#: Relative tolerance within which two sample rates are the same rate (a rate read
#: from a file and one computed as ``fs / downsample`` may differ in the last bits).
RATE_RTOL = 1e-9


def _hz(rate: float) -> str:
    return f"{float(rate):g} Hz"


def _same_rate(a: float, b: float) -> bool:
    return math.isclose(float(a), float(b), rel_tol=RATE_RTOL, abs_tol=0.0)


def dataset_sample_rate(ds: Any) -> float:
    """The sample rate of a Dataset, Hz: its attribute ``sample_rate_hz``.

    Parameters
    ----------
    ds : xarray.Dataset
        E.g. from :func:`vibrissa.data.load_dataset`.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``ds`` has no ``attrs`` mapping (is not a Dataset).
    ValueError
        If the attribute is missing or not a positive finite number.
    """
    attrs = getattr(ds, "attrs", None)
    if not isinstance(attrs, Mapping):
        raise TypeError(f"ds must be an xarray.Dataset, got {type(ds).__name__}")
    if attrs.get("sample_rate_hz") is None:
        raise ValueError("the dataset has no attribute 'sample_rate_hz' (its sampling rate, Hz)")
    return positive("the dataset's attribute 'sample_rate_hz'", attrs["sample_rate_hz"])


class SampleRateMixin:
    """Estimators that record the sample rate they were fitted at and refuse another.

    An estimator whose computation uses the sample rate has a constructor parameter
    ``sample_rate_hz`` (the rate it is built for); one that does not use it (e.g.
    :class:`StaticBeamClassifier`) has ``sample_rate_hz=None`` by default and then
    takes the rate of the data it is fitted on.

    - ``fit(X, y, sample_rate_hz=fs)`` refuses ``fs`` when the estimator (or a
      sub-estimator it fits) is built for another rate, in one ``ValueError`` naming
      both, and stores ``sample_rate_hz_``: ``fs``, else the constructor's rate
      (``None`` when neither is known).
    - ``predict``, ``predict_proba``, ``score`` and ``transform`` take an optional
      ``sample_rate_hz=`` and refuse a rate other than ``sample_rate_hz_``.
    - :meth:`from_dataset` builds the estimator for a Dataset's rate.

    Attributes
    ----------
    sample_rate_hz_ : float or None
        The rate the estimator was fitted at, Hz.
    """

    @classmethod
    def from_dataset(cls, ds: Any, **params: Any) -> Any:
        """The estimator built for the sample rate of ``ds`` (its attribute ``sample_rate_hz``).

        Parameters
        ----------
        ds : xarray.Dataset
            The data the estimator is for (e.g. from :func:`vibrissa.data.load_dataset`).
        **params
            Further constructor parameters. A ``sample_rate_hz`` among them must be
            the dataset's rate.

        Returns
        -------
        estimator
            Unfitted, with ``sample_rate_hz`` set to the dataset's rate.

        Raises
        ------
        TypeError
            If the estimator takes no sample rate (e.g. a wrapper of another estimator:
            build that one with ``from_dataset``).
        ValueError
            If the dataset has no valid rate, or ``sample_rate_hz`` differs from it.
        """
        rate = dataset_sample_rate(ds)
        if "sample_rate_hz" not in cls._get_param_names():  # type: ignore[attr-defined]
            raise TypeError(
                f"{cls.__name__} takes no sample rate of its own; build the estimator it "
                "wraps with from_dataset"
            )
        given = params.pop("sample_rate_hz", None)
        if given is not None and not _same_rate(positive("sample_rate_hz", given), rate):
            raise ValueError(
                f"sample_rate_hz={given!r} differs from the dataset's rate, {_hz(rate)}"
            )
        return cls(sample_rate_hz=rate, **params)

    # -- what subclasses may override ----------------------------------------------------
    def _rate_parts(self) -> list[tuple[str, Any]]:
        """Sub-estimators ``(parameter name, estimator)`` that see this estimator's input."""
        return []

    def _rate_after(self, sample_rate_hz: float) -> float:
        """Sample rate of this step's output for input at ``sample_rate_hz`` (a Pipeline step)."""
        return sample_rate_hz

    # -- the checks ----------------------------------------------------------------------
    def _configured_rate(self) -> float | None:
        rate = getattr(self, "sample_rate_hz", None)
        return None if rate is None else positive("sample_rate_hz", rate)

    def _check_configured_rate(self, sample_rate_hz: float) -> None:
        """Refuse data at ``sample_rate_hz`` when this estimator or a part is built for another."""
        name = type(self).__name__
        configured = self._configured_rate()
        if configured is not None and not _same_rate(configured, sample_rate_hz):
            raise ValueError(
                f"{name} is built for sample_rate_hz={configured:g} Hz, but the data are "
                f"sampled at {_hz(sample_rate_hz)}; build it for the data's rate "
                f"(sample_rate_hz={float(sample_rate_hz):g}, e.g. {name}.from_dataset(ds))"
            )
        for part, est in self._rate_parts():
            try:
                check_sample_rate(est, sample_rate_hz)
            except ValueError as exc:
                raise ValueError(f"{name}'s {part}: {exc}") from None

    def _check_rate(self, sample_rate_hz: float) -> None:
        """Refuse data at ``sample_rate_hz`` when fitted, built or with parts for another."""
        rate = positive("sample_rate_hz", sample_rate_hz)
        fitted = getattr(self, "sample_rate_hz_", None)
        if fitted is not None and not _same_rate(fitted, rate):
            raise ValueError(
                f"{type(self).__name__} was fitted on data sampled at {_hz(fitted)}, but "
                f"these data are sampled at {_hz(rate)}; fit it on data at {_hz(rate)}"
            )
        self._check_configured_rate(rate)

    def _fit_rate(self, sample_rate_hz: float | None) -> float | None:
        """The rate to fit at (given, else configured), checked; ``None`` if neither."""
        if sample_rate_hz is None:
            rate = self._configured_rate()
        else:
            rate = positive("sample_rate_hz", sample_rate_hz)
        if rate is not None:
            self._check_configured_rate(rate)
        return rate

    def _check_predict_rate(self, sample_rate_hz: float | None) -> None:
        check_is_fitted(self)
        if sample_rate_hz is not None:
            self._check_rate(sample_rate_hz)


def _rate_steps(estimator: Any, rate: float) -> tuple[list[tuple[str, Any, float]], float]:
    """``(path, step, input rate)`` of each rate-aware step of ``estimator``; its output rate."""
    if isinstance(estimator, Pipeline):
        out: list[tuple[str, Any, float]] = []
        for name, step in estimator.steps:
            if step is None or (isinstance(step, str) and step == "passthrough"):
                continue
            sub, rate = _rate_steps(step, rate)
            out += [(f"{name}__{path}" if path else name, s, r) for path, s, r in sub]
        return out, rate
    if isinstance(estimator, SampleRateMixin):
        return [("", estimator, rate)], estimator._rate_after(rate)
    return [], rate


def sample_rate_fit_params(estimator: Any, sample_rate_hz: float | None) -> dict[str, float]:
    """Fit parameters that pass a sample rate to an estimator or every step of a Pipeline.

    ``estimator.fit(X, y, **sample_rate_fit_params(estimator, fs))`` fits every
    :class:`SampleRateMixin` step at the rate of its own input: ``fs`` for the first,
    then as changed by each step (a :class:`SignalTransform` with ``downsample=k``
    passes on ``fs / k``). Other estimators take no parameter.

    Parameters
    ----------
    estimator : estimator or Pipeline
    sample_rate_hz : float or None
        The data's rate, Hz; ``None`` gives no parameters.

    Returns
    -------
    dict
        ``{"sample_rate_hz": fs}`` for a rate-aware estimator,
        ``{"<step>__sample_rate_hz": rate, ...}`` for a Pipeline, ``{}`` otherwise.
    """
    if sample_rate_hz is None:
        return {}
    steps, _ = _rate_steps(estimator, positive("sample_rate_hz", sample_rate_hz))
    return {(f"{path}__" if path else "") + "sample_rate_hz": r for path, _, r in steps}


def check_sample_rate(estimator: Any, sample_rate_hz: float) -> None:
    """Refuse an estimator (each step of a Pipeline) built or fitted for another sample rate.

    Parameters
    ----------
    estimator : estimator or Pipeline, fitted or not
    sample_rate_hz : float
        The rate of the data it is to be fitted on or applied to, Hz.

    Raises
    ------
    ValueError
        Naming the step, the rate it is built or fitted for and ``sample_rate_hz``.
    """
    steps, _ = _rate_steps(estimator, positive("sample_rate_hz", sample_rate_hz))
    for path, step, rate in steps:
        try:
            step._check_rate(rate)
        except ValueError as exc:
            raise ValueError(f"step {path!r}: {exc}" if path else str(exc)) from None


def fitted_sample_rate(estimator: Any) -> float | None:
    """The rate a fitted estimator (the first rate-aware step of a Pipeline) was fitted at."""
    steps, _ = _rate_steps(estimator, 1.0)
    rate = getattr(steps[0][1], "sample_rate_hz_", None) if steps else None
    return None if rate is None else float(rate)


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


#: Scores this close to a row's best may tie with it after the softmax's rounding.
_NEAR_SCORE = 1e-9


def argmax_softmax(scores: np.ndarray) -> np.ndarray:
    """``np.argmax(softmax(scores, axis=1), axis=1)``, computing the softmax only where needed.

    The row maximum has ``exp(0) = 1``; a score below it by more than
    :data:`_NEAR_SCORE` has ``exp`` smaller by far more than a rounding error, so
    its probability is smaller and the first maximum of the scores is the first
    maximum of the probabilities. Where another score lies within
    :data:`_NEAR_SCORE` of a row's maximum (an exact tie included), rounding in
    ``exp`` and in the division could make an earlier class tie with the best one
    after all: then the softmax of the whole array is computed, as
    :meth:`TrialClassifier.predict_proba` does, and its argmax taken.

    Parameters
    ----------
    scores : numpy.ndarray of shape (n_trials, n_classes)

    Returns
    -------
    numpy.ndarray of int, shape (n_trials,)
    """
    scores = np.asarray(scores)
    best = np.argmax(scores, axis=1)
    if scores.size == 0:
        return best
    top = scores[np.arange(scores.shape[0]), best]
    # the softmax's own differences x - max(x); the best class's is 0
    near = np.count_nonzero(scores - top[:, None] > -_NEAR_SCORE, axis=1) > 1
    if near.any() or not np.all(np.isfinite(top)):
        return np.argmax(softmax(scores, axis=1), axis=1)
    return best


class TrialClassifier(SampleRateMixin, ClassifierMixin, BaseEstimator):
    """Base class: validation of trials and joint encoding of multi-target labels.

    Fitted attributes set by :meth:`fit`
    ------------------------------------
    classes_ : ndarray of shape (n_classes,) or (n_classes, n_targets)
        The distinct labels (rows of a 2-D ``y``), sorted.
    n_channels_, n_timepoints_ : int
        Shape of one training trial.
    n_features_in_ : int
        ``n_channels_ * n_timepoints_`` (equals the column count of a 2-D ``X``).
    sample_rate_hz_ : float or None
        The rate the classifier was fitted at, Hz (see :class:`SampleRateMixin`).
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
                [
                    np.unique(y_arr[:, k], return_inverse=True)[1].ravel()
                    for k in range(y_arr.shape[1])
                ]
            )
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
    def fit(self, X: Any, y: Any, sample_rate_hz: float | None = None) -> TrialClassifier:
        """Fit the classifier on training trials.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
            Training trials, time last; finite values only.
        y : array-like of shape (n_trials,) or (n_trials, n_targets)
            Labels; each distinct row is one joint class.
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz. Refused when the classifier is built for
            another; default: the rate it is built for.

        Returns
        -------
        self
        """
        rate = self._fit_rate(sample_rate_hz)
        X3 = self._check_X(X, reset=True)
        y_idx = self._encode_y(y, X3.shape[0])
        self.sample_rate_hz_ = rate
        self._fit(X3, y, y_idx)
        return self

    def _fitted_input(self, X: Any, sample_rate_hz: float | None) -> np.ndarray:
        """``X`` validated against the fitted shape (and rate, when given), as 3-D float64."""
        self._check_predict_rate(sample_rate_hz)
        return self._check_X(X, reset=False)

    def predict_proba(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Class probabilities, columns ordered as ``classes_``.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_classes)
            Softmax of the classifier's joint scores; rows sum to 1.
        """
        return softmax(self._joint_scores(self._fitted_input(X, sample_rate_hz)), axis=1)

    def predict(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Most probable joint class of each trial.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials,) or (n_trials, n_targets)
            Rows of ``classes_`` (the argmax of :meth:`predict_proba`).
        """
        if type(self).predict_proba is not TrialClassifier.predict_proba:
            proba = self.predict_proba(X, sample_rate_hz=sample_rate_hz)
            return self.classes_[np.argmax(proba, axis=1)]
        scores = self._joint_scores(self._fitted_input(X, sample_rate_hz))
        return self.classes_[argmax_softmax(scores)]

    def score(
        self, X: Any, y: Any, sample_weight: Any = None, sample_rate_hz: float | None = None
    ) -> float:
        """Joint accuracy: fraction of trials whose whole label row is predicted exactly.

        Target columns that the classifier does not predict (NaN in ``classes_``,
        e.g. speed for :class:`StaticBeamClassifier`) are ignored.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
        y : array-like of shape (n_trials,) or (n_trials, n_targets)
        sample_weight : array-like of shape (n_trials,), optional
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        float
        """
        pred = self.predict(X, sample_rate_hz=sample_rate_hz)
        y_arr = np.asarray(y)
        if y_arr.shape != pred.shape:
            raise ValueError(f"y has shape {y_arr.shape}, predictions have shape {pred.shape}")
        equal = pred == y_arr
        if pred.dtype.kind == "f":
            equal |= np.isnan(pred)
        if equal.ndim == 2:
            equal = equal.all(axis=1)
        return float(np.average(equal, weights=sample_weight))

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.target_tags.multi_output = True
        tags.target_tags.single_output = True
        return tags

    # -- to implement ----------------------------------------------------------------
    def _fit(self, X: np.ndarray, y: Any, y_idx: np.ndarray) -> None:  # pragma: no cover
        raise NotImplementedError

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError
