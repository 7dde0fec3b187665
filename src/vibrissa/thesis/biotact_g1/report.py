"""The BIOTACT G1's report sections (thesis 6.4).

The claims of 6.4.4 tested, hit-rate tables and figures, whisk statistics and the
discussion; every number from the results.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vibrissa.evaluate.report_common import fmt, md_table
from vibrissa.thesis.biotact_g1.values import CLASSIFIER_TITLES, STRATEGIES, THESIS

__all__ = ["markdown_g1", "strategies_text"]


def _number(n: int) -> str:
    """``n`` in words up to twelve, as prose writes small counts."""
    words = (
        "zero",
        "one",
        "two",
        "three",
        "four",
        "five",
        "six",
        "seven",
        "eight",
        "nine",
        "ten",
        "eleven",
        "twelve",
    )
    return words[n] if 0 <= n < len(words) else str(n)


def strategies_text(names: list[str] | tuple[str, ...]) -> str:
    """The control strategies of a run in words, e.g. ``unmodulated, RCP7 (sigma_z = 0.7)``.

    sigma_z from :data:`~vibrissa.thesis.biotact_g1.values.STRATEGIES`.
    """
    return ", ".join(
        n if STRATEGIES[n] == 0 else f"{n.upper()} (sigma_z = {STRATEGIES[n]:g})" for n in names
    )


def _node(tree: Any, *path: Any) -> Any:
    """The spread tree's node at ``path`` (None where missing)."""
    for key in path:
        if isinstance(tree, dict):
            tree = tree.get(key)
        elif isinstance(tree, list) and isinstance(key, int) and 0 <= key < len(tree):
            tree = tree[key]
        else:
            return None
    return tree


def _pm(value: Any, leaf: Any, digits: int = 3) -> str:
    """``value +/- std`` over the sessions (``value`` alone with one session or no spread)."""
    if value is None:
        return "-"
    std = leaf.get("std") if isinstance(leaf, dict) else None
    return fmt(value, digits) if std is None else f"{fmt(value, digits)} +/- {fmt(std, digits)}"


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
        + (
            ""
            if steadier
            else " One possible reason: the feedback turns each contact's "
            "fluctuations (grains, the ringing left by the previous whisk) into changes of "
            "the housing's motion, which the unmodulated whisk does not have."
        ),
    ]


def markdown_g1(results: Mapping[str, Any], figures: Mapping[str, Path]) -> str:
    """The report's Markdown body for G1 results and the figures written.

    The results are those of :func:`~vibrissa.thesis.biotact_g1.evaluation.evaluate_g1`.
    """
    hit = results["hit_rate"]
    meta = results["meta"]
    proto = meta.get("protocol") or {}
    head = proto.get("head") or {}
    lengths = head.get("lengths_mm") or (80.0, 112.0, 158.0)  # the thesis' (3.4)
    chk = results["checks"]
    n_max = max(len(v) for s in hit.values() for c in s.values() for v in c.values())
    spread = results.get("spread") or {}

    def check_pm(key: str) -> str:
        return _pm(chk[key], _node(spread, "checks", key))

    def first_perfect(strategy: str, value: Any) -> str:
        vals = (_node(spread, "checks", "first_perfect_nb_joint", strategy) or {}).get("values")
        if not vals or len(vals) < 2:
            return f"{strategy}: {value if value is not None else 'never'}"
        per = ", ".join("never" if v is None else f"{v:g}" for v in vals)
        return f"{strategy}: {per} (per session)"

    out = [
        "The BIOTACT G1 (thesis 3.4, 6.4): a cone-shaped head with two bilaterally "
        f"symmetric rows of {_number(len(lengths))} whiskers "
        f"({', '.join(f'{v:g}' for v in lengths)} mm) whisking at "
        f"{proto.get('whisk_frequency_hz', 2):g} Hz into a vertical surface at "
        f"{', '.join(f'{d:g}' for d in results['parameters']['distance_mm']['values'])} "
        "mm from the head's front; textures "
        f"{', '.join(results['parameters']['texture']['values'])}; "
        f"{meta['whisks_per_class']} whisks per class; {len(meta['channels'])} channels "
        f"(x and y of {_number(2 * len(lengths))} whiskers) at "
        f"{meta['sample_rate_hz'] / 1000:g} kHz. "
        f"Strategies: {strategies_text(proto.get('strategies') or list(STRATEGIES))}, "
        f"tau_z = T_w x {proto.get('tau_z_periods', 0.25):g} (3.4.2).",
        "",
        "## Does RCP7 beat unmodulated whisking for naive Bayes after few whisks?",
        "",
        md_table(
            ["claim (thesis 6.4.4)", "this run"],
            [
                [
                    "RCP7 above unmodulated after 1-2 training whisks (9-class, naive Bayes)",
                    "n/a"
                    if chk.get("rcp7_beats_unmodulated_nb_joint_1_2_whisks") is None
                    else f"{'yes' if chk['rcp7_beats_unmodulated_nb_joint_1_2_whisks'] else 'no'}: "
                    f"mean {check_pm('rcp7_nb_joint_mean_1_2')} against "
                    f"{check_pm('unmodulated_nb_joint_mean_1_2')}",
                ],
                [
                    "RCP7 reaches 100 % after seven training whisks",
                    "n/a"
                    if chk.get("rcp7_nb_joint_at_7") is None
                    else f"{fmt(100 * chk['rcp7_nb_joint_at_7'], 1)} % after seven"
                    + (
                        ""
                        if _node(spread, "checks", "rcp7_nb_joint_at_7", "std") is None
                        else f" (std {fmt(100 * spread['checks']['rcp7_nb_joint_at_7']['std'], 1)})"
                    ),
                ],
                [
                    "first number of training whisks at 100 % (9-class, naive Bayes)",
                    "; ".join(
                        first_perfect(s, v) for s, v in chk["first_perfect_nb_joint"].items()
                    ),
                ],
            ],
        ),
        "",
    ]
    spread = results.get("spread") or {}
    n_seeds = int(meta.get("n_seeds", 1))
    if n_seeds > 1:
        out += [
            f"Every figure below is the mean over {n_seeds} sessions (seeds "
            f"{', '.join(str(q) for q in meta.get('seeds', []))}: sheets, tip placements, "
            "whisk amplitudes and sensor noise drawn anew) +/- the standard deviation "
            "over the sessions; RCP7 beats unmodulated naive Bayes after 1-2 whisks in "
            f"{fmt(100 * (chk.get('rcp7_beats_unmodulated_nb_joint_1_2_whisks_fraction') or 0), 0)}"
            " % of the sessions.",
            "",
        ]
    for c, title in CLASSIFIER_TITLES.items():
        out += [f"## Hit rate: {title}", ""]
        rows = []
        for task in ("joint", "texture", "distance"):
            for s, curves in hit.items():
                rows.append(
                    [task, s]
                    + [
                        _pm(r, _node(spread, "hit_rate", s, c, task, i))
                        for i, r in enumerate(curves[c][task])
                    ]
                    + [THESIS[(c, task)] if s == next(iter(hit)) else ""]
                )
        out += [
            md_table(
                ["task", "strategy"] + [str(n) for n in range(1, n_max + 1)] + ["thesis"], rows
            ),
            "",
        ]
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
            md_table(
                ["task", "strategy"] + [str(n) for n in range(1, n_max + 1)],
                [
                    [t, s] + [fmt(r, 3) if r is not None else "-" for r in c[t]]
                    for t in ("joint", "texture", "distance")
                    for s, c in rob.items()
                ],
            ),
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
        md_table(
            [
                "strategy",
                "contact time (s)",
                "peak deflection (V)",
                "within-class spread",
                "max z",
                "saturated whisks",
            ],
            [
                [
                    s,
                    _pm(v["contact_time_s"], _node(spread, "whisks", s, "contact_time_s")),
                    _pm(v["peak_deflection_v"], _node(spread, "whisks", s, "peak_deflection_v")),
                    _pm(v["peak_spread"], _node(spread, "whisks", s, "peak_spread")),
                    _pm(v["max_z"], _node(spread, "whisks", s, "max_z"), 2),
                    fmt(v["saturated_whisks"], 1),
                ]
                for s, v in ws.items()
            ],
        ),
        "",
    ]
    out += _discussion(ws, chk) + [""]
    for key, cap in (
        ("trajectories", "One whisk of each strategy"),
        ("distances", "Unmodulated whisks at each distance"),
    ):
        if key in figures:
            out += [
                f"{cap} (housing angle of the left row, Hall x of the 158 mm left "
                "whisker, gating z; contact of that whisker shaded):",
                "",
                f"![{cap}]({figures[key]})",
                "",
            ]
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
        "- RCP's contact signal (eq. 3.2): the largest low-passed x deflection of a "
        "row, as a fraction of the Hall half range, times "
        f"{fmt(proto.get('contact_signal_scale'), 2)} (the thesis gives neither its "
        "units nor its scale; chosen by scripts/identify_rcp.py, see "
        "docs/runs/identify_rcp.json).",
        "- Naive Bayes: 'Gaussian of width 5 intervals' read as a full width at half "
        "maximum of 5 bins (sigma 2.12 bins); bins span each channel's whole training "
        "range (6.4.2). Templates: the class mean of each channel over the training "
        "whisks, raw signals, sum of squared errors over the 12 channels (6.4.3).",
        "",
    ]
    return "\n".join(out)
