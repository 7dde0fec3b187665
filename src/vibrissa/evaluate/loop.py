"""What every experiment's evaluation shares: one fit-and-score step, progress, JSON values.

- :func:`fit_predict` clones an estimator, fits it, classifies a test set and times
  both (a :class:`FitRecord`); :func:`fit_and_score` adds a scorer. Both pass the
  dataset's sample rate to the estimator at fit and check it before classifying, so
  an estimator built for another rate is refused (:func:`check_rates` refuses it
  before any work). Chapter 4
  (:mod:`~vibrissa.thesis.radial_distance.evaluation`) and chapter 5
  (:mod:`~vibrissa.thesis.angle_texture.evaluation`) both go through it, so a classifier that fails
  is named the same way and every ``fit_seconds`` / ``classify_seconds`` in a
  results file is measured the same way.
- :class:`Progress` reports steps to a callable ``(done, total, description)`` or a
  rich ``Progress``.
- :func:`json_value` turns numpy scalars, non-finite floats and other attribute
  values into plain JSON values.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from sklearn.base import clone

from vibrissa.classify import check_sample_rate, sample_rate_fit_params

__all__ = [
    "FitRecord",
    "Progress",
    "ProgressLike",
    "check_rates",
    "fit_and_score",
    "fit_predict",
    "json_value",
]

#: A callable ``(done, total, description)``, a rich ``Progress`` or ``None``.
ProgressLike = Any


def json_value(v: Any) -> Any:
    """A value as plain JSON: numpy scalars as Python values, NaN/inf as ``None``.

    Strings, booleans, integers and finite floats pass through; anything else
    (e.g. a tuple attribute) becomes its ``str``.
    """
    if isinstance(v, np.generic):
        v = v.item()
    if v is None or isinstance(v, bool | int | str):
        return v
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    return str(v)


@dataclass
class FitRecord:
    """One estimator fitted on a training set and run on a test set.

    Attributes
    ----------
    estimator
        The fitted clone (the caller's estimator is never modified).
    y_pred : numpy.ndarray
        Predictions on the test set, as float.
    fit_seconds, classify_seconds : float
        Wall time of ``fit`` and of ``predict`` on the whole test set.
    n_train, n_test : int
        Trials in each set.
    """

    estimator: Any
    y_pred: np.ndarray
    fit_seconds: float
    classify_seconds: float
    n_train: int
    n_test: int

    def timing(self) -> dict[str, Any]:
        """The JSON record every experiment keeps per fit."""
        return {
            "fit_seconds": self.fit_seconds,
            "classify_seconds": self.classify_seconds,
            "n_train": self.n_train,
            "n_test": self.n_test,
        }


def check_rates(classifiers: Mapping[str, Any], sample_rate_hz: float) -> None:
    """Refuse, before any work, classifiers built for another rate than the data's.

    Parameters
    ----------
    classifiers : mapping of str to estimator
    sample_rate_hz : float
        The dataset's sample rate, Hz.

    Raises
    ------
    ValueError
        Naming the classifier, the step, its rate and the dataset's
        (:func:`vibrissa.classify.check_sample_rate`).
    """
    for name, est in classifiers.items():
        try:
            check_sample_rate(est, sample_rate_hz)
        except ValueError as exc:
            raise ValueError(f"classifier {name!r} does not fit the dataset: {exc}") from None


def fit_predict(
    name: str,
    estimator: Any,
    X_train: np.ndarray,
    y_train: np.ndarray,
    X_test: np.ndarray,
    *,
    sample_rate_hz: float | None = None,
) -> FitRecord:
    """Fit a clone of ``estimator`` on the training set and classify the test set.

    Parameters
    ----------
    name : str
        Classifier name, used in the error raised when it fails to fit.
    estimator : sklearn estimator
        Cloned, never modified.
    X_train, y_train, X_test : numpy.ndarray
        Trials ``(n, n_channels, n_timepoints)`` and label rows.
    sample_rate_hz : float, optional
        Sample rate of the trials, Hz: passed to every rate-aware step at fit
        (:func:`vibrissa.classify.sample_rate_fit_params`) and checked against the
        fitted estimator before it classifies the test set.

    Returns
    -------
    FitRecord

    Raises
    ------
    Exception
        Whatever ``fit`` raised, with the classifier's name in the message (the
        original type where it can be rebuilt from a message, else RuntimeError).
    """
    est = clone(estimator)
    t0 = time.perf_counter()
    try:
        est.fit(X_train, y_train, **sample_rate_fit_params(est, sample_rate_hz))
    except Exception as exc:  # name the classifier, keep the original type where possible
        msg = f"classifier {name!r} failed to fit: {exc}"
        try:
            wrapped = type(exc)(msg)
        except Exception:
            raise RuntimeError(msg) from exc
        raise wrapped from exc
    t1 = time.perf_counter()
    if sample_rate_hz is not None:
        check_sample_rate(est, sample_rate_hz)
    y_pred = np.asarray(est.predict(X_test), dtype=float)
    t2 = time.perf_counter()
    return FitRecord(est, y_pred, t1 - t0, t2 - t1, int(X_train.shape[0]), int(X_test.shape[0]))


def fit_and_score(
    name: str,
    estimator: Any,
    X_train: np.ndarray,
    y_train: np.ndarray,
    X_test: np.ndarray,
    y_test: np.ndarray,
    score: Callable[[np.ndarray, np.ndarray, FitRecord], dict[str, Any]],
    *,
    sample_rate_hz: float | None = None,
) -> tuple[dict[str, Any], FitRecord]:
    """:func:`fit_predict`, then ``score(y_test, y_pred, record)`` plus the timing record.

    Raises
    ------
    ValueError
        When the predictions' shape differs from ``y_test``'s.
    """
    rec = fit_predict(name, estimator, X_train, y_train, X_test, sample_rate_hz=sample_rate_hz)
    y_test = np.asarray(y_test, dtype=float)
    if rec.y_pred.shape != y_test.shape:
        raise ValueError(
            f"classifier {name!r} predicted shape {rec.y_pred.shape}, expected {y_test.shape} "
            "(one row of labels per test trial)"
        )
    out = score(y_test, rec.y_pred, rec)
    out.update(rec.timing())
    return out, rec


class Progress:
    """Steps of an evaluation, reported to a callable or a rich ``Progress``.

    Parameters
    ----------
    progress : callable, rich.progress.Progress or None
        A callable is called as ``progress(done, total, description)`` after every
        step; on a rich ``Progress`` one task is added and advanced.
    total : int
        Number of steps.
    label : str
        The rich task's description before the first step.
    """

    def __init__(self, progress: ProgressLike, total: int, label: str = "evaluating") -> None:
        self.done = 0
        self.total = int(total)
        self._cb: Callable[[int, int, str], Any] | None = None
        self._rich: Any = None
        self._task: Any = None
        if progress is None:
            return
        if hasattr(progress, "add_task") and hasattr(progress, "update"):
            self._rich = progress
            self._task = progress.add_task(label, total=self.total)
        elif callable(progress):
            self._cb = progress
        else:
            raise TypeError(
                "progress must be None, a callable (done, total, description) or a "
                f"rich.progress.Progress, got {type(progress).__name__}"
            )

    def step(self, description: str) -> None:
        """One step done."""
        self.done += 1
        if self._cb is not None:
            self._cb(self.done, self.total, description)
        elif self._rich is not None:
            self._rich.update(self._task, completed=self.done, description=description)
