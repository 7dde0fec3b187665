"""Thesis 6.4.4: hit rate against the number of training whisks on the BIOTACT G1 data.

For each control strategy and ``n`` = 1..8 training whisks: train on whisks 1..n of
every class, validate on the remaining whisks of every class (12 - n each), hit
rate = correct / validation whisks. Three tasks: the 9-class joint texture and
distance problem, and texture or distance alone (3 classes each, "constructed by
concatenating all training data for each distance or each texture", 6.4.4.3).
Two classifiers (6.4.2-6.4.3):

* stationary naive Bayes over all 12 channels (x and y of six whiskers) on the raw
  sensor values: 100 equal-width intervals spanning each channel's whole training
  range, histograms smoothed with a Gaussian "of width 5 intervals", read as a
  full width at half maximum of 5 bins (sigma = 5 / 2.355 = 2.12 bins): "width" of
  a Gaussian without qualification is its FWHM; the chapter-4 author's code, which
  calls the truncation half-width "width", ran with 10 for a text that also says
  five, so it does not pin this reading down;
* class-mean templates: per class the mean of each of the 12 channels over the
  training whisks; a whisk goes to the class with the smallest sum of squared
  errors over its 12 templates (on the raw signals: 6.4.3 names no filter).

The dataset holds whole whisks (from full retraction), so every whisk is aligned
to the pattern generator's phase, as on the robot. A dataset of several sessions
(``session_seed`` per trial) is evaluated session by session and every figure given as
the mean over the sessions with its spread (:func:`evaluate_g1_sessions`).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.evaluate.spread import SPREAD_KEY, seed_spread, spread_leaf

__all__ = [
    "CLASSIFIERS",
    "FWHM_PER_SIGMA",
    "TASKS",
    "evaluate_g1",
    "evaluate_g1_sessions",
    "session_seeds",
    "g1_classifiers",
    "hit_rate_curves",
    "whisk_statistics",
]

#: The three problems of 6.4.4.
TASKS = ("joint", "texture", "distance")
#: The two classifiers of 6.4.2-6.4.3.
CLASSIFIERS = ("naive_bayes", "template")
#: FWHM of a Gaussian over its sigma, 2 sqrt(2 ln 2).
FWHM_PER_SIGMA = 2.0 * np.sqrt(2.0 * np.log(2.0))


def g1_classifiers(
    sample_rate_hz: float,
    n_bins: int = 100,
    smoothing_fwhm_bins: float = 5.0,
    value_range: str | None = None,
) -> dict[str, Callable[[], Any]]:
    """Factories of the two classifiers of 6.4.2-6.4.3 (fresh, unfitted each call).

    ``value_range``: naive Bayes' bins; ``None`` spans each channel's whole training
    range (6.4.2), ``"robust"`` its central 99 % (beside the thesis, as a check).
    """
    from vibrissa.classify import StationaryNaiveBayes, TimeTemplateClassifier

    sigma = float(smoothing_fwhm_bins) / FWHM_PER_SIGMA
    return {
        "naive_bayes": lambda: StationaryNaiveBayes(
            signal="raw",
            n_bins=n_bins,
            value_range=value_range,
            smoothing_sigma=sigma,
            sample_rate_hz=sample_rate_hz,
        ),
        "template": lambda: TimeTemplateClassifier(
            sample_rate_hz=sample_rate_hz, cutoff_hz=None, templates="mean", distance="sse"
        ),
    }


def _labels(texture: np.ndarray, distance: np.ndarray) -> dict[str, np.ndarray]:
    return {
        "joint": np.array([f"{t}@{d:g}" for t, d in zip(texture, distance, strict=True)]),
        "texture": texture.astype(str),
        "distance": distance.astype(float),
    }


def hit_rate_curves(
    ds: xr.Dataset,
    max_training: int = 8,
    progress: Callable[[int, int, str], None] | None = None,
    classifiers: tuple[str, ...] = CLASSIFIERS,
    **classifier_options: Any,
) -> dict[str, Any]:
    """Hit rates of every strategy, classifier and task for 1..``max_training`` whisks.

    Parameters
    ----------
    ds
        A G1 dataset (per trial ``strategy``, ``texture``, ``distance_mm``, ``whisk``).
    max_training
        Largest number of training whisks (thesis: 8).
    progress
        Called as ``progress(done, total, strategy)``.
    classifiers
        Which of :data:`CLASSIFIERS` to run.
    classifier_options
        Passed to :func:`g1_classifiers`.

    Returns
    -------
    dict
        ``hit_rate[strategy][classifier][task]``: one value per number of training
        whisks (``None`` where no whisk is left to validate on), and
        ``n_validation[strategy]``: validation whisks per number.
    """
    fs = float(ds.attrs["sample_rate_hz"])
    makers = {k: v for k, v in g1_classifiers(fs, **classifier_options).items() if k in classifiers}
    X_all = np.asarray(ds["signal"].values, dtype=float)
    strat = np.asarray(ds["strategy"].values).astype(str)
    order = list(dict.fromkeys(strat.tolist()))
    hit: dict[str, Any] = {}
    n_val: dict[str, list[int]] = {}
    for k, s in enumerate(order):
        sel = strat == s
        X = X_all[sel]
        whisk = np.asarray(ds["whisk"].values)[sel]
        labels = _labels(
            np.asarray(ds["texture"].values)[sel],
            np.asarray(ds["distance_mm"].values, dtype=float)[sel],
        )
        curves: dict[str, dict[str, list[float | None]]] = {
            c: {t: [] for t in TASKS} for c in makers
        }
        n_val[s] = []
        for n in range(1, max_training + 1):
            train, val = whisk <= n, whisk > n
            n_val[s].append(int(val.sum()))
            for c, make in makers.items():
                for t in TASKS:
                    if not val.any():
                        curves[c][t].append(None)
                        continue
                    y = labels[t]
                    clf = make().fit(X[train], y[train])
                    curves[c][t].append(float(np.mean(clf.predict(X[val]) == y[val])))
        hit[s] = curves
        if progress:
            progress(k + 1, len(order), s)
    return {"hit_rate": hit, "n_validation": n_val}


def whisk_statistics(ds: xr.Dataset) -> dict[str, dict[str, float]]:
    """Whisk statistics per control strategy.

    Per strategy: contact time per whisk and whisker (s), peak ``x`` deflection from
    rest (V), the within-class spread of that peak (mean over classes and whiskers of
    std / mean over whisks), the largest gating variable, and the saturated whisks.
    """
    fs = float(ds.attrs["sample_rate_hz"])
    strat = np.asarray(ds["strategy"].values).astype(str)
    chans = [str(c) for c in ds["channel"].values]
    xs = [i for i, c in enumerate(chans) if c.endswith("x")]
    sig = np.asarray(ds["signal"].values)[:, xs, :]
    peak = np.abs(sig - np.median(sig[:, :, :20], axis=2, keepdims=True)).max(axis=2)
    cls = np.array(
        [f"{t}@{d:g}" for t, d in zip(ds["texture"].values, ds["distance_mm"].values, strict=True)]
    )
    out: dict[str, dict[str, float]] = {}
    for s in dict.fromkeys(strat.tolist()):
        sel = strat == s
        spreads = []
        for c in np.unique(cls[sel]):
            p = peak[sel & (cls == c)]
            if p.shape[0] > 1:
                spreads.append(np.mean(p.std(axis=0) / np.maximum(p.mean(axis=0), 1e-12)))
        out[s] = {
            "contact_time_s": float(np.mean(np.sum(ds["force_n"].values[sel] > 0, axis=2)) / fs),
            "peak_deflection_v": float(np.mean(peak[sel])),
            "peak_spread": float(np.mean(spreads)) if spreads else float("nan"),
            "max_z": float(np.max(ds["gating"].values[sel])),
            "saturated_whisks": int(np.sum(np.asarray(ds["saturated"].values)[sel])),
        }
    return out


def _mean(vals: list[float | None]) -> float | None:
    v = [x for x in vals if x is not None]
    return float(np.mean(v)) if v else None


def _checks(hit: Mapping[str, Any]) -> dict[str, Any]:
    """The thesis' claims about naive Bayes, tested on this run."""
    out: dict[str, Any] = {}
    if "rcp7" in hit and "unmodulated" in hit:
        r7 = hit["rcp7"]["naive_bayes"]["joint"]
        un = hit["unmodulated"]["naive_bayes"]["joint"]
        a, b = _mean(r7[:2]), _mean(un[:2])
        out["rcp7_beats_unmodulated_nb_joint_1_2_whisks"] = (
            None if a is None or b is None else bool(a > b)
        )
        out["rcp7_nb_joint_mean_1_2"] = a
        out["unmodulated_nb_joint_mean_1_2"] = b
        out["rcp7_nb_joint_at_7"] = r7[6] if len(r7) > 6 else None
    out["first_perfect_nb_joint"] = {
        s: next((i + 1 for i, r in enumerate(c["naive_bayes"]["joint"]) if r == 1.0), None)
        for s, c in hit.items()
    }
    return out


def evaluate_g1(ds: xr.Dataset, *, progress: Callable | None = None) -> dict[str, Any]:
    """Evaluate a G1 session: hit-rate curves, whisk statistics and the thesis' claims.

    The hit-rate curves are those of both classifiers (and naive Bayes with robust
    bins); the thesis' claims are tested on them.

    Parameters
    ----------
    ds : xarray.Dataset
        The session of :func:`vibrissa.thesis.biotact_g1.protocol.biotact_protocol` (or a
        recording with the same variables).
    progress : callable, optional
        Passed to :func:`hit_rate_curves`.

    Returns
    -------
    dict
        ``meta``, ``parameters``, ``classifiers``, ``hit_rate``, ``n_validation``,
        ``naive_bayes_robust_range``, ``whisks`` and ``checks``.
    """
    res = hit_rate_curves(ds, progress=progress)
    # beside the thesis: naive Bayes with bins over the central 99 % of each channel
    robust = hit_rate_curves(ds, classifiers=("naive_bayes",), value_range="robust")
    proto = json.loads(ds.attrs.get("protocol_params", "{}"))
    textures = list(dict.fromkeys(np.asarray(ds["texture"].values).astype(str).tolist()))
    dists = sorted({float(v) for v in ds["distance_mm"].values})
    return {
        "meta": {
            "n_trials": int(ds.sizes["trial"]),
            "sample_rate_hz": float(ds.attrs["sample_rate_hz"]),
            "channels": [str(c) for c in ds["channel"].values],
            "whisks_per_class": int(ds["whisk"].values.max()),
            "protocol": proto,
            "textures": json.loads(ds.attrs.get("textures", "{}")),
            "evaluation": "train on whisks 1..n of every class, validate on the "
            "rest (6.4.4); hit rate = correct / validation whisks",
        },
        "parameters": {
            "texture": {"coordinate": "texture", "unit": "name", "values": textures},
            "distance_mm": {"coordinate": "distance_mm", "unit": "mm", "values": dists},
        },
        "classifiers": {
            "naive_bayes": "stationary naive Bayes, raw values, 100 bins over "
            "each channel's range, Gaussian FWHM 5 bins",
            "template": "class-mean templates, raw, sum of squared errors",
        },
        "hit_rate": res["hit_rate"],
        "n_validation": res["n_validation"],
        "naive_bayes_robust_range": {s: v["naive_bayes"] for s, v in robust["hit_rate"].items()},
        "whisks": whisk_statistics(ds),
        "checks": _checks(res["hit_rate"]),
    }


#: Sections the same in every session (descriptive): from the first.
_SHARED = ("meta", "parameters", "classifiers")
#: The boolean checks: true only if true in every session; ``<name>_fraction`` beside.
_BOOLEAN_CHECKS = ("rcp7_beats_unmodulated_nb_joint_1_2_whisks",)


def session_seeds(ds: xr.Dataset) -> list[int]:
    """The seeds of the sessions in ``ds`` (one, the dataset's own, without ``session_seed``)."""
    if "session_seed" not in ds.coords and "session_seed" not in ds:
        return [int(ds.attrs.get("seed", 0))]
    return sorted({int(v) for v in np.asarray(ds["session_seed"].values)})


def evaluate_g1_sessions(ds: xr.Dataset, *, progress: Callable | None = None) -> dict[str, Any]:
    """Evaluate every session of ``ds``; each figure the mean over sessions, with its spread.

    Each session (the trials of one ``session_seed``) is evaluated by :func:`evaluate_g1`;
    :func:`vibrissa.evaluate.spread.seed_spread` gives every number's mean over the
    sessions (the results' figures: hit rates, whisk statistics, checks) and its spread
    (under ``spread``, with the per-session values). A boolean check is true only if it
    holds in every session; ``checks.<name>_fraction`` is the fraction of sessions where
    it holds (0/1 per session under ``spread.checks.<name>``).

    Parameters
    ----------
    ds : xarray.Dataset
        A G1 dataset of one or more sessions.
    progress : callable, optional
        ``progress(done, total, name)`` after each session.

    Returns
    -------
    dict
        The sections of :func:`evaluate_g1` (means), ``meta.n_seeds``, ``meta.seeds`` and
        ``spread``.
    """
    seeds = session_seeds(ds)
    per: list[dict[str, Any]] = []
    for i, q in enumerate(seeds):
        sub = (
            ds
            if len(seeds) == 1
            else ds.isel(trial=np.flatnonzero(np.asarray(ds["session_seed"].values) == q))
        )
        per.append(evaluate_g1(sub))
        if progress:
            progress(i + 1, len(seeds), f"session {q}")
    varying = [{k: v for k, v in r.items() if k not in _SHARED} for r in per]
    mean, spread = seed_spread(varying)
    spread = dict(spread or {})
    checks = dict(mean["checks"])
    check_spread = dict(spread.get("checks") or {})
    for key in _BOOLEAN_CHECKS:
        vals = [r["checks"].get(key) for r in per]
        known = [bool(v) for v in vals if v is not None]
        checks[key] = all(known) if known else None
        checks[f"{key}_fraction"] = float(np.mean(known)) if known else None
        check_spread[key] = spread_leaf([None if v is None else float(bool(v)) for v in vals])
    spread["checks"] = check_spread
    out = {k: per[0][k] for k in _SHARED}
    out["meta"] = {
        **per[0]["meta"],
        "n_trials": int(ds.sizes["trial"]),
        "n_seeds": len(seeds),
        "seeds": seeds,
        "seed_statistic": "each number is the mean over the sessions; its spread "
        "(mean, std, min, max, n, per-session values) under 'spread'",
    }
    out.update({k: v for k, v in mean.items() if k != "checks"})
    out["checks"] = checks
    out[SPREAD_KEY] = spread
    return out
