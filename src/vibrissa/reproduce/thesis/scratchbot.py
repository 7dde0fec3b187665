"""Chapter 6.3: radial distance and whisk speed on SCRATCHbot, a whisking robot.

A stationary head whisks one whisker into a vertical pole at 70, 100 and 130 mm
and 2, 4 and 6 Hz (:mod:`vibrissa.experiments.scratchbot`). Per condition the
peak deflection and the contact duration of every whisk (the chapter-4 features,
4.3.4: peak magnitude and the supra-0.05 V run about the peak); the chapter-4
feature and template classifiers trained on the odd whisks and tested on the
even ones. The report also draws figure 3.9 (rapid cessation of protraction
with two gains, :func:`vibrissa.robots.whisking.obstacle_whisk`).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.experiments.scratchbot import scratchbot_protocol
from vibrissa.reproduce.registry import Experiment, register

#: Chapter-4 feature threshold gamma (V, 4.3.4).
THRESHOLD_V = 0.05
#: Figure 3.9's two settings: (sigma_z, tau_z as a fraction of T_w).
FIG_3_9 = {"a": (0.7, 0.25), "b": (2.0, 0.1)}


def _stats(x: np.ndarray) -> dict[str, float]:
    return {"mean": float(np.mean(x)), "std": float(np.std(x))}


def _fig_3_9() -> dict[str, Any]:
    from vibrissa.robots.whisking import count_contacts, obstacle_whisk

    out = {}
    for key, (s, tau) in FIG_3_9.items():
        r = obstacle_whisk(s, tau)
        touching = r.angle_deg[0] > r.obstacle_deg[0]
        onsets = np.flatnonzero(touching[1:] & ~touching[:-1]) + 1
        period = 1.0 / 8.0  # obstacle_whisk's default whisk frequency
        later = onsets[r.time_s[onsets] >= period]
        out[key] = {
            "sigma_z": s, "tau_z_periods": tau,
            "contacts_left": count_contacts(r.angle_deg[0] - r.obstacle_deg[0], 0.0, -2.0),
            "contacts_right": count_contacts(r.angle_deg[1] - r.obstacle_deg[1], 0.0, -2.0),
            "whisks": 3,
            "z_max": float(r.gating[0].max()),
            "z_at_next_whisk": float(r.gating[0][later[0]]) if later.size else None,
            "_arrays": r,
        }
    return out


def _episodes(force: np.ndarray, dt_s: float, gap_s: float = 0.02) -> int:
    """Contacts: runs of positive force, bounces closer than ``gap_s`` merged."""
    idx = np.flatnonzero(force > 0)
    return 0 if idx.size == 0 else 1 + int(np.sum(np.diff(idx) * dt_s > gap_s))


def _closed_loop(ds: xr.Dataset) -> dict[str, Any] | None:
    """Per RCP setting of the closed-loop runs: peak deflection (V), contacts and
    contact time per whisk, largest ``z``."""
    from vibrissa.robots.whisking import HALF_RANGE_FRACTION

    if "rcp_gating" not in ds:
        return None
    p = json.loads(ds.attrs["protocol_params"])
    half_v = HALF_RANGE_FRACTION * float(p["sensor"]["supply_v"])
    n_whisks = int(p["rcp_whisks"])
    dt = float(ds["rcp_time"].values[1] - ds["rcp_time"].values[0])
    out = []
    for i in range(ds.sizes["rcp_setting"]):
        force = ds["rcp_force_n"].values[i]
        out.append({
            "sigma_z": float(ds["rcp_sigma_z"].values[i]),
            "tau_z_periods": float(ds["rcp_tau_z_periods"].values[i]),
            "peak_deflection_v": float(np.abs(ds["rcp_deflection"].values[i]).max() * half_v),
            "max_contact_force_n": float(force.max()),
            "contacts_per_whisk": _episodes(force, dt) / n_whisks,
            "contact_time_per_whisk_s": float(np.count_nonzero(force > 0) * dt / n_whisks),
            "max_z": float(ds["rcp_gating"].values[i].max()),
        })
    return {"radial_distance_mm": float(p["rcp_radial_distance_mm"]),
            "whisk_frequency_hz": float(p["rcp_whisk_frequency_hz"]), "whisks": n_whisks,
            "settings": out}


@register
class Scratchbot(Experiment):
    """Thesis 6.3 (see the module docstring)."""

    name = "scratchbot"
    chapter = 6
    title = "Chapter 6.3 reproduction: radial distance and whisk speed on SCRATCHbot"
    description = ("SCRATCHbot whisking into a pole at 3 distances x 3 whisk frequencies: "
                   "peak deflection, contact duration, feature and template classifiers "
                   "(figure 6.5); RCP gating (figure 3.9)")

    def protocol(self, quick: bool, seed: int) -> Any:
        return scratchbot_protocol(quick=quick, seed=seed)

    def evaluate(self, ds: xr.Dataset, *, seed: int, progress: Callable | None,
                 options: Mapping[str, int], workers: int | None = None) -> dict[str, Any]:
        from vibrissa.classify import (
            FeatureRegressionClassifier,
            TimeTemplateClassifier,
            contact_features,
        )
        from vibrissa.data import as_arrays

        fs = float(ds.attrs["sample_rate_hz"])
        labels = ["radial_distance_mm", "whisk_frequency_hz"]
        X, y = as_arrays(ds, labels)
        feats = contact_features(X, fs, threshold_v=THRESHOLD_V, duration_mode="peak")
        conditions = []
        for r, f in sorted({(float(a), float(b)) for a, b in y}, key=lambda t: (t[1], t[0])):
            m = (y[:, 0] == r) & (y[:, 1] == f)
            conditions.append({
                "radial_distance_mm": r, "whisk_frequency_hz": f,
                "peak_deflection_v": _stats(feats[m, 0]),
                "contact_duration_s": _stats(feats[m, 1]),
                "n_whisks": int(m.sum()),
            })
        train = ds["set"].values == 1
        test = ~train
        clfs = {
            "feature": FeatureRegressionClassifier(sample_rate_hz=fs, threshold_v=THRESHOLD_V,
                                                   degree=2, duration_mode="peak"),
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
            np.all(np.diff([c["peak_deflection_v"]["mean"] for c in conditions
                            if c["whisk_frequency_hz"] == f]) < 0)
            for f in {c["whisk_frequency_hz"] for c in conditions})
        dur_falls = all(
            np.all(np.diff([c["contact_duration_s"]["mean"] for c in conditions
                            if c["radial_distance_mm"] == r]) < 0)
            for r in {c["radial_distance_mm"] for c in conditions})
        fig39 = {k: {kk: vv for kk, vv in v.items() if not kk.startswith("_")}
                 for k, v in _fig_3_9().items()}
        closed_loop = _closed_loop(ds)
        sat = ds["run_saturated"].values if "run_saturated" in ds else np.zeros(1)
        return {
            "meta": {"n_trials": int(X.shape[0]), "sample_rate_hz": fs,
                     "feature_threshold_v": THRESHOLD_V,
                     "protocol": json.loads(ds.attrs.get("protocol_params", "{}")),
                     "split": {"train": "odd whisks (set 1)", "test": "even whisks (set 2)",
                               "n_train": int(train.sum()), "n_test": int(test.sum())},
                     "saturated_fraction": float(np.mean(sat))},
            "parameters": {
                "radial_distance_mm": {"unit": "mm",
                                       "values": sorted({c["radial_distance_mm"]
                                                         for c in conditions})},
                "whisk_frequency_hz": {"unit": "Hz",
                                       "values": sorted({c["whisk_frequency_hz"]
                                                         for c in conditions})},
            },
            "classifiers": classifiers,
            "conditions": conditions,
            "relations": {"peak_falls_with_distance": bool(peak_falls),
                          "duration_falls_with_frequency": bool(dur_falls)},
            "figure_3_9": fig39,
            "closed_loop": closed_loop,
        }

    def write_outputs(self, results: Mapping[str, Any], out_dir: Path, *,
                      dataset: xr.Dataset | None, figures: bool,
                      workers: int | None = None) -> dict[str, Path]:
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.evaluate.figures.whisking import (
            gating_figure,
            scratchbot_features_figure,
            whisk_trajectories_figure,
        )

        if not figures:
            return {}
        fig_dir = Path(out_dir) / "figures"
        out = {"features": save_figure(scratchbot_features_figure(results["conditions"]),
                                       fig_dir / "scratchbot_features.png")}
        panels = []
        for key, v in _fig_3_9().items():
            a = v["_arrays"]
            panels.append({"title": f"({key}) sigma_z = {v['sigma_z']:g}, tau_z = "
                                    f"T_w x {v['tau_z_periods']:g}",
                           "time_s": a.time_s, "angle_deg": a.angle_deg, "gating": a.gating,
                           "obstacle_deg": a.obstacle_deg})
        out["figure_3_9"] = save_figure(gating_figure(panels), fig_dir / "figure_3_9.png")
        if dataset is not None and "run_angle_deg" in dataset:
            p = dict(zip(dataset["condition"].values.tolist(), range(dataset.sizes["condition"]),
                         strict=True))
            conds = results["conditions"]
            pick = [i for i, c in enumerate(conds) if c["radial_distance_mm"] == 100.0] \
                or list(range(min(3, len(conds))))
            pick = [p[i] for i in pick][:3]
            t = dataset["run_time"].values
            fig = whisk_trajectories_figure(
                t, dataset["run_angle_deg"].values[pick], dataset["run_raw_v"].values[pick],
                dataset["run_force_n"].values[pick],
                [f"R = {conds[i]['radial_distance_mm']:g} mm, S = "
                 f"{conds[i]['whisk_frequency_hz']:g} Hz" for i in pick])
            out["trajectories"] = save_figure(fig, fig_dir / "whisk_trajectories.png")
        if dataset is not None and "rcp_gating" in dataset:
            from vibrissa.robots.whisking import HALF_RANGE_FRACTION

            n = dataset.sizes["rcp_setting"]
            fig = whisk_trajectories_figure(
                dataset["rcp_time"].values, dataset["rcp_angle_deg"].values,
                dataset["rcp_deflection"].values * HALF_RANGE_FRACTION * 5.0,
                dataset["rcp_force_n"].values,
                [f"sigma_z = {dataset['rcp_sigma_z'].values[i]:g}, tau_z = T_w x "
                 f"{dataset['rcp_tau_z_periods'].values[i]:g}" for i in range(n)],
                gating=dataset["rcp_gating"].values, signal_label="Hall x from rest (V)")
            out["closed_loop"] = save_figure(fig, fig_dir / "closed_loop.png")
        return out

    def report_sections(self, results: Mapping[str, Any], figures: Mapping[str, Path],
                        baseline: Mapping[str, Any] | None) -> str:
        from vibrissa.evaluate.report_common import fmt, md_table

        rel = results["relations"]
        rows = [[fmt(c["radial_distance_mm"], 0), fmt(c["whisk_frequency_hz"], 0),
                 f"{fmt(c['peak_deflection_v']['mean'], 3)} +/- "
                 f"{fmt(c['peak_deflection_v']['std'], 3)}",
                 f"{fmt(c['contact_duration_s']['mean'], 3)} +/- "
                 f"{fmt(c['contact_duration_s']['std'], 3)}", c["n_whisks"]]
                for c in results["conditions"]]
        proto = results["meta"].get("protocol") or {}
        setup = (
            f" The simulated head: the `{proto.get('whisker', 'scratchbot')}` whisker (3.2.3) "
            f"whisked {proto.get('amplitude_deg', '?')} deg from full retraction by a "
            f"{proto.get('motor_bandwidth_hz', '?')} Hz servo, the pole touching the straight "
            f"whisker {proto.get('contact_angle_deg', '?')} deg into the whisk, unmodulated "
            "(RCP off); each whisk's deflection is the Hall x minus the same whisk in air "
            "(self-motion cancelled), its features those of chapter 4 (peak magnitude; time "
            f"above {THRESHOLD_V:g} V about the peak)." if proto else "")
        out = [
            "SCRATCHbot (thesis 6.3) kept stationary, whisking one whisker into a vertical "
            "pole." + setup + " The thesis gives no numbers for this experiment, only "
            "figure 6.5 and two relations; ours beside them:",
            "",
            md_table(["relation", "thesis (6.3, fig 6.5)", "this run"], [
                ["peak deflection vs radial distance",
                 "varies predictably: falls with distance (fig 6.5 a)",
                 "falls at every frequency" if rel["peak_falls_with_distance"]
                 else "does NOT fall monotonically at every frequency"],
                ["contact duration vs whisk speed",
                 "falls as speed rises (the reverse of the XY robot)",
                 "falls at every distance" if rel["duration_falls_with_frequency"]
                 else "does NOT fall monotonically at every distance"],
            ]),
            "",
            "## Per condition (mean +/- std over whisks)",
            "",
            md_table(["R (mm)", "S (Hz)", "peak deflection (V)", "contact duration (s)",
                      "whisks"], rows),
            "",
        ]
        if "features" in figures:
            out += [f"![figure 6.5: features]({figures['features']})", ""]
        if "trajectories" in figures:
            out += ["Whisk trajectories (housing angle, raw Hall x; contacts shaded):", "",
                    f"![whisk trajectories]({figures['trajectories']})", ""]
        crow = [[k, f"{fmt(v['radius_mm']['mean'])} / {fmt(v['radius_mm']['std'])}",
                 f"{fmt(v['whisk_frequency_hz']['mean'])} / "
                 f"{fmt(v['whisk_frequency_hz']['std'])}",
                 fmt(v["radius_mae_mm"]), fmt(v["whisk_frequency_mae_hz"]),
                 fmt(v["joint_correct"])] for k, v in results["classifiers"].items()]
        sp = results["meta"]["split"]
        out += [
            "## Chapter-4 classifiers",
            "",
            f"Trained on the {sp['train']} ({sp['n_train']}), tested on the {sp['test']} "
            f"({sp['n_test']}); the thesis ran none on this small set (\"too small to do an "
            "analysis similar to that conducted on the XY positioning robot data\").",
            "",
            md_table(["classifier", "radius error mean / std (mm)",
                      "frequency error mean / std (Hz)", "radius MAE (mm)",
                      "frequency MAE (Hz)", "joint correct"], crow),
            "",
            "## Figure 3.9: rapid cessation of protraction",
            "",
        ]
        f39 = results["figure_3_9"]
        out.append(md_table(
            ["setting", "thesis", "contacts (left, 3 whisks)", "right", "max z",
             "z at the next whisk's first contact"],
            [[f"({k}) sigma_z = {v['sigma_z']:g}, tau_z = T_w x {v['tau_z_periods']:g}",
              "one contact per whisk, no inter-whisk modulation" if k == "a"
              else "biphasic whisk, two contacts",
              v["contacts_left"], v["contacts_right"], fmt(v["z_max"]),
              fmt(v["z_at_next_whisk"], 3)] for k, v in f39.items()]))
        out.append("")
        if "figure_3_9" in figures:
            out += [f"![figure 3.9]({figures['figure_3_9']})", ""]
        cl = results.get("closed_loop")
        if cl:
            out += [
                "## RCP on the simulated whisker (closed loop)",
                "",
                f"The same SCRATCHbot whisker whisking {cl['whisks']} times into the pole at "
                f"{cl['radial_distance_mm']:g} mm, {cl['whisk_frequency_hz']:g} Hz, the "
                "housing commanded by the pattern generator and eqs. 3.2-3.3 from the Hall "
                "x deflection (no self-motion cancellation), one control period (1 ms) at a "
                "time. Minimal impingement (3.2.4): RCP keeps the deflection smaller.",
                "",
                md_table(["setting", "peak deflection (V)", "max contact force (N)",
                          "contacts per whisk", "contact time per whisk (s)", "max z"],
                         [[f"sigma_z = {v['sigma_z']:g}, tau_z = T_w x {v['tau_z_periods']:g}",
                           fmt(v["peak_deflection_v"], 3), fmt(v["max_contact_force_n"], 3),
                           fmt(v["contacts_per_whisk"]), fmt(v["contact_time_per_whisk_s"], 3),
                           fmt(v["max_z"])] for v in cl["settings"]]),
                "",
            ]
            if "closed_loop" in figures:
                out += [f"![closed loop]({figures['closed_loop']})", ""]
        return "\n".join(out)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        return {
            "conditions": [
                {k: c[k] for k in ("radial_distance_mm", "whisk_frequency_hz",
                                   "peak_deflection_v", "contact_duration_s")}
                for c in results["conditions"]
            ],
            "classifiers": results["classifiers"],
            "relations": results["relations"],
            "closed_loop": results.get("closed_loop"),
        }
