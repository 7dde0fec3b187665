"""SCRATCHbot's report sections (thesis 6.3).

Relations, conditions, classifiers, figure 3.9 and the closed-loop RCP runs; every number
from the results.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vibrissa.evaluate.report_common import fmt, md_table
from vibrissa.thesis.scratchbot.evaluation import THRESHOLD_V
from vibrissa.thesis.scratchbot.values import THESIS

__all__ = ["markdown_scratchbot"]


def markdown_scratchbot(results: Mapping[str, Any], figures: Mapping[str, Path]) -> str:
    """The report's Markdown body for SCRATCHbot results and the figures written.

    The results are those of
    :func:`~vibrissa.thesis.scratchbot.evaluation.evaluate_scratchbot`.
    """
    rel = results["relations"]
    spread = results.get("spread") or {}
    n_seeds = int(results["meta"].get("n_seeds", 1))

    def seeds_range(i: int, key: str) -> str:
        """Min-max over the sessions of condition ``i``'s mean ``key``."""
        try:
            leaf = spread["conditions"][i][key]["mean"]
        except (KeyError, IndexError, TypeError):
            return "-"
        return f"{fmt(leaf['min'], 3)}-{fmt(leaf['max'], 3)}" if leaf.get("n", 0) > 1 else "-"

    rows = [
        [
            fmt(c["radial_distance_mm"], 0),
            fmt(c["whisk_frequency_hz"], 0),
            f"{fmt(c['peak_deflection_v']['mean'], 3)} +/- {fmt(c['peak_deflection_v']['std'], 3)}",
            seeds_range(i, "peak_deflection_v"),
            f"{fmt(c['contact_duration_s']['mean'], 3)} +/- "
            f"{fmt(c['contact_duration_s']['std'], 3)}",
            seeds_range(i, "contact_duration_s"),
            c["n_whisks"],
        ]
        for i, c in enumerate(results["conditions"])
    ]

    def held(key: str, yes: str, no: str) -> str:
        frac = rel.get(f"{key}_fraction")
        text = yes if rel[key] else no
        if frac is None or n_seeds < 2:
            return text
        return f"{text} (in {round(frac * n_seeds)} of {n_seeds} sessions)"

    proto = results["meta"].get("protocol") or {}
    setup = (
        f" The simulated head: the `{proto.get('whisker', 'scratchbot')}` whisker (3.2.3) "
        f"whisked {proto.get('amplitude_deg', '?')} deg from full retraction by a "
        f"{proto.get('motor_bandwidth_hz', '?')} Hz servo, the pole touching the straight "
        f"whisker {proto.get('contact_angle_deg', '?')} deg into the whisk, unmodulated "
        "(RCP off); each whisk's deflection is the Hall x minus the same whisk in air "
        "(self-motion cancelled), its features those of chapter 4 (peak magnitude; time "
        f"above {THRESHOLD_V:g} V about the peak)."
        if proto
        else ""
    )
    out = [
        "SCRATCHbot (thesis 6.3) kept stationary, whisking one whisker into a vertical "
        "pole." + setup + " The thesis gives no numbers for this experiment, only "
        "figure 6.5 and two relations; ours beside them:",
        "",
        md_table(
            ["relation", "thesis (6.3, fig 6.5)", "this run"],
            [
                [
                    "peak deflection vs radial distance",
                    THESIS["peak_vs_distance"],
                    held(
                        "peak_falls_with_distance",
                        "falls at every frequency",
                        "does NOT fall monotonically at every frequency",
                    ),
                ],
                [
                    "contact duration vs whisk speed",
                    THESIS["duration_vs_speed"],
                    held(
                        "duration_falls_with_frequency",
                        "falls at every distance",
                        "does NOT fall monotonically at every distance",
                    ),
                ],
            ],
        ),
        "",
        "## Per condition (mean +/- std over whisks)",
        "",
        (
            f"Over {n_seeds} sessions (seeds "
            f"{', '.join(str(q) for q in results['meta'].get('seeds', []))}): each figure is "
            "the mean over the sessions of the session's mean (or std) over its whisks, "
            "with the range of the session means beside it. The simulated whisker, pole and "
            "whisk are deterministic, so the sessions differ only in the sensor noise."
            if n_seeds > 1
            else "One session."
        ),
        "",
        md_table(
            [
                "R (mm)",
                "S (Hz)",
                "peak deflection (V)",
                "over sessions",
                "contact duration (s)",
                "over sessions",
                "whisks",
            ],
            rows,
        ),
        "",
    ]
    if "features" in figures:
        out += [f"![figure 6.5: features]({figures['features']})", ""]
    if "trajectories" in figures:
        out += [
            "Whisk trajectories (housing angle, raw Hall x; contacts shaded):",
            "",
            f"![whisk trajectories]({figures['trajectories']})",
            "",
        ]
    crow = [
        [
            k,
            f"{fmt(v['radius_mm']['mean'])} / {fmt(v['radius_mm']['std'])}",
            f"{fmt(v['whisk_frequency_hz']['mean'])} / {fmt(v['whisk_frequency_hz']['std'])}",
            fmt(v["radius_mae_mm"]),
            fmt(v["whisk_frequency_mae_hz"]),
            fmt(v["joint_correct"]),
        ]
        for k, v in results["classifiers"].items()
    ]
    sp = results["meta"]["split"]
    out += [
        "## Chapter-4 classifiers",
        "",
        f"Trained on the {sp['train']} ({sp['n_train']}), tested on the {sp['test']} "
        f'({sp["n_test"]}); the thesis ran none on this small set ("{THESIS["classifiers"]}").',
        "",
        md_table(
            [
                "classifier",
                "radius error mean / std (mm)",
                "frequency error mean / std (Hz)",
                "radius MAE (mm)",
                "frequency MAE (Hz)",
                "joint correct",
            ],
            crow,
        ),
        "",
        "## Figure 3.9: rapid cessation of protraction",
        "",
    ]
    f39 = results["figure_3_9"]
    out.append(
        md_table(
            [
                "setting",
                "thesis",
                "contacts (left, 3 whisks)",
                "right",
                "max z",
                "z at the next whisk's first contact",
            ],
            [
                [
                    f"({k}) sigma_z = {v['sigma_z']:g}, tau_z = T_w x {v['tau_z_periods']:g}",
                    THESIS.get(f"figure_3_9_{k}", ""),
                    v["contacts_left"],
                    v["contacts_right"],
                    fmt(v["z_max"]),
                    fmt(v["z_at_next_whisk"], 3),
                ]
                for k, v in f39.items()
            ],
        )
    )
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
            "time. Minimal impingement (3.2.4): RCP keeps the deflection smaller. The "
            "contact signal's scale in eq. 3.2 was identified so that figure 3.9's two "
            "outcomes hold here (scripts/identify_rcp.py, docs/runs/identify_rcp.json): "
            "sigma_z 0.7, tau_z T_w/4 one contact per whisk; sigma_z 2, tau_z T_w/10 the "
            "biphasic whisk (the housing withdraws, the whisker leaves the pole and the "
            "protraction resumes within the whisk: two contacts). 'Contact runs' counts "
            "every run of contact force (bounces at impact merged within 20 ms); "
            "'figure 3.9 contacts' counts as the figure does, per whisk.",
            "",
            md_table(
                [
                    "setting",
                    "peak deflection (V)",
                    "max contact force (N)",
                    "contact runs per whisk",
                    "figure 3.9 contacts per whisk",
                    "contact time per whisk (s)",
                    "max z",
                ],
                [
                    [
                        f"sigma_z = {v['sigma_z']:g}, tau_z = T_w x {v['tau_z_periods']:g}",
                        fmt(v["peak_deflection_v"], 3),
                        fmt(v["max_contact_force_n"], 3),
                        fmt(v["contacts_per_whisk"]),
                        ", ".join(str(c) for c in v.get("figure_3_9_contacts", [])) or "-",
                        fmt(v["contact_time_per_whisk_s"], 3),
                        fmt(v["max_z"]),
                    ]
                    for v in cl["settings"]
                ],
            ),
            "",
        ]
        if "closed_loop" in figures:
            out += [f"![closed loop]({figures['closed_loop']})", ""]
    return "\n".join(out)
