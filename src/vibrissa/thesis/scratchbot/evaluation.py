"""SCRATCHbot's evaluation (thesis 6.3).

Features per condition, the chapter-4 classifiers on odd/even whisks, the relations of
figure 6.5, the closed-loop RCP runs and figure 3.9's numbers; over several sessions
(seeds), each figure as the mean over the sessions with its spread
(:func:`evaluate_scratchbot_sessions`).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.classify import FeatureRegressionClassifier, TimeTemplateClassifier, contact_features
from vibrissa.data import as_arrays
from vibrissa.evaluate.spread import SPREAD_KEY, seed_spread, spread_leaf

__all__ = [
    "RELATIONS",
    "THRESHOLD_V",
    "closed_loop_summary",
    "evaluate_scratchbot",
    "evaluate_scratchbot_sessions",
    "session_seeds",
]

#: The relations of figure 6.5 (booleans per session).
RELATIONS = ("peak_falls_with_distance", "duration_falls_with_frequency")
#: Sections the same in every session (deterministic or descriptive): from the first.
_SHARED = ("meta", "parameters", "figure_3_9", "closed_loop")

#: Chapter-4 feature threshold gamma (V, 4.3.4).
THRESHOLD_V = 0.05


def _stats(x: np.ndarray) -> dict[str, float]:
    return {"mean": float(np.mean(x)), "std": float(np.std(x))}


def _episodes(force: np.ndarray, dt_s: float, gap_s: float = 0.02) -> int:
    """Contacts: runs of positive force, bounces closer than ``gap_s`` merged."""
    idx = np.flatnonzero(force > 0)
    return 0 if idx.size == 0 else 1 + int(np.sum(np.diff(idx) * dt_s > gap_s))


def closed_loop_summary(ds: xr.Dataset, half_range_fraction: float) -> dict[str, Any] | None:
    """Per RCP setting of the closed-loop runs, their whisk statistics.

    Peak deflection (V), contacts and contact time per whisk, largest ``z``; ``None``
    without closed-loop runs.

    ``half_range_fraction`` scales the normalised deflection to volts: the Hall
    output's half range as a fraction of its supply
    (:data:`vibrissa.robots.whisking.HALF_RANGE_FRACTION`).
    """
    if "rcp_gating" not in ds:
        return None
    p = json.loads(ds.attrs["protocol_params"])
    half_v = half_range_fraction * float(p["sensor"]["supply_v"])
    n_whisks = int(p["rcp_whisks"])
    dt = float(ds["rcp_time"].values[1] - ds["rcp_time"].values[0])
    out = []
    for i in range(ds.sizes["rcp_setting"]):
        force = ds["rcp_force_n"].values[i]
        out.append(
            {
                "sigma_z": float(ds["rcp_sigma_z"].values[i]),
                "tau_z_periods": float(ds["rcp_tau_z_periods"].values[i]),
                "peak_deflection_v": float(np.abs(ds["rcp_deflection"].values[i]).max() * half_v),
                "max_contact_force_n": float(force.max()),
                "contacts_per_whisk": _episodes(force, dt) / n_whisks,
                "contact_time_per_whisk_s": float(np.count_nonzero(force > 0) * dt / n_whisks),
                "max_z": float(ds["rcp_gating"].values[i].max()),
                **(
                    {
                        "figure_3_9_contacts": [int(v) for v in ds["rcp_contacts"].values[i]],
                        "biphasic_whisks": int(np.sum(ds["rcp_contacts"].values[i] >= 2)),
                    }
                    if "rcp_contacts" in ds
                    else {}
                ),
            }
        )
    return {
        "radial_distance_mm": float(p["rcp_radial_distance_mm"]),
        "whisk_frequency_hz": float(p["rcp_whisk_frequency_hz"]),
        "whisks": n_whisks,
        "settings": out,
    }


def evaluate_scratchbot(
    ds: xr.Dataset,
    *,
    figure_3_9: Mapping[str, Mapping[str, Any]],
    half_range_fraction: float,
    progress: Callable | None = None,
) -> dict[str, Any]:
    """Evaluate a SCRATCHbot dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        The session of :func:`vibrissa.thesis.scratchbot.protocol.scratchbot_protocol`
        (or a recording with the same variables).
    figure_3_9 : mapping
        Figure 3.9's panel -> numbers (:meth:`vibrissa.robots.whisking.Figure39Panel.summary`).
    half_range_fraction : float
        See :func:`closed_loop_summary`.
    progress : callable, optional
        ``progress(done, total, name)`` after each classifier.

    Returns
    -------
    dict
        ``meta``, ``parameters``, ``classifiers``, ``conditions``, ``relations``,
        ``figure_3_9`` and ``closed_loop``.
    """
    fs = float(ds.attrs["sample_rate_hz"])
    labels = ["radial_distance_mm", "whisk_frequency_hz"]
    X, y = as_arrays(ds, labels)
    feats = contact_features(X, fs, threshold_v=THRESHOLD_V, duration_mode="peak")
    conditions: list[dict[str, Any]] = []
    for r, f in sorted({(float(a), float(b)) for a, b in y}, key=lambda t: (t[1], t[0])):
        m = (y[:, 0] == r) & (y[:, 1] == f)
        conditions.append(
            {
                "radial_distance_mm": r,
                "whisk_frequency_hz": f,
                "peak_deflection_v": _stats(feats[m, 0]),
                "contact_duration_s": _stats(feats[m, 1]),
                "n_whisks": int(m.sum()),
            }
        )
    train = ds["set"].values == 1
    test = ~train
    clfs = {
        "feature": FeatureRegressionClassifier(
            sample_rate_hz=fs, threshold_v=THRESHOLD_V, degree=2, duration_mode="peak"
        ),
        "template": TimeTemplateClassifier(sample_rate_hz=fs),
    }
    classifiers = {}
    for i, (name, clf) in enumerate(clfs.items()):
        clf.fit(X[train], y[train])
        pred = np.asarray(clf.predict(X[test]), dtype=float)
        err = pred - y[test]
        classifiers[name] = {
            "radius_mm": _stats(err[:, 0]),
            "whisk_frequency_hz": _stats(err[:, 1]),
            "radius_mae_mm": float(np.mean(np.abs(err[:, 0]))),
            "whisk_frequency_mae_hz": float(np.mean(np.abs(err[:, 1]))),
            "joint_correct": float(np.mean(np.all(err == 0, axis=1))),
        }
        if progress:
            progress(i + 1, len(clfs), name)
    peak_falls = all(
        np.all(
            np.diff(
                [c["peak_deflection_v"]["mean"] for c in conditions if c["whisk_frequency_hz"] == f]
            )
            < 0
        )
        for f in {c["whisk_frequency_hz"] for c in conditions}
    )
    dur_falls = all(
        np.all(
            np.diff(
                [
                    c["contact_duration_s"]["mean"]
                    for c in conditions
                    if c["radial_distance_mm"] == r
                ]
            )
            < 0
        )
        for r in {c["radial_distance_mm"] for c in conditions}
    )
    closed_loop = closed_loop_summary(ds, half_range_fraction)
    sat = ds["run_saturated"].values if "run_saturated" in ds else np.zeros(1)
    return {
        "meta": {
            "n_trials": int(X.shape[0]),
            "sample_rate_hz": fs,
            "feature_threshold_v": THRESHOLD_V,
            "protocol": json.loads(ds.attrs.get("protocol_params", "{}")),
            "split": {
                "train": "odd whisks (set 1)",
                "test": "even whisks (set 2)",
                "n_train": int(train.sum()),
                "n_test": int(test.sum()),
            },
            "saturated_fraction": float(np.mean(sat)),
        },
        "parameters": {
            "radial_distance_mm": {
                "unit": "mm",
                "values": sorted({c["radial_distance_mm"] for c in conditions}),
            },
            "whisk_frequency_hz": {
                "unit": "Hz",
                "values": sorted({c["whisk_frequency_hz"] for c in conditions}),
            },
        },
        "classifiers": classifiers,
        "conditions": conditions,
        "relations": {
            "peak_falls_with_distance": bool(peak_falls),
            "duration_falls_with_frequency": bool(dur_falls),
        },
        "figure_3_9": {k: dict(v) for k, v in figure_3_9.items()},
        "closed_loop": closed_loop,
    }


def session_seeds(ds: xr.Dataset) -> list[int]:
    """The seeds of the sessions in ``ds`` (one, the dataset's own, without ``session_seed``)."""
    if "session_seed" not in ds.coords and "session_seed" not in ds:
        return [int(ds.attrs.get("seed", 0))]
    return sorted({int(v) for v in np.asarray(ds["session_seed"].values)})


def evaluate_scratchbot_sessions(
    ds: xr.Dataset,
    *,
    figure_3_9: Mapping[str, Mapping[str, Any]],
    half_range_fraction: float,
    progress: Callable | None = None,
) -> dict[str, Any]:
    """Evaluate every session of ``ds``; each figure the mean over sessions, with its spread.

    Each session (trials of one ``session_seed``) is evaluated by
    :func:`evaluate_scratchbot`; :func:`vibrissa.evaluate.spread.seed_spread` gives the
    mean of every number over the sessions (the results' figures) and its spread (under
    ``spread``). A relation of figure 6.5 is true only if it holds in every session;
    ``relations.<name>_fraction`` is the fraction of sessions where it holds (its
    per-session 0/1 values under ``spread.relations.<name>``).

    Parameters
    ----------
    ds, figure_3_9, half_range_fraction
        As for :func:`evaluate_scratchbot`.
    progress : callable, optional
        ``progress(done, total, name)`` after each session.

    Returns
    -------
    dict
        The sections of :func:`evaluate_scratchbot` (means), ``meta.n_seeds``,
        ``meta.seeds`` and ``spread``.
    """
    seeds = session_seeds(ds)
    per: list[dict[str, Any]] = []
    for i, q in enumerate(seeds):
        sub = (
            ds
            if len(seeds) == 1
            else ds.isel(trial=np.flatnonzero(np.asarray(ds["session_seed"].values) == q))
        )
        per.append(
            evaluate_scratchbot(sub, figure_3_9=figure_3_9, half_range_fraction=half_range_fraction)
        )
        if progress:
            progress(i + 1, len(seeds), f"session {q}")
    varying = [{k: v for k, v in r.items() if k not in _SHARED} for r in per]
    mean, spread = seed_spread(varying)
    spread = dict(spread or {})
    relations: dict[str, Any] = {}
    rel_spread: dict[str, Any] = {}
    for key in RELATIONS:
        held = [bool(r["relations"][key]) for r in per]
        relations[key] = all(held)
        relations[f"{key}_fraction"] = float(np.mean(held))
        rel_spread[key] = spread_leaf([1.0 if h else 0.0 for h in held])
    spread["relations"] = rel_spread
    out = {k: per[0][k] for k in _SHARED}
    out["meta"] = {
        **per[0]["meta"],
        "n_trials": int(ds.sizes["trial"]),
        "n_seeds": len(seeds),
        "seeds": seeds,
        "seed_statistic": "each number is the mean over the sessions; its spread "
        "(mean, std, min, max, n, per-session values) under 'spread'",
    }
    out.update({k: v for k, v in mean.items() if k != "relations"})
    out["relations"] = relations
    out[SPREAD_KEY] = spread
    return out
