"""The chapter-4 evaluation protocol (thesis 4.2-4.4).

The thesis recorded four complete grids of contacts (2 runs x 2 directions,
4.2). Training and test sets "were each complete data sets of 26 speeds and 101
radial distances" placed "at random from the original data" (4.3); reduced
training sets are the first ``fraction x N`` trials of a random permutation of
the training set, for 80, 60, 40, 20, 10 and 5 %, repeated with five random
seeds (4.3). Every classifier reports the mean and spread of the signed error
of radial distance and speed (tables 4.2-4.5, 4.7), the static beam its radial
error per speed (figures 4.2b, 4.3b), and each its computing time (table 4.6).

:func:`run_chapter4` runs all of it and returns a plain dict that serialises to
JSON (the contract is in its docstring); the building blocks
(:func:`check_dataset`, :func:`split_sets`, :func:`subsample_indices`,
:func:`score_predictions`, :func:`fit_and_score`) are public for other protocols.

Seeds: the train/test split draws from ``numpy.random.default_rng(seed)``; the
reduced subsets of repeat ``k`` (0-based) from ``numpy.random.default_rng([seed, k])``,
one permutation per repeat shared by all fractions (so, as in the thesis, the
5 % subset is the head of the 10 % subset, and so on).
"""

from __future__ import annotations

import math
import time
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from sklearn.base import clone
from sklearn.pipeline import Pipeline

from vibrissa.classify import (
    RecordingWindow,
    check_sample_rate,
    dataset_sample_rate,
    estimator_tags,
    sample_rate_fit_params,
)
from vibrissa.evaluate import metrics
from vibrissa.evaluate.jobs import SharedArrays, resolve_workers, run_jobs
from vibrissa.evaluate.loop import FitRecord, Progress, ProgressLike, check_rates, json_value
from vibrissa.evaluate.loop import fit_and_score as loop_fit_and_score
from vibrissa.evaluate.splits import Split

__all__ = [
    "ORACLE_ANGLE_LABEL",
    "ORACLE_ANGLE_NAMES",
    "PARAMETERS",
    "THESIS_FRACTIONS",
    "Split",
    "check_dataset",
    "dataset_arrays",
    "fit_and_score",
    "fitted_parameters",
    "fraction_key",
    "is_radius_only",
    "oracle_angle_scores",
    "run_chapter4",
    "run_oracle_angle",
    "score_predictions",
    "split_sets",
    "subsample_combinations",
    "subsample_indices",
]

#: Dataset coordinate -> result key, in the column order of ``y``.
PARAMETERS: dict[str, str] = {"radial_distance_mm": "radius_mm", "speed_mm_s": "speed_mm_s"}

#: Reduced training-set sizes of the thesis (4.3), as fractions of the training set.
THESIS_FRACTIONS: tuple[float, ...] = (0.8, 0.6, 0.4, 0.2, 0.1, 0.05)

_REQUIRED_COORDS = ("radial_distance_mm", "speed_mm_s", "set")

#: The label of the static beam rows that use the thesis author's protraction angle.
ORACLE_ANGLE_LABEL = "author's angle (oracle: true speed and radius of each test trial)"

#: The static-beam classifiers evaluated again with the author's oracle angle.
ORACLE_ANGLE_NAMES: tuple[str, ...] = ("static_beam_measured", "static_beam_fitted")

#: Trials windowed at a time when the reduced training sets' windows are cut.
_WINDOW_BLOCK = 2048


# --------------------------------------------------------------------------- dataset
def check_dataset(ds: xr.Dataset, *, require_complete: bool = True) -> dict[Any, np.ndarray]:
    """Validate a chapter-4 dataset and return the trial indices of each recorded set.

    Parameters
    ----------
    ds : xarray.Dataset
        Needs the variable ``signal`` with dims ``trial``, ``channel``, ``time`` and
        the per-trial coordinates ``radial_distance_mm``, ``speed_mm_s`` and ``set``.
    require_complete : bool, default=True
        Require every set to hold every (radial distance, speed) combination of the
        dataset's grid at least once ("complete data sets", thesis 4.3).

    Returns
    -------
    dict
        Set value -> sorted trial indices (positions along ``trial``), in sorted
        order of the set values.

    Raises
    ------
    ValueError
        Naming what is missing: the variable, a dimension, a coordinate, a second
        set, or the combinations a set lacks.
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"ds must be an xarray.Dataset, got {type(ds).__name__}")
    if "signal" not in ds.data_vars:
        raise ValueError("dataset has no 'signal' variable (dims trial, channel, time)")
    dims = set(ds["signal"].dims)
    missing_dims = [d for d in ("trial", "channel", "time") if d not in dims]
    if missing_dims or len(dims) != 3:
        raise ValueError(
            "dataset 'signal' must have dims (trial, channel, time), got "
            f"{tuple(ds['signal'].dims)}"
        )
    missing = [c for c in _REQUIRED_COORDS if c not in ds.coords and c not in ds.data_vars]
    if missing:
        raise ValueError(
            "dataset lacks the per-trial coordinate(s) "
            + ", ".join(repr(m) for m in missing)
            + " needed by the chapter-4 protocol"
        )
    for c in _REQUIRED_COORDS:
        if ds[c].dims != ("trial",):
            raise ValueError(f"coordinate {c!r} must have dims ('trial',), got {ds[c].dims}")
    n = ds.sizes["trial"]
    if n == 0:
        raise ValueError("dataset has no trials")
    for c in ("radial_distance_mm", "speed_mm_s"):
        vals = np.asarray(ds[c].values, dtype=float)
        if not np.all(np.isfinite(vals)):
            raise ValueError(f"coordinate {c!r} contains NaN or infinite values")
    set_vals = np.asarray(ds["set"].values)
    sets = np.unique(set_vals)
    if sets.shape[0] < 2:
        raise ValueError(
            f"the chapter-4 protocol needs at least 2 recorded sets (one to train, one to test); "
            f"dataset has {sets.shape[0]}"
        )
    groups = {json_value(s): np.flatnonzero(set_vals == s) for s in sets}
    if require_complete:
        r = np.round(np.asarray(ds["radial_distance_mm"].values, dtype=float), 6)
        v = np.round(np.asarray(ds["speed_mm_s"].values, dtype=float), 6)
        grid = {(a, b) for a in np.unique(r) for b in np.unique(v)}
        for s, idx in groups.items():
            have = set(zip(r[idx].tolist(), v[idx].tolist(), strict=True))
            lack = grid - have
            if lack:
                ex = sorted(lack)[:3]
                raise ValueError(
                    f"set {s!r} is not a complete grid: it lacks {len(lack)} of {len(grid)} "
                    f"(radial_distance_mm, speed_mm_s) combinations, e.g. {ex}"
                )
    return groups


def dataset_arrays(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Trials and labels of a dataset in the package layout.

    Parameters
    ----------
    ds : xarray.Dataset
        Dataset with ``signal`` and the coordinates ``radial_distance_mm`` and
        ``speed_mm_s``.

    Returns
    -------
    X : numpy.ndarray of shape (n_trials, n_channels, n_timepoints)
        The signal, V.
    y : numpy.ndarray of shape (n_trials, 2)
        Columns ``[radial_distance_mm, speed_mm_s]``.
    """
    X = np.asarray(ds["signal"].transpose("trial", "channel", "time").values, dtype=float)
    y = np.column_stack([np.asarray(ds[c].values, dtype=float) for c in PARAMETERS])
    return X, y


# --------------------------------------------------------------------------- splits
def split_sets(
    ds: xr.Dataset,
    seed: int | None = 0,
    *,
    train_set: Any = None,
    test_set: Any = None,
    require_complete: bool = True,
) -> Split:
    """Assign one recorded set to training and another to testing (thesis 4.3).

    Parameters
    ----------
    ds : xarray.Dataset
        Chapter-4 dataset (see :func:`check_dataset`).
    seed : int, default=0
        Seed of the random draw (two distinct sets, without replacement).
    train_set, test_set : optional
        Explicit set values; both or neither. ``train_set`` may be a list of set
        values, pooled for training (the thesis author's naive Bayes trained on
        sets 2-4 and tested on set 1).
    require_complete : bool, default=True
        Passed to :func:`check_dataset`.

    Returns
    -------
    Split
        The assignment; training and test sets never share a trial.
    """
    groups = check_dataset(ds, require_complete=require_complete)
    names = list(groups)
    if (train_set is None) != (test_set is None):
        raise ValueError("give both train_set and test_set, or neither")
    if train_set is not None:
        pooled = list(train_set) if isinstance(train_set, list | tuple) else [train_set]
        if not pooled:
            raise ValueError("train_set must name at least one set")
        for label, vals in (("train_set", pooled), ("test_set", [test_set])):
            for s in vals:
                if s not in groups:
                    raise ValueError(f"{label}={s!r} is not a set of the dataset (sets: {names})")
        if test_set in pooled:
            raise ValueError(
                f"train_set and test_set must differ: test_set {test_set!r} is also a training set"
            )
        if len(set(pooled)) != len(pooled):
            raise ValueError(f"train_set repeats a set: {pooled}")
        used_seed = None
        if len(pooled) > 1:
            idx = np.sort(np.concatenate([groups[s] for s in pooled]))
            return Split(pooled, test_set, idx, groups[test_set], used_seed)
        train_set = pooled[0]
    else:
        rng = np.random.default_rng(seed)
        i, j = rng.choice(len(names), size=2, replace=False)
        train_set, test_set = names[int(i)], names[int(j)]
        used_seed = None if seed is None else int(seed)
    return Split(train_set, test_set, groups[train_set], groups[test_set], used_seed)


def _check_fraction(fraction: float) -> float:
    try:
        f = float(fraction)
    except (TypeError, ValueError):
        raise ValueError(
            f"training fraction must be a number in (0, 1], got {fraction!r}"
        ) from None
    if not math.isfinite(f) or not 0 < f <= 1:
        raise ValueError(f"training fraction must lie in (0, 1], got {fraction!r}")
    return f


def subsample_indices(
    n: int, fraction: float, seed: int | Sequence[int] | np.random.Generator
) -> np.ndarray:
    """Positions of a reduced training set: the first ``round(fraction x n)`` of a permutation.

    Parameters
    ----------
    n : int
        Size of the full training set.
    fraction : float
        Share kept, in (0, 1] (at least one trial is kept).
    seed : int, sequence of int or numpy.random.Generator
        Seed of the permutation; the same seed gives the same permutation for
        every ``fraction``, so smaller subsets are heads of larger ones.

    Returns
    -------
    numpy.ndarray
        Sorted positions in ``range(n)``, without repeats.
    """
    f = _check_fraction(fraction)
    if n < 1:
        raise ValueError(f"cannot subsample an empty training set (n={n})")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    perm = rng.permutation(n)
    k = min(n, max(1, int(round(f * n))))
    return np.sort(perm[:k])


def subsample_combinations(
    y: np.ndarray, fraction: float, seed: int | Sequence[int] | np.random.Generator
) -> np.ndarray:
    """Positions of a reduced training set drawn by class: all trials of a subset of classes.

    The thesis permuted the 2,626 (speed, radial distance) combinations and kept the
    first ``fraction x N`` of them, with every recorded trial of each kept
    combination (4.3; the author's naive Bayes kept all three training trials of a
    class). With one trial per class this is :func:`subsample_indices`.

    Parameters
    ----------
    y : numpy.ndarray of shape (n_trials, n_targets)
        Labels of the full training set; each distinct row is one class.
    fraction, seed
        As for :func:`subsample_indices` (the permutation is over classes).

    Returns
    -------
    numpy.ndarray
        Sorted trial positions.
    """
    _, inverse = np.unique(np.round(np.asarray(y, dtype=float), 6), axis=0, return_inverse=True)
    inverse = np.asarray(inverse).ravel()
    keep = subsample_indices(int(inverse.max()) + 1, fraction, seed)
    return np.flatnonzero(np.isin(inverse, keep))


def fraction_key(fraction: float) -> str:
    """The JSON key of a training fraction: ``0.8 -> "0.8"``, ``0.05 -> "0.05"``, ``1 -> "1.0"``."""
    return repr(float(_check_fraction(fraction)))


# --------------------------------------------------------------------------- scoring
def is_radius_only(estimator: Any, y_pred: np.ndarray | None = None) -> bool:
    """Whether a classifier estimates radial distance only (the static beam, thesis 4.3.1).

    True when the estimator's tags say it estimates column 0 alone
    (:func:`vibrissa.classify.estimator_tags`), or when every predicted speed is NaN.
    """
    if estimator_tags(estimator).estimates_only(0):
        return True
    if y_pred is not None:
        col = np.asarray(y_pred, dtype=float)[:, 1]
        return bool(col.size) and bool(np.all(np.isnan(col)))
    return False


def score_predictions(
    y_true: np.ndarray, y_pred: np.ndarray, *, radius_only: bool = False
) -> dict[str, Any]:
    """Per-parameter and joint scores of one classifier on one test set.

    Parameters
    ----------
    y_true, y_pred : numpy.ndarray of shape (n_trials, 2)
        Columns ``[radial_distance_mm, speed_mm_s]``.
    radius_only : bool, default=False
        The classifier estimates radial distance only: speed and joint scores
        are ``None``.

    Returns
    -------
    dict
        ``radius_mm`` and ``speed_mm_s``: :func:`metrics.error_summary` plus
        ``kappa``, ``kappa_linear``, ``kappa_quadratic``; ``joint``:
        ``exact_hit`` and ``kappa`` of the joint class (or ``None``);
        ``radius_error_by_speed``: list of ``{"speed_mm_s", "mean", "std",
        "sem", "exact_hit", "n"}`` of the radial error at each true speed.
    """
    t = np.asarray(y_true, dtype=float)
    p = np.asarray(y_pred, dtype=float)
    if t.ndim != 2 or t.shape[1] != 2 or p.shape != t.shape:
        raise ValueError(
            f"y_true and y_pred must both have shape (n_trials, 2), got {t.shape} and {p.shape}"
        )
    out: dict[str, Any] = {"radius_mm": metrics.parameter_scores(t[:, 0], p[:, 0])}
    if radius_only:
        out["speed_mm_s"] = None
        out["joint"] = None
    else:
        if not np.all(np.isfinite(p[:, 1])):
            raise ValueError("predicted speeds contain NaN or infinite values")
        out["speed_mm_s"] = metrics.parameter_scores(t[:, 1], p[:, 1])
        out["joint"] = {
            "exact_hit": metrics.exact_hit_rate(t, p),
            "kappa": metrics.joint_kappa(t, p),
        }
    by_speed = []
    for s in np.unique(t[:, 1]):
        m = t[:, 1] == s
        summ = metrics.error_summary(t[m, 0], p[m, 0])
        keep = ("mean", "std", "sem", "exact_hit", "n")
        by_speed.append({"speed_mm_s": float(s), **{k: summ[k] for k in keep}})
    out["radius_error_by_speed"] = by_speed
    return out


def fitted_parameters(est: Any) -> dict[str, float]:
    """Scalar fitted physical parameters an estimator exposes (e.g. the static beam's)."""
    if hasattr(est, "steps"):  # a Pipeline: the final estimator holds them
        est = est.steps[-1][1]
    names = (
        "youngs_modulus_gpa_",
        "base_radius_mm_",
        "length_mm_",
        "moment_scale_",
        "protraction_mm_",
        "training_error_mm_",
    )
    out = {}
    for n in names:
        v = getattr(est, n, None)
        if isinstance(v, int | float | np.integer | np.floating) and math.isfinite(float(v)):
            out[n.rstrip("_")] = float(v)
    return out


def fit_and_score(
    name: str,
    estimator: Any,
    X_train: np.ndarray,
    y_train: np.ndarray,
    X_test: np.ndarray,
    y_test: np.ndarray,
    *,
    radius_only: bool | None = None,
    keep_predictions: bool = False,
    sample_rate_hz: float | None = None,
) -> dict[str, Any]:
    """Fit a clone of ``estimator``, classify the test set, time both and score.

    Parameters
    ----------
    name : str
        Classifier name (used in error messages).
    estimator : sklearn estimator
        Takes ``X (n, n_channels, n_timepoints)`` and ``y (n, 2)``; it is cloned,
        never modified.
    X_train, y_train, X_test, y_test : numpy.ndarray
        Trials and ``[radial_distance_mm, speed_mm_s]`` labels.
    radius_only : bool or None
        ``None``: decided by :func:`is_radius_only` from the estimator's tags and
        the predictions.
    keep_predictions : bool, default=False
        Also return the predictions (``"y_pred"``, an array; not JSON).
    sample_rate_hz : float, optional
        Sample rate of the trials, Hz, passed to the estimator at fit and checked
        before it classifies (see :func:`vibrissa.evaluate.loop.fit_predict`).

    Returns
    -------
    dict
        :func:`score_predictions` plus ``fit_seconds``, ``classify_seconds``
        (wall time to classify the whole test set), ``n_train``, ``n_test``,
        ``n_classes_train``, ``radius_only`` and ``fitted_parameters``.
    """

    def score(t: np.ndarray, p: np.ndarray, rec: FitRecord) -> dict[str, Any]:
        ro = is_radius_only(estimator, p) if radius_only is None else bool(radius_only)
        out = score_predictions(t, p, radius_only=ro)
        out.update(
            n_classes_train=int(np.unique(np.round(y_train, 6), axis=0).shape[0]),
            radius_only=ro,
            fitted_parameters=fitted_parameters(rec.estimator),
        )
        return out

    out, rec = loop_fit_and_score(
        name, estimator, X_train, y_train, X_test, y_test, score, sample_rate_hz=sample_rate_hz
    )
    if keep_predictions:
        out["y_pred"] = rec.y_pred
    return out


# --------------------------------------------------------------------------- averaging
_PARAM_KEYS = (
    "mean",
    "std",
    "sem",
    "mean_abs",
    "rmse",
    "exact_hit",
    "kappa",
    "kappa_linear",
    "kappa_quadratic",
)


def _avg(values: list[Any]) -> float | None:
    vals = [float(v) for v in values if v is not None]
    return float(np.mean(vals)) if vals else None


def _sd(values: list[Any]) -> float | None:
    vals = [float(v) for v in values if v is not None]
    return float(np.std(vals, ddof=1)) if len(vals) > 1 else None


def _average_runs(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Average per-seed scores of one classifier at one fraction."""
    out: dict[str, Any] = {}
    for par in ("radius_mm", "speed_mm_s"):
        entries = [r[par] for r in runs]
        if any(e is None for e in entries):
            out[par] = None
            continue
        d = {k: _avg([e[k] for e in entries]) for k in _PARAM_KEYS}
        d["mean_sd_over_seeds"] = _sd([e["mean"] for e in entries])
        d["n"] = entries[0]["n"]
        out[par] = d
    joints = [r["joint"] for r in runs]
    out["joint"] = (
        None
        if any(j is None for j in joints)
        else {k: _avg([j[k] for j in joints]) for k in ("exact_hit", "kappa")}
    )
    for k in ("fit_seconds", "classify_seconds"):
        out[k] = _avg([r[k] for r in runs])
    out["n_train"] = runs[0]["n_train"]
    out["n_test"] = runs[0]["n_test"]
    out["radius_only"] = runs[0]["radius_only"]
    out["per_seed"] = runs
    return out


# --------------------------------------------------------------------------- jobs
def window_head(estimator: Any) -> tuple[str | None, Any, Any]:
    """A Pipeline's leading :class:`~vibrissa.classify.RecordingWindow` and the rest.

    The window is stateless (its ``fit`` learns nothing) and cuts each recording on
    its own, so fitting the pipeline on some trials is fitting the rest of it on
    those trials' windows, whichever trials were windowed together: the reduced
    training sets of :func:`run_chapter4` window every trial once and share it.

    Returns
    -------
    (key, window, rest)
        ``key`` names the window by its class and parameters (equal windows of
        different classifiers share a key); ``rest`` is the remaining step or
        Pipeline. ``(None, None, None)`` when the estimator does not start with a
        window followed by another step.
    """
    if not isinstance(estimator, Pipeline):
        return None, None, None
    steps = estimator.steps
    if len(steps) < 2:
        return None, None, None
    head = steps[0][1]
    if type(head) is not RecordingWindow:
        return None, None, None
    rest = steps[1][1] if len(steps) == 2 else Pipeline(steps[1:])
    key = "window:" + repr(sorted(head.get_params(deep=False).items()))
    return key, head, rest


def _job(arrays: Mapping[str, np.ndarray], kind: str, **job: Any) -> Any:
    """One step of :func:`run_chapter4`, in this process or a worker."""
    X = arrays["X"]
    if kind == "window":  # every trial's window, a block of trials at a time
        window = clone(job["window"]).fit(X[:1], sample_rate_hz=job["sample_rate_hz"])
        return np.concatenate(
            [
                window.transform(X[s : s + _WINDOW_BLOCK])
                for s in range(0, X.shape[0], _WINDOW_BLOCK)
            ]
        )
    data, y, train, test = arrays[job["data"]], arrays["y"], job["train"], job["test"]
    return fit_and_score(
        job["name"],
        job["estimator"],
        data[train],
        y[train],
        data[test],
        y[test],
        radius_only=job["radius_only"],
        keep_predictions=job["keep_predictions"],
        sample_rate_hz=job["sample_rate_hz"],
    )


def _longest_first(jobs: Sequence[Mapping[str, Any]]) -> list[int]:
    """Job order for the workers: by falling training-set size (the longest first)."""
    return sorted(range(len(jobs)), key=lambda j: -len(jobs[j]["train"]))


# --------------------------------------------------------------------------- protocol
@dataclass(frozen=True)
class _Inputs:
    """The checked inputs of :func:`run_chapter4`.

    Attributes
    ----------
    fractions : list of float
        Reduced training-set sizes, checked, in the order given.
    n_seeds, seed : int
        Random subsets per fraction and the seed of the split and subsets.
    n_workers : int
        Processes that fit the classifiers.
    split : Split
        The train/test assignment.
    sample_rate_hz : float
        The dataset's sample rate.
    X, y : numpy.ndarray
        Every trial and its ``[radial_distance_mm, speed_mm_s]`` labels.
    train_sets : dict of str to sequence
        Each classifier's training sets (its own, or all the pooled ones).
    train_index : dict of str to numpy.ndarray
        Each classifier's training trials.
    radius_only : set of str or None
        Names of the radius-only classifiers; ``None``: tags and predictions decide.
    """

    fractions: list[float]
    n_seeds: int
    seed: int
    n_workers: int
    split: Split
    sample_rate_hz: float
    X: np.ndarray
    y: np.ndarray
    train_sets: dict[str, Sequence[Any]]
    train_index: dict[str, np.ndarray]
    radius_only: set[str] | None


@dataclass(frozen=True)
class _Plan:
    """Every fit of :func:`run_chapter4`, planned and not yet run.

    Attributes
    ----------
    reduced : dict
        ``(fraction position, name, repeat)`` -> the reduced set's trials, ``None``
        when it is too small to train on (recorded as skipped).
    windows : dict of str to RecordingWindow
        The windows shared by the reduced sets' fits, by :func:`window_head` key.
    fit_keys : list of tuple
        ``("full", name, -1)`` for every classifier, then the reduced sets' keys
        that are fitted, in the order of ``jobs``.
    jobs : list of dict
        Keyword arguments of :func:`_job`, one per fit.
    """

    reduced: dict[tuple[int, str, int], np.ndarray | None]
    windows: dict[str, Any]
    fit_keys: list[tuple[Any, str, int]]
    jobs: list[dict[str, Any]]


def _check_inputs(
    ds: xr.Dataset,
    classifiers: Mapping[str, Any],
    *,
    fractions: Sequence[float],
    n_seeds: int,
    seed: int,
    train_set: Any,
    test_set: Any,
    radius_only: Collection[str] | None,
    require_complete: bool,
    classifier_train_sets: Mapping[str, Sequence[Any]] | None,
    workers: int | None,
) -> _Inputs:
    """Check the arguments of :func:`run_chapter4` and draw the train/test split.

    Parameters
    ----------
    ds, classifiers, fractions, n_seeds, seed, train_set, test_set, radius_only
        As for :func:`run_chapter4`.
    require_complete, classifier_train_sets, workers
        As for :func:`run_chapter4`.

    Returns
    -------
    _Inputs
        The checked inputs, the split and every classifier's training trials.

    Raises
    ------
    ValueError
        On the first wrong input, with the messages :func:`run_chapter4` documents.
    """
    if not isinstance(classifiers, Mapping) or not classifiers:
        raise ValueError("classifiers must be a non-empty mapping of name -> estimator")
    fr = [_check_fraction(f) for f in fractions]
    if len(set(fr)) != len(fr):
        raise ValueError(f"fractions contain duplicates: {list(fractions)}")
    if isinstance(n_seeds, bool) or not isinstance(n_seeds, int | np.integer) or n_seeds < 1:
        raise ValueError(f"n_seeds must be a positive integer, got {n_seeds!r}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    n_workers = resolve_workers(workers)
    split = split_sets(
        ds, seed, train_set=train_set, test_set=test_set, require_complete=require_complete
    )
    fs = dataset_sample_rate(ds)
    check_rates(classifiers, fs)
    X, y = dataset_arrays(ds)
    if not np.all(np.isfinite(X)):
        raise ValueError("dataset 'signal' contains NaN or infinite values")
    set_vals = np.asarray(ds["set"].values)
    pooled = split.train_set if isinstance(split.train_set, list) else [split.train_set]
    own_sets = dict(classifier_train_sets or {})
    unknown = sorted(set(own_sets) - set(classifiers))
    if unknown:
        raise ValueError(f"classifier_train_sets names unknown classifier(s) {unknown}")
    train_sets: dict[str, Sequence[Any]] = {}
    train_index: dict[str, np.ndarray] = {}
    for name in classifiers:
        train_sets[name] = own_sets.get(name, pooled)
        sets_k = list(train_sets[name])
        bad = [s_ for s_ in sets_k if s_ not in pooled]
        if bad or not sets_k:
            raise ValueError(
                f"classifier_train_sets[{name!r}] = {sets_k} must be a non-empty subset of "
                f"the training sets {pooled}"
            )
        keep = np.isin(set_vals[split.train_index], sets_k)
        train_index[name] = split.train_index[keep]
    return _Inputs(
        fractions=fr,
        n_seeds=int(n_seeds),
        seed=int(seed),
        n_workers=n_workers,
        split=split,
        sample_rate_hz=fs,
        X=X,
        y=y,
        train_sets=train_sets,
        train_index=train_index,
        radius_only=None if radius_only is None else set(radius_only),
    )


def _plan_fits(classifiers: Mapping[str, Any], inputs: _Inputs) -> _Plan:
    """Draw the reduced training sets and list every fit as a job for the workers.

    One permutation of the classes per repeat ``k`` (from
    ``numpy.random.default_rng([seed, k])``) is shared by every fraction, so the
    5 % subset is the head of the 10 % subset, as in the thesis.

    Parameters
    ----------
    classifiers : mapping of str to sklearn estimator
        As for :func:`run_chapter4`.
    inputs : _Inputs
        From :func:`_check_inputs`.

    Returns
    -------
    _Plan
        The full training sets' fits (one per classifier, through the whole
        pipeline on the raw trials), then the reduced sets' fits that are not too
        small (on the shared windows where the pipeline starts with one).
    """
    fr, n_seeds, y, train_index = inputs.fractions, inputs.n_seeds, inputs.y, inputs.train_index
    ro_names = inputs.radius_only

    def ro(name: str) -> bool | None:
        if ro_names is None:
            return None  # the estimator's tags and its predictions decide
        return name in ro_names

    # one permutation of the classes per repeat, shared by every classifier and
    # fraction (the 5 % subset is the head of the 10 % subset, as in the thesis)
    subsets = {
        name: [
            [
                subsample_combinations(
                    y[train_index[name]], f, np.random.default_rng([inputs.seed, k])
                )
                for f in fr
            ]
            for k in range(n_seeds)
        ]
        for name in classifiers
    }
    # the reduced sets' fits: (fraction, name, repeat) -> trials, None when too small
    reduced: dict[tuple[int, str, int], np.ndarray | None] = {}
    for i in range(len(fr)):
        for name in classifiers:
            y_tr = y[train_index[name]]
            for k in range(n_seeds):
                idx = subsets[name][k][i]
                small = min(len(np.unique(y_tr[idx, c])) for c in range(y_tr.shape[1])) < 2
                # too small a subset of a small grid to train on: recorded as skipped
                reduced[i, name, k] = None if small else train_index[name][idx]
    # the reduced sets' fits share the window each preset cuts from every recording
    # (computed once, for all trials) and fit the rest of the pipeline on it
    heads = {name: window_head(est) for name, est in classifiers.items()}
    windows = {}
    if any(v is not None for v in reduced.values()):
        windows = {key: head for name, (key, head, _) in heads.items() if key is not None}

    # every fit: the full training sets (table 4.6 times them) through the whole
    # pipeline on the raw trials, the reduced sets on the shared windows
    fit_keys: list[tuple[Any, str, int]] = [("full", name, -1) for name in classifiers]
    fit_keys += [k for k, v in reduced.items() if v is not None]
    jobs: list[dict[str, Any]] = []
    for i, name, k in fit_keys:
        key, _, rest = heads[name]
        full = i == "full"
        jobs.append(
            {
                "kind": "fit",
                "name": name,
                "estimator": classifiers[name] if full or key is None else rest,
                "data": "X" if full or key is None else key,
                "train": train_index[name] if full else reduced[i, name, k],
                "test": inputs.split.test_index,
                "radius_only": ro(name),
                "keep_predictions": full,
                "sample_rate_hz": inputs.sample_rate_hz,
            }
        )
    return _Plan(reduced=reduced, windows=windows, fit_keys=fit_keys, jobs=jobs)


def _run_fits(
    plan: _Plan, inputs: _Inputs, prog: Progress
) -> dict[tuple[Any, str, int], dict[str, Any]]:
    """Cut the shared windows and run every planned fit on the worker processes.

    The skipped reduced sets are reported to ``prog`` first, then every fit as it
    finishes; the workers take the fits longest first (:func:`_longest_first`).

    Parameters
    ----------
    plan : _Plan
        From :func:`_plan_fits`.
    inputs : _Inputs
        From :func:`_check_inputs` (trials, labels, rate, fractions, workers).
    prog : vibrissa.evaluate.loop.Progress
        Advanced once per fit, skipped or run.

    Returns
    -------
    dict
        ``plan.fit_keys`` -> :func:`fit_and_score` results, in that order.
    """
    fr, fs = inputs.fractions, inputs.sample_rate_hz

    def step(i: Any, name: str, k: int) -> None:
        prog.step(
            f"{name}: full training set"
            if i == "full"
            else f"{name}: {fr[i]:g} of training set, seed {k}"
        )

    for i, name, k in (k for k, v in plan.reduced.items() if v is None):
        step(i, name, k)
    with SharedArrays(inputs.n_workers) as arrays:
        arrays.add("X", inputs.X)
        arrays.add("y", inputs.y)
        cut = run_jobs(
            _job,
            [
                {"kind": "window", "window": head, "sample_rate_hz": fs}
                for head in plan.windows.values()
            ],
            arrays,
        )
        for key, w in zip(plan.windows, cut, strict=True):
            arrays.add(key, w)
        del cut
        jobs, fit_keys = plan.jobs, plan.fit_keys
        done = run_jobs(
            _job, jobs, arrays, order=_longest_first(jobs), on_done=lambda j: step(*fit_keys[j])
        )
    return dict(zip(plan.fit_keys, done, strict=True))


def _assemble_results(
    ds: xr.Dataset,
    classifiers: Mapping[str, Any],
    inputs: _Inputs,
    fits: dict[tuple[Any, str, int], dict[str, Any]],
    *,
    keep_predictions: bool,
) -> dict[str, Any]:
    """Gather the fits' scores into the JSON-ready results of :func:`run_chapter4`.

    Parameters
    ----------
    ds : xarray.Dataset
        The evaluated dataset (for its set values).
    classifiers : mapping of str to sklearn estimator
        As for :func:`run_chapter4` (for the names and their order).
    inputs : _Inputs
        From :func:`_check_inputs`.
    fits : dict
        From :func:`_run_fits`; its results are modified (predictions and the
        reduced sets' errors by speed are taken out).
    keep_predictions : bool
        Include the full-training-set predictions.

    Returns
    -------
    dict
        As described in :func:`run_chapter4`.
    """
    X, y, fr, n_seeds, seed = inputs.X, inputs.y, inputs.fractions, inputs.n_seeds, inputs.seed
    results: dict[str, Any] = {}
    preds: dict[str, Any] = {}
    for name in classifiers:
        r = fits["full", name, -1]
        y_pred = r.pop("y_pred")
        r["train_sets"] = [json_value(v) for v in inputs.train_sets[name]]
        results[name] = r
        preds[name] = {
            "radius_mm": y_pred[:, 0].tolist(),
            "speed_mm_s": None if r["radius_only"] else y_pred[:, 1].tolist(),
        }
    fractions_out: dict[str, Any] = {}
    for i, f in enumerate(fr):
        key = fraction_key(f)
        fractions_out[key] = {}
        for name in classifiers:
            runs = []
            for k in range(n_seeds):
                run = fits.get((i, name, k))
                if run is None:
                    continue
                run.pop("radius_error_by_speed")
                runs.append({"seed": [seed, k], **run})
            fractions_out[key][name] = _average_runs(runs) if runs else None

    out: dict[str, Any] = {
        "meta": {
            "evaluation": "evans2011_chapter4",
            "n_trials": int(X.shape[0]),
            "n_channels": int(X.shape[1]),
            "n_timepoints": int(X.shape[2]),
            "sample_rate_hz": inputs.sample_rate_hz,
            "sets": [json_value(s) for s in np.unique(np.asarray(ds["set"].values))],
            "split": inputs.split.to_dict(),
            "radii_mm": np.unique(y[:, 0]).tolist(),
            "speeds_mm_s": np.unique(y[:, 1]).tolist(),
            "fractions": fr,
            "n_seeds": n_seeds,
            "seed": seed,
        },
        "parameters": {
            key: {"coordinate": coord, "unit": unit, "values": np.unique(y[:, i]).tolist()}
            for i, (coord, key, unit) in enumerate(
                zip(PARAMETERS, PARAMETERS.values(), ("mm", "mm/s"), strict=True)
            )
        },
        "classifiers": results,
        "training_fractions": fractions_out,
    }
    if keep_predictions:
        y_te = y[inputs.split.test_index]
        out["predictions"] = {
            "radius_mm_true": y_te[:, 0].tolist(),
            "speed_mm_s_true": y_te[:, 1].tolist(),
            "classifiers": preds,
        }
    return out


def run_chapter4(
    ds: xr.Dataset,
    classifiers: Mapping[str, Any],
    *,
    fractions: Sequence[float] = THESIS_FRACTIONS,
    n_seeds: int = 5,
    seed: int = 0,
    progress: ProgressLike = None,
    train_set: Any = None,
    test_set: Any = None,
    radius_only: Collection[str] | None = None,
    require_complete: bool = True,
    keep_predictions: bool = True,
    classifier_train_sets: Mapping[str, Sequence[Any]] | None = None,
    workers: int | None = 1,
) -> dict[str, Any]:
    """Run the thesis' chapter-4 evaluation (4.2-4.4) and return JSON-ready results.

    Parameters
    ----------
    ds : xarray.Dataset
        Dataset with ``signal (trial, channel, time)``, per-trial coordinates
        ``radial_distance_mm``, ``speed_mm_s`` and ``set`` (at least two complete
        grids) and the attribute ``sample_rate_hz``.
    classifiers : mapping of str to sklearn estimator
        E.g. :func:`vibrissa.classify.chapter4_classifiers` built for the dataset's
        rate. Estimators take ``X (n, n_channels, n_timepoints)`` and ``y (n, 2)``
        and predict ``(n, 2)``; they are cloned for every fit. The evaluation does
        not adapt them to the data: the dataset's ``sample_rate_hz`` is passed to
        every rate-aware step at fit and checked before it classifies, and a
        classifier built for another rate is refused before any is fitted
        (``ValueError`` naming the classifier and both rates).
    fractions : sequence of float, default=(0.8, 0.6, 0.4, 0.2, 0.1, 0.05)
        Reduced training-set sizes, each in (0, 1]. May be empty.
    n_seeds : int, default=5
        Random subsets per fraction.
    seed : int, default=0
        Seeds the train/test assignment and (as ``[seed, k]``) the subsets.
    progress : callable or rich.progress.Progress, optional
        Called as ``progress(done, total, description)`` after every fit, or a
        rich ``Progress`` on which one task is added and advanced.
    train_set, test_set : optional
        Explicit set values instead of the random assignment; ``train_set`` may be
        a list of sets pooled for training.
    classifier_train_sets : mapping of str to list, optional
        Classifiers trained on only some of the training sets (e.g. the thesis
        author's template, frequency and feature code kept one of its three
        training sets); each list must be a subset of ``train_set``.
    radius_only : collection of str, optional
        Names of classifiers that estimate radial distance only; default: names
        tagged as estimating radial distance only (:func:`vibrissa.classify.estimator_tags`)
        and any whose predicted speeds are all NaN.
    require_complete : bool, default=True
        Require every set to be a complete grid (see :func:`check_dataset`).
    keep_predictions : bool, default=True
        Include the full-training-set predictions (key ``predictions``).
    workers : int or None, default=1
        Processes that fit the classifiers (``None``: every core); the results do
        not depend on it. The full training sets are fitted through each whole
        pipeline (their times are table 4.6's); for the reduced sets, a pipeline
        that starts with a :class:`~vibrissa.classify.RecordingWindow` is fitted
        on windows cut once from every trial (:func:`window_head`), so their
        ``fit_seconds`` and ``classify_seconds`` leave the window out.

    Returns
    -------
    dict
        JSON-ready (no NaN; ``None`` where undefined)::

            {
              "meta": {evaluation: "evans2011_chapter4", n_trials, n_channels,
                       n_timepoints, sample_rate_hz, sets,
                       split: {train_set, test_set, n_train, n_test, seed},
                       radii_mm, speeds_mm_s, fractions, n_seeds, seed},
              "parameters": {"radius_mm": {coordinate, unit, values},
                             "speed_mm_s": {...}},
              "classifiers": {
                name: {
                  "radius_mm": {"mean", "std", "sem", "mean_abs", "rmse", "exact_hit",
                                "n", "kappa", "kappa_linear", "kappa_quadratic"},
                  "speed_mm_s": {same keys} or None (radius-only classifiers),
                  "joint": {"exact_hit", "kappa"} or None,
                  "classify_seconds", "fit_seconds", "n_train", "n_test",
                  "n_classes_train", "radius_only", "fitted_parameters",
                  "radius_error_by_speed": [{"speed_mm_s", "mean", "std", "sem",
                                             "exact_hit", "n"}, ...],
                }
              },
              "training_fractions": {
                "0.8": {
                  name: {"radius_mm": {same keys averaged over seeds,
                                       + "mean_sd_over_seeds"},
                         "speed_mm_s": {...} or None, "joint": {...} or None,
                         "classify_seconds", "fit_seconds" (means over seeds),
                         "n_train", "n_test", "radius_only",
                         "per_seed": [{"seed": [seed, k], ...per-seed scores...}]}
                }, ...
              },
              "predictions": {"radius_mm_true": [...], "speed_mm_s_true": [...],
                              "classifiers": {name: {"radius_mm": [...],
                                                     "speed_mm_s": [...] or None}}}
            }

        "std" is the standard deviation of the signed per-trial errors (the
        thesis' "Std Err"); "mean" the mean signed error ``predicted - true``.
    """
    inputs = _check_inputs(
        ds,
        classifiers,
        fractions=fractions,
        n_seeds=n_seeds,
        seed=seed,
        train_set=train_set,
        test_set=test_set,
        radius_only=radius_only,
        require_complete=require_complete,
        classifier_train_sets=classifier_train_sets,
        workers=workers,
    )
    total = len(classifiers) * (1 + len(inputs.fractions) * inputs.n_seeds)
    prog = Progress(progress, total, "chapter 4")
    plan = _plan_fits(classifiers, inputs)
    fits = _run_fits(plan, inputs, prog)
    return _assemble_results(ds, classifiers, inputs, fits, keep_predictions=keep_predictions)


# --------------------------------------------------------------------------- oracle angle
def oracle_angle_scores(
    name: str,
    estimator: Any,
    X_train: np.ndarray,
    y_train: np.ndarray,
    X_test: np.ndarray,
    y_test: np.ndarray,
    *,
    sample_rate_hz: float | None = None,
) -> dict[str, Any]:
    """Fit a static beam with the thesis author's oracle angle and score it on the test set.

    The angle of every trial, training and test, is its TRUE speed x 0.3 s over
    its TRUE radial distance (``ProtractionAngle.m`` of the author's code; see
    :meth:`vibrissa.classify.StaticBeamClassifier.predict_with_oracle_angle`): a
    clone of ``estimator`` (a :class:`~vibrissa.classify.StaticBeamClassifier` or
    a Pipeline ending in one) is set to ``angle="oracle"``, so a parameter search
    runs under that angle too, and the test trials' true labels are passed in.

    Parameters
    ----------
    name : str
        Classifier name (used in error messages).
    estimator : sklearn estimator
        Cloned, never modified.
    X_train, y_train, X_test, y_test : numpy.ndarray
        Trials and ``[radial_distance_mm, speed_mm_s]`` labels.
    sample_rate_hz : float, optional
        Sample rate of the trials, Hz (passed at fit, checked before classifying).

    Returns
    -------
    dict
        :func:`score_predictions` (radius only) plus ``fit_seconds``,
        ``classify_seconds``, ``n_train``, ``n_test``, ``n_classes_train``,
        ``radius_only`` (True), ``fitted_parameters`` and ``abs_error_mm``
        (``mean`` and ``std`` of the absolute radial error).
    """
    est = clone(estimator)
    step, final = est.steps[-1] if isinstance(est, Pipeline) else (None, est)
    if not hasattr(final, "predict_with_oracle_angle") or "angle" not in final.get_params():
        raise TypeError(
            f"estimator of {name!r} must be a StaticBeamClassifier or a Pipeline ending in one, "
            f"got {type(final).__name__}"
        )
    est.set_params(**{"angle" if step is None else f"{step}__angle": "oracle"})
    y_tr = np.asarray(y_train, dtype=float)
    y_te = np.asarray(y_test, dtype=float)
    t0 = time.perf_counter()
    try:
        est.fit(X_train, y_tr, **sample_rate_fit_params(est, sample_rate_hz))
    except ValueError as exc:
        raise ValueError(f"classifier {name!r} (oracle angle) failed to fit: {exc}") from exc
    t1 = time.perf_counter()
    if sample_rate_hz is not None:
        check_sample_rate(est, sample_rate_hz)
    X_in = est[:-1].transform(X_test) if step is not None else X_test
    final = est.steps[-1][1] if step is not None else est
    y_pred = np.asarray(
        final.predict_with_oracle_angle(X_in, y_te[:, 1], y_te[:, 0]), dtype=float
    ).reshape(len(y_te), -1)
    if y_pred.shape[1] == 1:
        y_pred = np.column_stack([y_pred[:, 0], np.full(len(y_te), np.nan)])
    t2 = time.perf_counter()
    out = score_predictions(y_te, y_pred, radius_only=True)
    abs_err = np.abs(y_pred[:, 0] - y_te[:, 0])
    out.update(
        abs_error_mm={
            "mean": float(abs_err.mean()),
            "std": float(abs_err.std(ddof=1)) if abs_err.size > 1 else None,
        },
        fit_seconds=t1 - t0,
        classify_seconds=t2 - t1,
        n_train=int(X_train.shape[0]),
        n_test=int(X_test.shape[0]),
        n_classes_train=int(np.unique(np.round(y_tr, 6), axis=0).shape[0]),
        radius_only=True,
        fitted_parameters=fitted_parameters(est),
    )
    return out


def run_oracle_angle(
    ds: xr.Dataset,
    classifiers: Mapping[str, Any],
    *,
    train_set: Any,
    test_set: Any,
    names: Sequence[str] = ORACLE_ANGLE_NAMES,
    require_complete: bool = True,
) -> dict[str, Any]:
    """The static-beam rows again with the thesis author's oracle protraction angle.

    An extra, labelled result (:data:`ORACLE_ANGLE_LABEL`) beside table 4.7: the
    author's code computed ``theta`` from each test trial's true speed and radial
    distance, which no classifier of unknown contacts can; evaluated on the given
    split (that of the static-beam rows), full training set only.

    Parameters
    ----------
    ds : xarray.Dataset
        Chapter-4 dataset (see :func:`check_dataset`).
    classifiers : mapping of str to sklearn estimator
        As for :func:`run_chapter4`; those of ``names`` present are evaluated.
    train_set, test_set
        As for :func:`split_sets` (``train_set`` may be a list, pooled).
    names : sequence of str, default=ORACLE_ANGLE_NAMES
        Static-beam classifiers to evaluate with the oracle angle.
    require_complete : bool, default=True
        Passed to :func:`check_dataset`.

    Returns
    -------
    dict
        JSON-ready: ``{"label", "description", "split": {...}, "classifiers":
        {name: oracle_angle_scores(...)}}`` keyed by the static-beam row each
        entry redoes.
    """
    split = split_sets(
        ds, train_set=train_set, test_set=test_set, require_complete=require_complete
    )
    X, y = dataset_arrays(ds)
    fs = dataset_sample_rate(ds)
    tr, te = split.train_index, split.test_index
    rows = {
        name: oracle_angle_scores(
            name, classifiers[name], X[tr], y[tr], X[te], y[te], sample_rate_hz=fs
        )
        for name in names
        if name in classifiers
    }
    return {
        "label": ORACLE_ANGLE_LABEL,
        "description": "the static beam with theta = true speed x latency / true radial "
        "distance of every trial (training and test), as in the thesis author's "
        "ProtractionAngle.m; an oracle, not a classifier of unknown contacts",
        "split": split.to_dict(),
        "classifiers": rows,
    }
