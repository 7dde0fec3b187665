"""SCRATCHbot's evaluation (thesis 6.3).

Features per condition, the chapter-4 classifiers on odd/even whisks, the relations of
figure 6.5, the closed-loop RCP runs and figure 3.9's numbers.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.classify import FeatureRegressionClassifier, TimeTemplateClassifier, contact_features
from vibrissa.data import as_arrays

__all__ = ["THRESHOLD_V", "closed_loop_summary", "evaluate_scratchbot"]

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
