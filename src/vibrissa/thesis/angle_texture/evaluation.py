"""The chapter-5 evaluation: angle, speed and texture classified simultaneously (5.3-5.4).

Training and test sets are recorded sets, as in chapter 4: one of the two runs
of the experiment (both directions, two complete grids) trains and the other
tests, drawn at random with the seed (704 test trials on the full grid); see
:func:`split_chapter5`. Every classifier is scored on:

* confusion matrices of angle, speed and texture (figures 5.3-5.14);
* mean and standard deviation of the signed error per parameter (tables
  5.1-5.11; texture as a signed difference of texture codes, smooth to coarse);
* Cohen's kappa of each parameter under simultaneous classification, and of
  texture alone: trained and tested on each speed-angle combination separately,
  predictions pooled (5.3.6);
* weighted kappa (linear and quadratic) of the ordered parameters (suggested in 5.5);
* classification time of the whole test set.

Beyond the thesis, ``sequential`` is the texture kappa after accumulating the
evidence of 1, 2, 3, 5 and 10 contacts with the same surface
(:class:`~vibrissa.classify.SequentialEvidenceClassifier`).

JSON contract (fixed; more keys may be added)::

    {"meta": {"evaluation": "evans2011_chapter5", ...},
     "parameters": {"angle": {...}, "speed": {...}, "texture": {...}},
     "classifiers": {name: {"kappa": {"angle", "speed", "texture", "texture_alone"},
                            "classify_seconds": t, ...}},
     "sequential": {"1": k, "2": k, "3": k, "5": k, "10": k}}
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any, Literal, overload

import numpy as np
import xarray as xr
from sklearn.base import clone

from vibrissa.classify import check_sample_rate, dataset_sample_rate, sample_rate_fit_params
from vibrissa.data.schema import TEXTURE_CODES, encode_texture
from vibrissa.evaluate import metrics
from vibrissa.evaluate.loop import Progress, check_rates, fit_predict, json_value
from vibrissa.evaluate.splits import Split

__all__ = [
    "CONTACTS",
    "PARAMETERS5",
    "chapter5_arrays",
    "check_chapter5_dataset",
    "run_chapter5",
    "score_chapter5",
    "split_chapter5",
    "texture_alone_predictions",
]

#: Result key of each column of the chapter-5 label rows.
PARAMETERS5: tuple[str, ...] = ("angle", "speed", "texture")

#: Numbers of contacts of the sequential texture curve.
CONTACTS: tuple[int, ...] = (1, 2, 3, 5, 10)

_COORDS = ("angle_deg", "speed_mm_s", "texture", "set")


def check_chapter5_dataset(
    ds: xr.Dataset, *, require_complete: bool = True
) -> dict[Any, np.ndarray]:
    """Validate an angle-texture dataset; return the trial indices of each recorded set.

    Parameters
    ----------
    ds : xarray.Dataset
        ``signal (trial, channel, time)`` and per-trial ``angle_deg``,
        ``speed_mm_s``, ``texture`` and ``set``.
    require_complete : bool, default=True
        Every set must hold every (angle, speed, texture) combination.

    Returns
    -------
    dict
        Set value -> sorted trial positions.
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"ds must be an xarray.Dataset, got {type(ds).__name__}")
    if "signal" not in ds.data_vars or set(ds["signal"].dims) != {"trial", "channel", "time"}:
        raise ValueError("dataset needs a 'signal' variable with dims (trial, channel, time)")
    missing = [c for c in _COORDS if c not in ds.coords and c not in ds.data_vars]
    if missing:
        raise ValueError(
            "dataset lacks the per-trial coordinate(s) "
            + ", ".join(repr(m) for m in missing)
            + " needed by chapter 5"
        )
    if ds.sizes["trial"] == 0:
        raise ValueError("dataset has no trials")
    sets = np.asarray(ds["set"].values)
    names = np.unique(sets)
    if len(names) < 2:
        raise ValueError(f"chapter 5 needs at least 2 recorded sets, dataset has {len(names)}")
    groups = {json_value(s): np.flatnonzero(sets == s) for s in names}
    if require_complete:
        _, y = chapter5_arrays(ds, signal=False)
        rows = [tuple(r) for r in np.round(y, 6).tolist()]
        grid = set(rows)
        for s, idx in groups.items():
            lack = grid - {rows[i] for i in idx}
            if lack:
                raise ValueError(
                    f"set {s!r} is not a complete grid: it lacks {len(lack)} of {len(grid)} "
                    f"(angle_deg, speed_mm_s, texture_code) combinations, e.g. {sorted(lack)[:3]}"
                )
    return groups


@overload
def chapter5_arrays(
    ds: xr.Dataset, signal: Literal[True] = True
) -> tuple[np.ndarray, np.ndarray]: ...
@overload
def chapter5_arrays(ds: xr.Dataset, signal: bool) -> tuple[np.ndarray | None, np.ndarray]: ...
def chapter5_arrays(ds: xr.Dataset, signal: bool = True) -> tuple[np.ndarray | None, np.ndarray]:
    """Trials and numeric label rows ``[angle_deg, speed_mm_s, texture_code]``.

    Parameters
    ----------
    ds : xarray.Dataset
    signal : bool, default=True
        Also return the signal (else ``None``).

    Returns
    -------
    X : ndarray of shape (n_trials, n_channels, n_timepoints) or None
    y : ndarray of shape (n_trials, 3)
        Texture as :data:`vibrissa.data.TEXTURE_CODES` codes.
    """
    y = np.column_stack(
        [
            np.asarray(ds["angle_deg"].values, dtype=float),
            np.asarray(ds["speed_mm_s"].values, dtype=float),
            encode_texture(ds["texture"].values).astype(float),
        ]
    )
    if not np.all(np.isfinite(y)):
        raise ValueError("angle_deg or speed_mm_s contains NaN or infinite values")
    X = None
    if signal:
        X = np.asarray(ds["signal"].transpose("trial", "channel", "time").values, dtype=float)
    return X, y


def split_chapter5(ds: xr.Dataset, seed: int = 0, *, require_complete: bool = True) -> Split:
    """Assign recorded sets to training and test (thesis 5.3).

    "The experiment was performed twice" (5.2), each run in both directions: when
    the dataset has a ``run`` coordinate with at least two runs, the runs are put
    in a seeded random order and the sets of the first half of the runs train,
    the rest test, so both sides hold both movement directions (704 test trials
    on the full grid). Without runs, the sets themselves are split in half.

    Parameters
    ----------
    ds : xarray.Dataset
    seed : int, default=0
    require_complete : bool, default=True

    Returns
    -------
    Split
        ``train_set`` / ``test_set`` are sorted lists of set values.
    """
    groups = check_chapter5_dataset(ds, require_complete=require_complete)
    names = list(groups)
    rng = np.random.default_rng(seed)
    set_vals = np.asarray(ds["set"].values)
    runs = np.unique(np.asarray(ds["run"].values)) if "run" in ds.coords else np.array([])
    if len(runs) >= 2:
        run_vals = np.asarray(ds["run"].values)
        perm = rng.permutation(len(runs))
        train_runs = set(runs[perm[: len(runs) // 2]].tolist())
        tr = sorted(
            {
                json_value(s)
                for s, r in zip(set_vals, run_vals, strict=True)
                if json_value(r) in train_runs
            }
        )
        te = sorted(s for s in names if s not in tr)
        if not te or any(
            json_value(s) in te
            for s, r in zip(set_vals, run_vals, strict=True)
            if json_value(r) in train_runs
        ):
            raise ValueError("recorded sets must not span runs")
    else:
        perm = rng.permutation(len(names))
        half = len(names) // 2
        tr = sorted(names[i] for i in perm[:half])
        te = sorted(names[i] for i in perm[half:])
    tri = np.sort(np.concatenate([groups[s] for s in tr]))
    tei = np.sort(np.concatenate([groups[s] for s in te]))
    return Split(tr, te, tri, tei, int(seed))


def score_chapter5(y_true: np.ndarray, y_pred: np.ndarray) -> dict[str, Any]:
    """Scores of one classifier's chapter-5 predictions.

    Parameters
    ----------
    y_true, y_pred : ndarray of shape (n_trials, 3)
        Rows ``[angle_deg, speed_mm_s, texture_code]``.

    Returns
    -------
    dict
        ``angle``, ``speed``, ``texture``: :func:`metrics.error_summary` plus
        ``kappa``, ``kappa_linear``, ``kappa_quadratic`` and ``confusion``
        (``labels``, ``matrix``; rows true); ``joint``: ``exact_hit``, ``kappa``.
    """
    t = np.asarray(y_true, dtype=float)
    p = np.asarray(y_pred, dtype=float)
    if t.ndim != 2 or t.shape[1] != 3 or p.shape != t.shape:
        raise ValueError(f"y_true and y_pred must have shape (n, 3), got {t.shape} and {p.shape}")
    out: dict[str, Any] = {}
    for k, key in enumerate(PARAMETERS5):
        out[key] = metrics.parameter_scores(t[:, k], p[:, k], np.unique(t[:, k]))
    out["joint"] = {"exact_hit": metrics.exact_hit_rate(t, p), "kappa": metrics.joint_kappa(t, p)}
    return out


def texture_alone_predictions(
    estimator: Any,
    X_tr: np.ndarray,
    y_tr: np.ndarray,
    X_te: np.ndarray,
    y_te: np.ndarray,
    *,
    sample_rate_hz: float | None = None,
) -> np.ndarray:
    """Texture predicted by classifiers trained per speed-angle combination (5.3.6).

    For each (angle, speed) of the test set a clone of ``estimator`` is trained on
    the training trials of that combination only (their labels vary in texture
    alone) and classifies the test trials of the combination. ``sample_rate_hz``
    (optional, Hz) is passed to every rate-aware step at fit and checked before
    each clone classifies.

    Returns
    -------
    ndarray of shape (n_test,)
        Predicted texture codes, in the order of ``y_te``.
    """
    out = np.full(y_te.shape[0], np.nan)
    combos = np.unique(np.round(y_te[:, :2], 6), axis=0)
    for a, v in combos:
        mtr = np.isclose(y_tr[:, 0], a) & np.isclose(y_tr[:, 1], v)
        mte = np.isclose(y_te[:, 0], a) & np.isclose(y_te[:, 1], v)
        if len(np.unique(y_tr[mtr, 2])) < 2:
            raise ValueError(f"training set has fewer than 2 textures at angle {a}, speed {v}")
        est = clone(estimator).fit(
            X_tr[mtr], y_tr[mtr], **sample_rate_fit_params(estimator, sample_rate_hz)
        )
        if sample_rate_hz is not None:
            check_sample_rate(est, sample_rate_hz)
        out[mte] = np.asarray(est.predict(X_te[mte]), dtype=float)[:, 2]
    return out


def _sequential_curve(
    fitted: Any,
    X_te: np.ndarray,
    y_te: np.ndarray,
    contacts: Sequence[int],
    seed: int,
    threshold: float,
    sample_rate_hz: float,
) -> dict[str, Any]:
    from vibrissa.classify import SequentialEvidenceClassifier, draw_sequences

    seq = SequentialEvidenceClassifier.from_fitted(fitted, target_column=2, threshold=threshold)
    lp = seq.contact_log_proba(X_te, sample_rate_hz=sample_rate_hz)
    seqs = draw_sequences(y_te[:, 2], max(contacts), np.random.default_rng([int(seed), 5]))
    kappas, used = {}, {}
    for n in contacts:
        pred, n_used = seq.predict_sequences_from_log_proba(lp, seqs, n)
        kappas[str(int(n))] = metrics.kappa(y_te[:, 2], np.asarray(pred, dtype=float))
        used[str(int(n))] = float(np.mean(n_used))
    return {"kappa": kappas, "mean_contacts_used": used}


def run_chapter5(
    ds: xr.Dataset,
    classifiers: Mapping[str, Any],
    seed: int = 0,
    progress: Any = None,
    *,
    texture_alone: bool = True,
    sequential_base: str | None = "minirocket",
    contacts: Sequence[int] = CONTACTS,
    threshold: float = 0.99,
    require_complete: bool = True,
    keep_predictions: bool = True,
) -> dict[str, Any]:
    """Run the chapter-5 evaluation and return JSON-ready results (contract in the module doc).

    Parameters
    ----------
    ds : xarray.Dataset
        Angle-texture dataset (see :func:`check_chapter5_dataset`).
    classifiers : mapping of str to estimator
        E.g. :func:`vibrissa.classify.chapter5_classifiers` built for the dataset's
        rate; fitted on rows ``[angle_deg, speed_mm_s, texture_code]``, cloned for
        every fit. The dataset's ``sample_rate_hz`` is passed to every rate-aware
        step at fit and checked before it classifies; a classifier built for
        another rate is refused before any is fitted.
    seed : int, default=0
        Seeds the set assignment and the sequences of contacts.
    progress : callable or rich.progress.Progress, optional
        ``progress(done, total, description)`` after every classifier stage.
    texture_alone : bool, default=True
        Also train and test per speed-angle combination (5.3.6); otherwise
        ``kappa.texture_alone`` is ``None``.
    sequential_base : str or None, default="minirocket"
        Classifier (a key of ``classifiers``) whose posteriors are accumulated
        over contacts; ``None`` or a missing key: ``sequential`` is empty. The
        default is the best single-contact texture classifier on the simulated
        data; the naive Bayes posteriors are nearly one-hot and at chance for
        texture, and accumulating a biased vote makes kappa worse, not better.
    contacts : sequence of int, default=(1, 2, 3, 5, 10)
    threshold : float, default=0.99
        Posterior at which a sequence stops early.
    require_complete : bool, default=True
    keep_predictions : bool, default=True
        Include the test labels and every classifier's predictions.

    Returns
    -------
    dict
        ``protocol``, ``meta``, ``classifiers`` (per name: ``kappa`` {angle, speed,
        texture, texture_alone}, ``weighted_kappa`` {angle, speed, texture:
        {linear, quadratic}}, ``errors`` {angle_deg, speed_mm_s, texture: mean,
        std, sem, mean_abs, rmse, exact_hit, n}, ``confusion`` {angle, speed,
        texture, texture_alone: {labels, matrix}}, ``joint`` {exact_hit, kappa},
        ``classify_seconds``, ``fit_seconds``, ``texture_alone_seconds``,
        ``n_train``, ``n_test``), ``sequential`` {"1": kappa, ...},
        ``sequential_detail``, ``predictions``.
    """
    if not isinstance(classifiers, Mapping) or not classifiers:
        raise ValueError("classifiers must be a non-empty mapping of name -> estimator")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    cts = [int(c) for c in contacts]
    if not cts or min(cts) < 1:
        raise ValueError(f"contacts must be positive integers, got {list(contacts)}")
    split = split_chapter5(ds, int(seed), require_complete=require_complete)
    fs = dataset_sample_rate(ds)
    check_rates(classifiers, fs)
    X, y = chapter5_arrays(ds)
    if not np.all(np.isfinite(X)):
        raise ValueError("dataset 'signal' contains NaN or infinite values")
    X_tr, y_tr, X_te, y_te = (
        X[split.train_index],
        y[split.train_index],
        X[split.test_index],
        y[split.test_index],
    )
    do_seq = sequential_base is not None and sequential_base in classifiers
    prog = Progress(
        progress, len(classifiers) * (2 if texture_alone else 1) + int(do_seq), "chapter 5"
    )
    results: dict[str, Any] = {}
    preds: dict[str, Any] = {}
    seq_fitted: Any = None
    for name, est0 in classifiers.items():
        rec = fit_predict(name, est0, X_tr, y_tr, X_te, sample_rate_hz=fs)
        est, p = rec.estimator, rec.y_pred
        prog.step(f"{name}: simultaneous")
        if do_seq and name == sequential_base:
            seq_fitted = est  # the sequential curve reuses this fit
        sc = score_chapter5(y_te, p)
        ta, ta_s = None, None
        if texture_alone:
            t3 = time.perf_counter()
            ta = texture_alone_predictions(est0, X_tr, y_tr, X_te, y_te, sample_rate_hz=fs)
            ta_s = time.perf_counter() - t3
            prog.step(f"{name}: texture alone")
        ta_scores = (
            None if ta is None else metrics.parameter_scores(y_te[:, 2], ta, np.unique(y_te[:, 2]))
        )
        results[name] = {
            "kappa": {
                "angle": sc["angle"]["kappa"],
                "speed": sc["speed"]["kappa"],
                "texture": sc["texture"]["kappa"],
                "texture_alone": None if ta_scores is None else ta_scores["kappa"],
            },
            "weighted_kappa": {
                k: {"linear": sc[k]["kappa_linear"], "quadratic": sc[k]["kappa_quadratic"]}
                for k in PARAMETERS5
            },
            "errors": {
                unit: {k: v for k, v in sc[key].items() if k != "confusion"}
                for key, unit in zip(
                    PARAMETERS5, ("angle_deg", "speed_mm_s", "texture"), strict=True
                )
            },
            "confusion": {
                **{k: sc[k]["confusion"] for k in PARAMETERS5},
                "texture_alone": None if ta_scores is None else ta_scores["confusion"],
            },
            "joint": sc["joint"],
            **rec.timing(),
            "texture_alone_seconds": ta_s,
        }
        preds[name] = {"y_pred": p.tolist(), "texture_alone": None if ta is None else ta.tolist()}
    sequential: dict[str, Any] = {}
    detail: dict[str, Any] | None = None
    if do_seq:
        detail = _sequential_curve(seq_fitted, X_te, y_te, cts, int(seed), threshold, fs)
        detail.update(base=sequential_base, threshold=float(threshold))
        sequential = dict(detail["kappa"])
        prog.step("sequential contacts")
    out: dict[str, Any] = {
        "meta": {
            "evaluation": "evans2011_chapter5",
            "n_trials": int(X.shape[0]),
            "n_channels": int(X.shape[1]),
            "n_timepoints": int(X.shape[2]),
            "sample_rate_hz": fs,
            "split": {
                "train_sets": [json_value(s) for s in split.train_set],
                "test_sets": [json_value(s) for s in split.test_set],
                "n_train": int(X_tr.shape[0]),
                "n_test": int(X_te.shape[0]),
                "seed": int(seed),
            },
            "angles_deg": np.unique(y[:, 0]).tolist(),
            "speeds_mm_s": np.unique(y[:, 1]).tolist(),
            "texture_codes": dict(TEXTURE_CODES),
            "seed": int(seed),
        },
        "parameters": {
            key: {"coordinate": coord, "unit": unit, "values": np.unique(y[:, i]).tolist()}
            for i, (key, coord, unit) in enumerate(
                (
                    ("angle", "angle_deg", "deg"),
                    ("speed", "speed_mm_s", "mm/s"),
                    ("texture", "texture", "code (TEXTURE_CODES)"),
                )
            )
        },
        "classifiers": results,
        "sequential": sequential,
        "sequential_detail": detail,
    }
    if keep_predictions:
        out["predictions"] = {"y_true": y_te.tolist(), "classifiers": preds}
    return out
