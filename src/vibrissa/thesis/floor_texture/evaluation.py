"""The Roomba floor-texture evaluation (thesis 6.2.1-6.2.2).

Per movement condition: each 16 s recording loses its quiet packets (160 samples
with variance below 5e-5 V^2), the rest is cut into 800-sample windows, odd-numbered
windows train and even-numbered ones test (:func:`vibrissa.signal.packet_windows`,
:func:`vibrissa.signal.odd_even_split`). Spectral templates (one mean DFT-magnitude
template per floor, 5.3.2 / figure 6.3) give the confusion matrices of tables
6.1-6.3; the clockwise templates classify the anticlockwise test windows and back
(the cross-condition test); stationary naive Bayes on the raw values' histograms is
the comparison of 6.2.3 (Lepora et al. 2010b).

"Mean correct" is the mean over floors of the fraction of each floor's test windows
classified correctly, as the thesis' tables compute it (table 6.1: the mean of 97.5,
67.5, 54 and 67.5 % is 72 %); it is reported as a fraction (0.72).

A dataset of several sessions (coordinate ``seed``, :class:`FloorProtocol` with
``n_seeds`` > 1) is evaluated session by session (:func:`run_floor_texture_seeds`):
every figure is the mean over the sessions, and the key ``spread`` holds each figure's
spread (:func:`vibrissa.evaluate.spread.seed_spread`).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.classify import FrequencyTemplateClassifier, StationaryNaiveBayes
from vibrissa.evaluate.spread import SPREAD_KEY, seed_spread
from vibrissa.signal import (
    PACKET_SAMPLES,
    QUIET_VARIANCE_V2,
    WINDOW_SAMPLES,
    active_packets,
    magnitude_spectrum,
    odd_even_split,
    packet_windows,
    spectrum_frequencies,
)
from vibrissa.thesis.floor_texture.values import THESIS

__all__ = [
    "confusion_matrix",
    "condition_windows",
    "floor_classifiers",
    "mean_correct",
    "per_class_correct",
    "run_floor_texture",
    "run_floor_texture_seeds",
    "signal_levels",
]

#: Per-trial diagnostics of the simulation summarised per condition and floor, when the
#: dataset records them (:data:`vibrissa.thesis.floor_texture.protocol.FLOOR_DIAGNOSTICS`).
_TRIAL_DIAGNOSTICS = ("catches", "catch_fraction", "rail_fraction", "contact_force_n")


def confusion_matrix(true: np.ndarray, pred: np.ndarray, n_classes: int) -> np.ndarray:
    """Counts, rows = true class, columns = predicted (integer labels 0..n-1)."""
    cm = np.zeros((n_classes, n_classes), dtype=np.int64)
    np.add.at(cm, (np.asarray(true, dtype=int), np.asarray(pred, dtype=int)), 1)
    return cm


def mean_correct(cm: np.ndarray) -> float | None:
    """Mean over the true classes (rows with any window) of the fraction correct."""
    cm = np.asarray(cm, dtype=float)
    n = cm.sum(axis=1)
    ok = n > 0
    if not ok.any():
        return None
    return float(np.mean(np.diag(cm)[ok] / n[ok]))


def per_class_correct(cm: np.ndarray, names: list[str]) -> dict[str, float | None]:
    """Fraction of each true class's windows classified correctly (``None``: no window)."""
    cm = np.asarray(cm, dtype=float)
    n = cm.sum(axis=1)
    return {f: (float(cm[i, i] / n[i]) if n[i] > 0 else None) for i, f in enumerate(names)}


def signal_levels(X: np.ndarray, sample_rate_hz: float) -> dict[str, Any]:
    """How loud a set of windows is: what a spectral template's squared error weighs.

    Parameters
    ----------
    X : ndarray
        Windows, shape (n, n_channels, n_samples), volts.
    sample_rate_hz : float

    Returns
    -------
    dict
        ``rms_v``: per channel, the RMS about each window's mean, averaged over windows;
        ``spectrum_norm``: the mean over windows of the L2 norm of the DC-less magnitude
        spectrum (both channels); ``centroid_hz``: per channel, the mean spectral
        centroid. ``None`` values without windows.
    """
    X = np.asarray(X, dtype=float)
    if X.shape[0] == 0:
        return {"rms_v": None, "spectrum_norm": None, "centroid_hz": None}
    ac = X - X.mean(axis=-1, keepdims=True)
    spec = magnitude_spectrum(X)
    spec[..., 0] = 0.0
    f = spectrum_frequencies(X.shape[-1], sample_rate_hz)
    power = spec.sum(axis=-1)
    centroid = np.divide((spec * f).sum(axis=-1), power, out=np.zeros_like(power), where=power > 0)
    return {
        "rms_v": np.sqrt((ac**2).mean(axis=-1)).mean(axis=0).tolist(),
        "spectrum_norm": float(np.linalg.norm(spec.reshape(spec.shape[0], -1), axis=1).mean()),
        "centroid_hz": centroid.mean(axis=0).tolist(),
    }


def condition_windows(ds: xr.Dataset, condition: str, floors: list[str]) -> dict[str, Any]:
    """Windows of one condition, split into training and test sets.

    Returns
    -------
    dict
        ``X_train``, ``y_train``, ``X_test``, ``y_test`` (windows and floor indices),
        ``packets`` {floor: [kept, total]} and ``windows`` {floor: [train, test]}.
    """
    sig = ds["signal"].values
    X_tr, y_tr, X_te, y_te = [], [], [], []
    packets = {f: [0, 0] for f in floors}
    windows = {f: [0, 0] for f in floors}
    for i in np.flatnonzero(ds["condition"].values == condition):
        f = str(ds["floor"].values[i])
        keep = active_packets(sig[i])
        packets[f][0] += int(keep.sum())
        packets[f][1] += int(keep.size)
        w = packet_windows(sig[i])
        tr, te = odd_even_split(len(w))
        X_tr.append(w[tr])
        X_te.append(w[te])
        y_tr += [floors.index(f)] * len(tr)
        y_te += [floors.index(f)] * len(te)
        windows[f][0] += len(tr)
        windows[f][1] += len(te)
    shape = (0, sig.shape[1], WINDOW_SAMPLES)
    return {
        "X_train": np.concatenate(X_tr) if X_tr else np.zeros(shape),
        "y_train": np.asarray(y_tr, dtype=int),
        "X_test": np.concatenate(X_te) if X_te else np.zeros(shape),
        "y_test": np.asarray(y_te, dtype=int),
        "packets": packets,
        "windows": windows,
    }


def floor_classifiers(sample_rate_hz: float) -> dict[str, Any]:
    """The methods of 6.2: spectral templates, the nearest spectrum and naive Bayes.

    Spectral templates (one mean template per floor, the thesis'), the nearest single
    training spectrum (a variant), and stationary naive Bayes on raw values (6.2.3).

    The spectra leave out the DC bin, as the thesis author's chapter-4 code did
    (``zero_dc``, docs/methods.md): a window's mean is the whisker's static bend,
    which follows the turning direction (the lateral drag) more than the floor.
    """
    fs = float(sample_rate_hz)
    return {
        "spectral_template": FrequencyTemplateClassifier(
            sample_rate_hz=fs, cutoff_hz=None, templates="mean", zero_dc=True
        ),
        "spectral_nearest": FrequencyTemplateClassifier(
            sample_rate_hz=fs, cutoff_hz=None, templates="all", zero_dc=True
        ),
        "naive_bayes": StationaryNaiveBayes(signal="raw", sample_rate_hz=fs),
    }


def _predict(clf: Any, X: np.ndarray) -> np.ndarray:
    return np.asarray(clf.predict(X)).ravel().astype(int)


def run_floor_texture(
    ds: xr.Dataset, *, seed: int = 0, progress: Callable[[int, int, str], None] | None = None
) -> dict[str, Any]:
    """Evaluate every condition of a floor-texture dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        Coordinates ``floor`` and ``condition`` per trial, attribute ``sample_rate_hz``.
    seed : int
        Unused (the evaluation is deterministic); kept for the common signature.
    progress : callable, optional
        ``progress(done, total, description)``.

    Returns
    -------
    dict
        ``meta``, ``parameters``, ``classifiers``, ``confusion``, ``mean_correct``,
        ``cross_condition``, ``naive_bayes``, ``windows``, ``packets``, ``templates``.
    """
    from sklearn.base import clone

    fs = float(ds.attrs["sample_rate_hz"])
    floors = [f for f in THESIS["floors"] if f in set(ds["floor"].values.tolist())]
    floors += sorted(set(ds["floor"].values.tolist()) - set(floors))
    conditions = list(dict.fromkeys(ds["condition"].values.tolist()))
    methods = floor_classifiers(fs)
    data = {c: condition_windows(ds, c, floors) for c in conditions}
    fitted: dict[str, dict[str, Any]] = {m: {} for m in methods}
    out: dict[str, Any] = {m: {"confusion": {}, "mean_correct": {}} for m in methods}
    seconds = {m: 0.0 for m in methods}
    total = len(conditions) * len(methods)
    done = 0
    for c in conditions:
        d = data[c]
        for m, proto in methods.items():
            t0 = time.perf_counter()
            if len(set(d["y_train"].tolist())) >= 2 and len(d["y_test"]):
                clf = clone(proto).fit(d["X_train"], d["y_train"])
                fitted[m][c] = clf
                cm = confusion_matrix(d["y_test"], _predict(clf, d["X_test"]), len(floors))
                out[m]["confusion"][c] = cm.tolist()
                out[m]["mean_correct"][c] = mean_correct(cm)
                out[m].setdefault("per_floor_correct", {})[c] = per_class_correct(cm, floors)
            else:
                out[m]["confusion"][c] = None
                out[m]["mean_correct"][c] = None
                out[m].setdefault("per_floor_correct", {})[c] = None
            seconds[m] += time.perf_counter() - t0
            done += 1
            if progress:
                progress(done, total, f"{m} {c}")
    cross: dict[str, Any] = {}
    for key, (src, dst) in {
        "cw_on_ccw": ("clockwise", "anticlockwise"),
        "ccw_on_cw": ("anticlockwise", "clockwise"),
    }.items():
        clf = fitted["spectral_template"].get(src)
        if clf is None or dst not in data or not len(data[dst]["y_test"]):
            cross[key] = None
            continue
        cm = confusion_matrix(data[dst]["y_test"], _predict(clf, data[dst]["X_test"]), len(floors))
        cross[key] = mean_correct(cm)
        cross[f"{key}_confusion"] = cm.tolist()
        cross[f"{key}_per_floor"] = per_class_correct(cm, floors)
    templates = {}
    for c in fitted["spectral_template"]:
        d = data[c]
        spec = magnitude_spectrum(d["X_train"])
        templates[c] = {
            "frequency_hz": spectrum_frequencies(WINDOW_SAMPLES, fs).tolist(),
            "spectra": {
                f: spec[d["y_train"] == k].mean(axis=0).tolist()
                for k, f in enumerate(floors)
                if np.any(d["y_train"] == k)
            },
        }
    saturated: dict[str, dict[str, int]] = {}
    if "saturated" in ds.coords:
        for c in conditions:
            sel = ds["condition"].values == c
            saturated[c] = {
                f: int(np.sum(ds["saturated"].values[sel & (ds["floor"].values == f)]))
                for f in floors
            }
    # per condition and floor: how loud the windows are, and how the tip met the floor
    levels: dict[str, dict[str, Any]] = {}
    for c in conditions:
        d = data[c]
        X = np.concatenate([d["X_train"], d["X_test"]])
        y = np.concatenate([d["y_train"], d["y_test"]])
        levels[c] = {}
        for k, f in enumerate(floors):
            entry = signal_levels(X[y == k], fs)
            sel = (ds["condition"].values == c) & (ds["floor"].values == f)
            for name in _TRIAL_DIAGNOSTICS:
                if name in ds.coords and sel.any():
                    entry[name] = float(np.mean(ds[name].values[sel]))
            levels[c][f] = entry
    return {
        "meta": {
            "evaluation": "6.2: quiet packets dropped, 800-sample windows, odd train / even "
            "test, per movement condition",
            "floors": floors,
            "conditions": conditions,
            "packet_samples": PACKET_SAMPLES,
            "window_samples": WINDOW_SAMPLES,
            "quiet_variance_v2": QUIET_VARIANCE_V2,
            "n_trials": int(ds.sizes["trial"]),
            # the simulated session's floors and robot, when the dataset records them
            "floor_specs": json.loads(ds.attrs.get("floors", "{}")),
            "robot": json.loads(ds.attrs.get("robot", "{}")),
        },
        "parameters": {"floor": {"coordinate": "floor", "unit": "name", "values": floors}},
        "classifiers": {
            m: {"mean_correct": out[m]["mean_correct"], "seconds": round(seconds[m], 3)}
            for m in methods
        },
        "confusion": out["spectral_template"]["confusion"],
        "mean_correct": out["spectral_template"]["mean_correct"],
        "per_floor_correct": out["spectral_template"]["per_floor_correct"],
        "cross_condition": cross,
        "naive_bayes": out["naive_bayes"],
        "spectral_nearest": out["spectral_nearest"],
        "windows": {c: data[c]["windows"] for c in conditions},
        "packets": {c: data[c]["packets"] for c in conditions},
        "saturated_trials": saturated,
        "levels": levels,
        "templates": templates,
    }


#: Result keys left out of the spread tree: the templates' spectra (averaged, but a
#: spread per frequency bin would only bloat the file) and the run's description.
_NO_SPREAD = ("meta", "parameters", "templates")


def run_floor_texture_seeds(
    ds: xr.Dataset, *, progress: Callable[[int, int, str], None] | None = None
) -> dict[str, Any]:
    """Evaluate each session of a dataset and give every figure as mean and spread.

    Parameters
    ----------
    ds : xarray.Dataset
        As for :func:`run_floor_texture`; a coordinate ``seed`` (one value per session)
        splits it into sessions (without one: a single session).
    progress : callable, optional
        ``progress(done, total, description)`` over all sessions.

    Returns
    -------
    dict
        The keys of :func:`run_floor_texture`, every number the mean over the sessions
        (confusion matrices as mean counts), plus ``spread`` (per number: ``mean``,
        ``std``, ``min``, ``max``, ``n``, ``values`` in seed order); ``meta`` gains
        ``seeds`` and ``n_seeds``.
    """
    if "seed" in ds.coords:
        seeds = sorted({int(v) for v in ds["seed"].values.tolist()})
    else:
        seeds = []
    parts = (
        [ds.isel(trial=np.flatnonzero(ds["seed"].values == s)) for s in seeds]
        if len(seeds) > 1
        else [ds]
    )
    per_seed = []
    for k, part in enumerate(parts):

        def step(done: int, total: int, desc: str, k: int = k) -> None:
            if progress:
                progress(k * total + done, len(parts) * total, desc)

        per_seed.append(run_floor_texture(part, progress=step))
    figures = [{k: v for k, v in r.items() if k not in _NO_SPREAD} for r in per_seed]
    mean, spread = seed_spread(figures)
    templates, _ = seed_spread([r["templates"] for r in per_seed])
    first = per_seed[0]
    meta = {
        **first["meta"],
        "n_trials": int(ds.sizes["trial"]),
        "seeds": seeds or [int(ds.attrs.get("seed", 0))],
        "n_seeds": len(parts),
    }
    return {
        "meta": meta,
        "parameters": first["parameters"],
        **mean,
        "templates": templates,
        SPREAD_KEY: spread or {},
    }
