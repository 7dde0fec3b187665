"""Chapter 6.4: texture and distance on the BIOTACT G1 head, with and without RCP.

The G1 head whisks two rows of three whiskers at 2 Hz into a vertical surface (smooth
plastic, P600 or P180 silicon-carbide paper) 5, 10 or 15 mm ahead of it, unmodulated
or with rapid cessation of protraction (RCP7, RCP9), twelve whisks per class
(:mod:`vibrissa.experiments.biotact`). Hit rate against 1-8 training whisks for
stationary naive Bayes and class-mean templates, on the 9-class problem and on
texture or distance alone (:mod:`vibrissa.evaluate.biotact`), beside figures 6.6
and 6.7.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.reproduce.registry import Experiment, Option, register

#: What 6.4.4 says of each curve (figures 6.6 and 6.7 give no numbers in the text).
THESIS = {
    ("naive_bayes", "joint"): "rises, maximum after 4-5 whisks (unmodulated); RCP higher "
                              "after 1-2 whisks, RCP7 best; RCP7 reaches 100 % after 7",
    ("naive_bayes", "texture"): "high after 3-4 whisks; RCP7 best, then RCP9, then "
                                "unmodulated; maximum at 4 whisks",
    ("naive_bayes", "distance"): "high after 3-4 whisks; RCP7 best, then RCP9, then "
                                 "unmodulated; maximum at 4 whisks",
    ("template", "joint"): "maximum after 4-5 whisks (unmodulated); RCP higher after 1-2 "
                           "whisks; RCP7 improves little; RCP9 falls, then improves after 6",
    ("template", "texture"): "unmodulated only reaches 75 %; RCP9 higher",
    ("template", "distance"): "like naive Bayes (unmodulated); RCP9 higher below 3 whisks, "
                              "RCP lower than unmodulated with more",
}
CLASSIFIER_TITLES = {"naive_bayes": "stationary naive Bayes (figure 6.6)",
                     "template": "class-mean templates (figure 6.7)"}


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
            None if a is None or b is None else bool(a > b))
        out["rcp7_nb_joint_mean_1_2"] = a
        out["unmodulated_nb_joint_mean_1_2"] = b
        out["rcp7_nb_joint_at_7"] = r7[6] if len(r7) > 6 else None
    out["first_perfect_nb_joint"] = {
        s: next((i + 1 for i, r in enumerate(c["naive_bayes"]["joint"]) if r == 1.0), None)
        for s, c in hit.items()}
    return out


def _discussion(ws: Mapping[str, Any], chk: Mapping[str, Any]) -> list[str]:
    """What this run says about 6.4.5's reading of RCP, computed from its numbers."""
    if "unmodulated" not in ws or "rcp7" not in ws:
        return []
    un, r7 = ws["unmodulated"], ws["rcp7"]
    beats = chk.get("rcp7_beats_unmodulated_nb_joint_1_2_whisks")
    steadier = r7["peak_spread"] < un["peak_spread"]
    shorter = r7["contact_time_s"] < un["contact_time_s"]
    lower = r7["peak_deflection_v"] < un["peak_deflection_v"]
    return [
        f"RCP7 {'shortens' if shorter else 'lengthens'} "
        f"the contact ({r7['contact_time_s']:.3f} s against {un['contact_time_s']:.3f} s per "
        f"whisker and whisk) and {'lowers' if lower else 'raises'} "
        f"the peak deflection ({r7['peak_deflection_v']:.3f} V against "
        f"{un['peak_deflection_v']:.3f} V), as 6.4.5 says RCP does. 6.4.5 suggests its "
        "benefit 'may be to increase the repeatability of whisker-surface contacts'; here "
        f"RCP7's whisks are {'more' if steadier else 'less'} repeatable than unmodulated "
        f"ones (within-class spread of the peak {r7['peak_spread']:.3f} against "
        f"{un['peak_spread']:.3f}), and RCP7 "
        f"{'beats' if beats else 'does not beat'} unmodulated whisking for naive Bayes after "
        "one or two training whisks."
        + ("" if steadier else " One possible reason: the feedback turns each contact's "
           "fluctuations (grains, the ringing left by the previous whisk) into changes of "
           "the housing's motion, which the unmodulated whisk does not have."),
    ]


@register
class BiotactG1(Experiment):
    """Thesis 6.4 (see the module docstring)."""

    name = "biotact-g1"
    chapter = 6
    title = "Chapter 6.4 reproduction: texture and distance on the BIOTACT G1 with RCP"
    description = ("BIOTACT G1 head (2 x 3 whiskers) whisking into 3 textures at 3 distances, "
                   "unmodulated, RCP7 and RCP9: naive Bayes and template hit rates against "
                   "training whisks (figures 6.6, 6.7)")
    options = (
        Option("distances", "", "Horizontal distances of the surface from the head's front, "
               "mm, comma-separated (default 5,10,15; --quick 5,15).", minimum=2,
               numbers=True),
        Option("whisk_frequency", "", "Whisk frequency, Hz (default 2).", numbers=True),
    )

    def protocol(self, quick: bool, seed: int) -> Any:
        from vibrissa.experiments.biotact import biotact_protocol

        return biotact_protocol(quick=quick, seed=seed)

    def protocol_for(self, quick: bool, seed: int, options: Mapping[str, Any]) -> Any:
        from vibrissa.experiments.biotact import biotact_protocol
        from vibrissa.robots.biotact import G1Head

        freq = tuple(options.get("whisk_frequency") or ())
        if len(freq) > 1:
            raise ValueError(f"--whisk-frequency takes one number, got {len(freq)}")
        if freq and freq[0] <= 0:
            raise ValueError(f"--whisk-frequency must be > 0 Hz, got {freq[0]:g}")
        dists = tuple(options.get("distances") or ())
        for d in dists:
            G1Head().check_distance(d, "--distances")
        try:
            return biotact_protocol(quick=quick, seed=seed, distances_mm=dists or None,
                                    whisk_frequency_hz=freq[0] if freq else None)
        except ValueError as exc:
            raise ValueError(str(exc).replace("whisk_frequency_hz", "--whisk-frequency")
                             .replace("distances_mm", "--distances")) from None

    def n_trials(self, quick: bool) -> int:
        return int(self.protocol(quick, 0).n_trials)

    def evaluate(self, ds: xr.Dataset, *, seed: int, progress: Callable | None,
                 options: Mapping[str, Any], workers: int | None = None) -> dict[str, Any]:
        from vibrissa.evaluate.biotact import hit_rate_curves, whisk_statistics

        res = hit_rate_curves(ds, progress=progress)
        # beside the thesis: naive Bayes with bins over the central 99 % of each channel
        robust = hit_rate_curves(ds, classifiers=("naive_bayes",), value_range="robust")
        proto = json.loads(ds.attrs.get("protocol_params", "{}"))
        textures = list(dict.fromkeys(np.asarray(ds["texture"].values).astype(str).tolist()))
        dists = sorted({float(v) for v in ds["distance_mm"].values})
        return {
            "meta": {"n_trials": int(ds.sizes["trial"]),
                     "sample_rate_hz": float(ds.attrs["sample_rate_hz"]),
                     "channels": [str(c) for c in ds["channel"].values],
                     "whisks_per_class": int(ds["whisk"].values.max()),
                     "protocol": proto,
                     "textures": json.loads(ds.attrs.get("textures", "{}")),
                     "evaluation": "train on whisks 1..n of every class, validate on the "
                                   "rest (6.4.4); hit rate = correct / validation whisks"},
            "parameters": {"texture": {"coordinate": "texture", "unit": "name",
                                       "values": textures},
                           "distance_mm": {"coordinate": "distance_mm", "unit": "mm",
                                           "values": dists}},
            "classifiers": {"naive_bayes": "stationary naive Bayes, raw values, 100 bins over "
                                           "each channel's range, Gaussian FWHM 5 bins",
                            "template": "class-mean templates, raw, sum of squared errors"},
            "hit_rate": res["hit_rate"],
            "n_validation": res["n_validation"],
            "naive_bayes_robust_range": {s: v["naive_bayes"]
                                         for s, v in robust["hit_rate"].items()},
            "whisks": whisk_statistics(ds),
            "checks": _checks(res["hit_rate"]),
        }

    def write_outputs(self, results: Mapping[str, Any], out_dir: Path, *,
                      dataset: xr.Dataset | None, figures: bool,
                      workers: int | None = None) -> dict[str, Path]:
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.evaluate.figures.whisking import hit_rate_figure

        if not figures:
            return {}
        fig_dir = Path(out_dir) / "figures"
        hit = results["hit_rate"]
        out = {}
        for c, title in CLASSIFIER_TITLES.items():
            fig = hit_rate_figure({s: v[c] for s, v in hit.items()}, title)
            out[f"hit_rate_{c}"] = save_figure(fig, fig_dir / f"hit_rate_{c}.png")
        if dataset is not None:
            out.update(_trajectory_figures(dataset, fig_dir))
        return out

    def report_sections(self, results: Mapping[str, Any], figures: Mapping[str, Path],
                        baseline: Mapping[str, Any] | None) -> str:
        from vibrissa.evaluate.report_common import fmt, md_table

        hit = results["hit_rate"]
        meta = results["meta"]
        proto = meta.get("protocol") or {}
        head = proto.get("head") or {}
        chk = results["checks"]
        n_max = max(len(v) for s in hit.values() for c in s.values() for v in c.values())
        out = [
            "The BIOTACT G1 (thesis 3.4, 6.4): a cone-shaped head with two bilaterally "
            "symmetric rows of three whiskers (80, 112, 158 mm) whisking at "
            f"{proto.get('whisk_frequency_hz', 2):g} Hz into a vertical surface at "
            f"{', '.join(f'{d:g}' for d in results['parameters']['distance_mm']['values'])} "
            "mm from the head's front; textures "
            f"{', '.join(results['parameters']['texture']['values'])}; "
            f"{meta['whisks_per_class']} whisks per class; 12 channels (x and y of six "
            "whiskers) at 2 kHz. Strategies: unmodulated, RCP7 (sigma_z = 0.7), RCP9 "
            f"(sigma_z = 0.9), tau_z = T_w x {proto.get('tau_z_periods', 0.25):g} (3.4.2).",
            "",
            "## Does RCP7 beat unmodulated whisking for naive Bayes after few whisks?",
            "",
            md_table(["claim (thesis 6.4.4)", "this run"], [
                ["RCP7 above unmodulated after 1-2 training whisks (9-class, naive Bayes)",
                 "n/a" if chk.get("rcp7_beats_unmodulated_nb_joint_1_2_whisks") is None else
                 f"{'yes' if chk['rcp7_beats_unmodulated_nb_joint_1_2_whisks'] else 'no'}: "
                 f"mean {fmt(chk['rcp7_nb_joint_mean_1_2'], 3)} against "
                 f"{fmt(chk['unmodulated_nb_joint_mean_1_2'], 3)}"],
                ["RCP7 reaches 100 % after seven training whisks",
                 "n/a" if chk.get("rcp7_nb_joint_at_7") is None
                 else f"{fmt(100 * chk['rcp7_nb_joint_at_7'], 1)} % after seven"],
                ["first number of training whisks at 100 % (9-class, naive Bayes)",
                 ", ".join(f"{s}: {v if v is not None else 'never'}"
                           for s, v in chk["first_perfect_nb_joint"].items())],
            ]),
            "",
        ]
        for c, title in CLASSIFIER_TITLES.items():
            out += [f"## Hit rate: {title}", ""]
            rows = []
            for task in ("joint", "texture", "distance"):
                for s, curves in hit.items():
                    rows.append([task, s] + [fmt(r, 3) if r is not None else "-"
                                             for r in curves[c][task]]
                                + [THESIS[(c, task)] if s == next(iter(hit)) else ""])
            out += [md_table(["task", "strategy"] + [str(n) for n in range(1, n_max + 1)]
                             + ["thesis"], rows), ""]
            if f"hit_rate_{c}" in figures:
                out += [f"![{title}]({figures[f'hit_rate_{c}']})", ""]
        rob = results.get("naive_bayes_robust_range")
        if rob:
            out += [
                "### Beside the thesis: naive Bayes with bins over the central 99 %",
                "",
                "6.4.2's bins span each channel's whole training range, so every training "
                "whisk that adds an extreme value (a snap at contact onset) makes the bins "
                "coarser; where the hit rates above fall as training whisks are added, "
                "this is the first suspect. The same classifier with each channel's bins "
                "over the central 99 % of its training values:",
                "",
                md_table(["task", "strategy"] + [str(n) for n in range(1, n_max + 1)],
                         [[t, s] + [fmt(r, 3) if r is not None else "-" for r in c[t]]
                          for t in ("joint", "texture", "distance") for s, c in rob.items()]),
                "",
            ]
        ws = results["whisks"]
        out += [
            "## The whisks",
            "",
            "Per strategy, over all whisks: contact time per whisker and whisk, peak x "
            "deflection from rest, its spread within a class (std / mean over the whisks "
            "of a class, mean over classes and whiskers; the thesis suggests RCP's benefit "
            "'may be to increase the repeatability of whisker-surface contacts'), the "
            "largest gating variable z and the whisks with a saturated sensor.",
            "",
            md_table(["strategy", "contact time (s)", "peak deflection (V)",
                      "within-class spread", "max z", "saturated whisks"],
                     [[s, fmt(v["contact_time_s"], 3), fmt(v["peak_deflection_v"], 3),
                       fmt(v["peak_spread"], 3), fmt(v["max_z"], 2), v["saturated_whisks"]]
                      for s, v in ws.items()]),
            "",
        ]
        out += _discussion(ws, chk) + [""]
        for key, cap in (("trajectories", "One whisk of each strategy"),
                         ("distances", "Unmodulated whisks at each distance")):
            if key in figures:
                out += [f"{cap} (housing angle of the left row, Hall x of the 158 mm left "
                        "whisker, gating z; contact of that whisker shaded):", "",
                        f"![{cap}]({figures[key]})", ""]
        out += [
            "## Modelling choices",
            "",
            f"- Head: a truncated cone of half angle {head.get('cone_half_angle_deg', '?')} "
            f"deg, front radius {head.get('front_radius_mm', '?')} mm; the whiskers pivot "
            f"{', '.join(f'{v:g}' for v in head.get('setbacks_mm', []))} mm behind the "
            "front face, so that the three straight whiskers reach a plane 10 mm ahead at "
            "the same protraction (60 deg from the axis), as the thesis' length "
            "choice intends. The whisk: from "
            f"{head.get('retracted_deg', '?')} deg (full retraction) to "
            f"{head.get('retracted_deg', 0) - head.get('amplitude_deg', 0):g} deg from the "
            "axis, in the rows' horizontal plane; the module's servo is a critically "
            f"damped {proto.get('motor_bandwidth_hz', '?')} Hz second-order follower.",
            "- Textures: smooth plastic (Ra ~ 0.1 um) and FEPA P600 and P180 silicon-"
            "carbide papers, both sold as 3M Wetordry Tri-M-ite; one fine, one coarse "
            "(the thesis does not give the grades).",
            "- A class's whisks are one continuous run after a lead-in whisk from rest "
            "(dropped), so each whisk inherits the previous one's ringing and gating "
            "variable. Whisk-to-whisk variation: that inheritance, the whisk amplitude "
            f"(std {proto.get('amplitude_jitter_deg', '?')} deg per side and whisk, an "
            "assumption) and the sensors' noise; where each tip meets the sheet is drawn "
            "once per class.",
            "- Naive Bayes: 'Gaussian of width 5 intervals' read as a full width at half "
            "maximum of 5 bins (sigma 2.12 bins); bins span each channel's whole training "
            "range (6.4.2). Templates: the class mean of each channel over the training "
            "whisks, raw signals, sum of squared errors over the 12 channels (6.4.3).",
            "",
        ]
        return "\n".join(out)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        return {"hit_rate": results["hit_rate"], "n_validation": results["n_validation"],
                "naive_bayes_robust_range": results.get("naive_bayes_robust_range"),
                "whisks": results["whisks"], "checks": results["checks"]}


def _trajectory_figures(ds: xr.Dataset, fig_dir: Path) -> dict[str, Path]:
    """Whisk trajectories with contacts: one whisk per strategy (middle class), and
    the unmodulated whisks at every distance (middle texture)."""
    from vibrissa.evaluate.figures.common import save_figure
    from vibrissa.evaluate.figures.whisking import whisk_trajectories_figure

    strat = np.asarray(ds["strategy"].values).astype(str)
    tex = np.asarray(ds["texture"].values).astype(str)
    dist = np.asarray(ds["distance_mm"].values, dtype=float)
    whisk = np.asarray(ds["whisk"].values)
    textures = list(dict.fromkeys(tex.tolist()))
    dists = sorted(set(dist.tolist()))
    t_mid, d_mid = textures[len(textures) // 2], dists[len(dists) // 2]
    chans = [str(c) for c in ds["channel"].values]
    wid = [str(w) for w in ds["whisker_id"].values]
    xi, fi = chans.index("L3x"), wid.index("L3")
    out: dict[str, Path] = {}

    def draw(cases: list[tuple[str, float]], name: str) -> None:
        """First whisk of each (strategy, distance) at the middle texture."""
        picks, titles = [], []
        for s, d in cases:
            m = np.flatnonzero((strat == s) & (tex == t_mid) & (dist == d) & (whisk == 1))
            if m.size:
                picks.append(int(m[0]))
                titles.append(f"{s}: {t_mid}, {d:g} mm")
        if not picks:
            return
        fig = whisk_trajectories_figure(
            ds["time"].values, ds["angle_deg"].values[picks, 0],
            ds["signal"].values[picks, xi], ds["force_n"].values[picks, fi], titles,
            gating=ds["gating"].values[picks, 0], signal_label="Hall x, L3 (V)")
        out[name] = save_figure(fig, fig_dir / f"{name}.png")

    draw([(s, d_mid) for s in dict.fromkeys(strat.tolist())], "trajectories")
    draw([(strat[0], d) for d in dists], "distances")
    return out
