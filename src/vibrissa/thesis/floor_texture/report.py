"""Report sections of the Roomba floor-texture experiment beside the thesis (6.2).

Every number the prose quotes is computed from the results; the thesis' values are
:data:`vibrissa.thesis.floor_texture.values.THESIS` (tables 6.1-6.3 and 6.2.2).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.evaluate.report_common import md_table
from vibrissa.thesis.floor_texture.values import THESIS

__all__ = ["CAPTIONS", "discussion", "markdown_floor_texture", "percent"]

#: Figure captions by key.
CAPTIONS = {
    "confusion": "Confusion matrices (rows true floor, % of its test windows): this run "
    "(top) and the thesis' tables 6.1-6.3 (bottom)",
    "templates": "Spectral templates, clockwise condition (cf. figure 6.3): mean DFT "
    "magnitude of each floor's training windows, x and y channels",
    "signals": "Example recordings, one per floor, clockwise (cf. figure 6.2); grey: "
    "packets dropped for low variance",
    "trajectories": "The whisker tip's path over the floor in one trial of each condition; "
    "grey: packets dropped (robot not yet moving), colour: kept",
}


def percent(x: Any) -> str:
    """A fraction as a whole percentage (``0.72`` -> ``72 %``); ``—`` if undefined."""
    return "—" if x is None else f"{100 * float(x):.0f} %"


def _row_percent(cm: Any) -> list[list[str]]:
    m = np.asarray(cm, dtype=float)
    n = m.sum(axis=1, keepdims=True)
    p = np.divide(m, n, out=np.zeros_like(m), where=n > 0) * 100
    return [[f"{v:.0f}" for v in row] for row in p]


def _confusion_section(
    results: Mapping[str, Any], condition: str, floors: list[str], table: str
) -> list[str]:
    ours = results["confusion"].get(condition)
    th = THESIS["confusion"].get(condition)
    out = [f"### {condition} ({table})", ""]
    if ours is None:
        return out + ["No test windows in this condition.", ""]
    header = ["true \\ predicted", *floors, "correct (ours)", "correct (thesis)"]
    rows = []
    mo = np.asarray(ours)
    mt = np.asarray(th) if th is not None and floors == THESIS["floors"] else None
    for i, f in enumerate(floors):
        n = mo[i].sum()
        ours_ok = mo[i, i] / n if n else None
        th_ok = mt[i, i] / mt[i].sum() if mt is not None else None
        rows.append([f, *(f"{int(v)}" for v in mo[i]), percent(ours_ok), percent(th_ok)])
    out += [
        md_table(header, rows),
        "",
        f"Mean correct: **{percent(results['mean_correct'].get(condition))}** "
        f"(thesis {percent(THESIS['mean_correct'].get(condition))}); "
        f"{int(mo.sum())} test windows (thesis {int(mt.sum()) if mt is not None else '—'}).",
        "",
    ]
    return out


def markdown_floor_texture(
    results: Mapping[str, Any],
    figures: Mapping[str, Path] | None,
    baseline: Mapping[str, Any] | None = None,
) -> str:
    """The Markdown report body of floor-texture results.

    The results are those of
    :func:`~vibrissa.thesis.floor_texture.evaluation.run_floor_texture`; ``baseline`` is
    not used: the thesis' numbers are the comparison.
    """
    meta = results["meta"]
    floors = list(meta["floors"])
    conds = list(meta["conditions"])
    tables = {"anticlockwise": "table 6.1", "clockwise": "table 6.2", "spot": "table 6.3"}
    out = [
        "Thesis 6.2: a SCRATCHbot whisker on a Roomba over four floors, turning clockwise, "
        "anticlockwise or running its 'spot' pattern; packets of 160 samples with variance "
        f"below {meta['quiet_variance_v2']:g} V^2 dropped, {meta['window_samples']}-sample "
        "windows, odd windows train and even windows test, spectral templates per "
        "condition.",
        "",
        "## Mean correct",
        "",
        md_table(
            ["condition", "spectral templates", "thesis", "naive Bayes (raw)", "nearest spectrum"],
            [
                [
                    c,
                    percent(results["mean_correct"].get(c)),
                    percent(THESIS["mean_correct"].get(c)),
                    percent(results["naive_bayes"]["mean_correct"].get(c)),
                    percent(results["spectral_nearest"]["mean_correct"].get(c)),
                ]
                for c in conds
            ],
        ),
        "",
    ]
    cross = results["cross_condition"]
    out += [
        "## Cross-condition",
        "",
        md_table(
            ["templates from", "classifying", "mean correct", "thesis"],
            [
                [
                    "clockwise",
                    "anticlockwise",
                    percent(cross.get("cw_on_ccw")),
                    percent(THESIS["cross_condition"]),
                ],
                [
                    "anticlockwise",
                    "clockwise",
                    percent(cross.get("ccw_on_cw")),
                    percent(THESIS["cross_condition"]),
                ],
            ],
        ),
        "",
        "## Confusion matrices (spectral templates)",
        "",
        "Counts of test windows, rows the true floor (the thesis' tables print the true "
        "floor in columns).",
        "",
    ]
    for c in conds:
        out += _confusion_section(results, c, floors, tables.get(c, "beyond the thesis"))
    out += [
        "## Windows",
        "",
        md_table(
            ["condition", *(f"{f} (train/test)" for f in floors), "packets kept"],
            [
                [
                    c,
                    *(
                        f"{results['windows'][c][f][0]}/{results['windows'][c][f][1]}"
                        for f in floors
                    ),
                    f"{sum(v[0] for v in results['packets'][c].values())} of "
                    f"{sum(v[1] for v in results['packets'][c].values())}",
                ]
                for c in conds
            ],
        ),
        "",
        "The thesis' tables hold 80 test windows per floor: 4 trials x 40 windows / 2, "
        "i.e. every packet of every trial (none fell below the threshold, or the counts "
        "were equalised; the text does not say).",
        "",
        "## Discussion",
        "",
        discussion(results),
        "",
    ]
    out += _model_section(meta)
    if figures:
        out += ["## Figures", ""]
        for k, p in figures.items():
            out += [f"![{CAPTIONS.get(k, k)}]({p.as_posix() if isinstance(p, Path) else p})", ""]
    return "\n".join(out) + "\n"


def discussion(results: Mapping[str, Any]) -> str:
    """How this run compares with the thesis, every number computed from ``results``."""
    mc = results["mean_correct"]
    conds = [c for c in results["meta"]["conditions"] if mc.get(c) is not None]
    lines = []
    if conds:
        best = max(conds, key=mc.__getitem__)
        worst = min(conds, key=mc.__getitem__)
        lines.append(
            f"- Spectral templates do best turning **{best}** ({percent(mc[best])}) "
            f"and worst in **{worst}** ({percent(mc[worst])}); the thesis: "
            "anticlockwise 72 %, clockwise 64 %, spot 56 %."
        )
    floors = results["meta"]["floors"]
    for c in conds:
        cm = np.asarray(results["confusion"][c], dtype=float)
        n = cm.sum(axis=1)
        ok = np.divide(np.diag(cm), n, out=np.zeros(len(n)), where=n > 0)
        lines.append(
            f"- {c}: hardest floor {floors[int(np.argmin(ok))]} "
            f"({percent(ok.min())} correct), easiest {floors[int(np.argmax(ok))]} "
            f"({percent(ok.max())})."
        )
    cross = results["cross_condition"]
    if cross.get("cw_on_ccw") is not None and cross.get("ccw_on_cw") is not None:
        lines.append(
            f"- Templates of one turning direction on the other: "
            f"{percent(cross['cw_on_ccw'])} (clockwise on anticlockwise) and "
            f"{percent(cross['ccw_on_cw'])} (back); the thesis: both about 52 %."
        )
    sat = results.get("saturated_trials") or {}
    hit = [(c, f, n) for c, per in sat.items() for f, n in per.items() if n]
    if hit:
        lines.append(
            "- Trials whose sensor reached a rail (the whisker caught in the floor "
            "and whipped free): " + ", ".join(f"{f} {c} {n}" for c, f, n in hit) + "."
        )
    nb = results["naive_bayes"]["mean_correct"]
    if any(nb.get(c) is not None for c in conds):
        lines.append(
            "- Stationary naive Bayes on raw values: "
            + ", ".join(f"{c} {percent(nb.get(c))}" for c in conds)
            + " (the thesis reports > 90 % hit rates under several conditions, "
            "Lepora et al. 2010b)."
        )
    return "\n".join(lines) if lines else "No results to compare."


def _model_section(meta: Mapping[str, Any]) -> list[str]:
    """The simulated floors and robot (from the dataset's attributes), if recorded."""
    specs = meta.get("floor_specs") or {}
    robot = meta.get("robot") or {}
    if not specs and not robot:
        return []
    out = ["## Model", ""]
    if robot:
        out += [
            f"The whisker's base sits {robot.get('mount_radius_mm')} mm from the turning "
            f"centre, the whisker pointing backward at {robot.get('tilt_deg')} deg to the "
            f"floor and pressed {robot.get('preload_mm')} mm into it; spinning at "
            f"{robot.get('spin_wheel_speed_mm_s')} mm/s per wheel (wheel base "
            f"{robot.get('wheel_base_mm')} mm); 'spot': an outward spiral at "
            f"{robot.get('spot_speed_mm_s')} mm/s. Anticlockwise the floor runs from the "
            "whisker's base to its tip (the whisker trails), clockwise from tip to base (the "
            "tip leads), and in both it also slides across the whisker's plane. The thesis "
            "gives no speeds or mounting; these are our choices (`vibrissa.robots.roomba`).",
            "",
        ]
    if specs:
        out += [
            md_table(
                [
                    "floor",
                    "kind",
                    "element (mm)",
                    "relief / MTD (mm)",
                    "roughness (um)",
                    "friction",
                    "contact stiffness (N/m)",
                ],
                [
                    [
                        f,
                        s.get("kind"),
                        s.get("element_mm"),
                        s.get("relief_mm"),
                        s.get("roughness_um"),
                        s.get("friction"),
                        s.get("stiffness_n_m"),
                    ]
                    for f, s in specs.items()
                ],
            ),
            "",
        ]
        out += [f"- **{f}**: {s.get('source', '')}" for f, s in specs.items()] + [""]
    return out
