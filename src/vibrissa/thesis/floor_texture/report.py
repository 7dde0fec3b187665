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

__all__ = [
    "CAPTIONS",
    "discussion",
    "markdown_floor_texture",
    "percent",
    "percent_pm",
    "spread_of",
]

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


def percent_pm(x: Any, std: Any = None) -> str:
    """A mean fraction and its standard deviation (``72 ± 3 %``); as :func:`percent` without one."""
    if x is None or std is None:
        return percent(x)
    return f"{100 * float(x):.0f} ± {100 * float(std):.0f} %"


def spread_of(results: Mapping[str, Any], *path: str) -> Any:
    """The standard deviation over the seeds of the figure at ``path`` (``None`` if none)."""
    node: Any = results.get("spread") or {}
    for p in path:
        node = node.get(p) if isinstance(node, Mapping) else None
    return node.get("std") if isinstance(node, Mapping) else None


def _pm(results: Mapping[str, Any], *path: str) -> str:
    """``mean ± std %`` of the figure at ``path`` of the results."""
    node: Any = results
    for p in path:
        node = node.get(p) if isinstance(node, Mapping) else None
    return percent_pm(node, spread_of(results, *path))


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
    mo = np.asarray(ours, dtype=float)
    mt = np.asarray(th) if th is not None and floors == THESIS["floors"] else None
    per_floor = (results.get("per_floor_correct") or {}).get(condition) or {}
    for i, f in enumerate(floors):
        n = mo[i].sum()
        ours_ok = per_floor.get(f, mo[i, i] / n if n else None)
        th_ok = mt[i, i] / mt[i].sum() if mt is not None else None
        rows.append(
            [
                f,
                *(_count(v) for v in mo[i]),
                percent_pm(ours_ok, spread_of(results, "per_floor_correct", condition, f)),
                percent(th_ok),
            ]
        )
    out += [
        md_table(header, rows),
        "",
        f"Mean correct: **{_pm(results, 'mean_correct', condition)}** "
        f"(thesis {percent(THESIS['mean_correct'].get(condition))}); "
        f"{_count(mo.sum())} test windows (thesis {int(mt.sum()) if mt is not None else '—'}).",
        "",
    ]
    return out


def _count(v: float) -> str:
    """A count, or a mean count over seeds with one decimal."""
    return f"{int(v)}" if float(v).is_integer() else f"{v:.1f}"


def markdown_floor_texture(
    results: Mapping[str, Any],
    figures: Mapping[str, Path] | None,
    baseline: Mapping[str, Any] | None = None,
) -> str:
    """The Markdown report body of floor-texture results.

    The results are those of
    :func:`~vibrissa.thesis.floor_texture.evaluation.run_floor_texture`. ``baseline``, an
    earlier floor-texture run's results (``--baseline``), adds a *before* column beside
    this run's and the thesis' mean-correct and cross-condition figures.
    """
    meta = results["meta"]
    floors = list(meta["floors"])
    conds = list(meta["conditions"])
    tables = {"anticlockwise": "table 6.1", "clockwise": "table 6.2", "spot": "table 6.3"}
    n_seeds = int(meta.get("n_seeds", 1))
    seeds = meta.get("seeds") or []
    over = (
        f"Every figure is the mean ± standard deviation over {n_seeds} sessions (seeds "
        f"{', '.join(str(s) for s in seeds)}), each a whole session of its own floors, "
        "robot motions and sensor noise; the per-seed values are in `results.json` under "
        "`spread`."
        if n_seeds > 1
        else "One session (one seed): no spread."
    )
    before = (lambda *path: _pm(baseline, *path)) if baseline is not None else None
    label = str((baseline or {}).get("meta", {}).get("label", "an earlier run"))
    out = [
        "Thesis 6.2: a SCRATCHbot whisker on a Roomba over four floors, turning clockwise, "
        "anticlockwise or running its 'spot' pattern; packets of 160 samples with variance "
        f"below {meta['quiet_variance_v2']:g} V^2 dropped, {meta['window_samples']}-sample "
        "windows, odd windows train and even windows test, spectral templates per "
        "condition.",
        "",
        over,
        "",
        *([f"*Before* is {label} (`--baseline`).", ""] if before is not None else []),
        "## Mean correct",
        "",
        md_table(
            [
                "condition",
                "spectral templates",
                *(["before"] if before is not None else []),
                "thesis",
                "naive Bayes (raw)",
                "nearest spectrum",
            ],
            [
                [
                    c,
                    _pm(results, "mean_correct", c),
                    *([before("mean_correct", c)] if before is not None else []),
                    percent(THESIS["mean_correct"].get(c)),
                    _pm(results, "naive_bayes", "mean_correct", c),
                    _pm(results, "spectral_nearest", "mean_correct", c),
                ]
                for c in conds
            ],
        ),
        "",
    ]
    cross_before = ["before"] if before is not None else []
    out += [
        "## Cross-condition",
        "",
        md_table(
            ["templates from", "classifying", "mean correct", *cross_before, "thesis"],
            [
                [
                    "clockwise",
                    "anticlockwise",
                    _pm(results, "cross_condition", "cw_on_ccw"),
                    *([before("cross_condition", "cw_on_ccw")] if before is not None else []),
                    percent(THESIS["cross_condition"]),
                ],
                [
                    "anticlockwise",
                    "clockwise",
                    _pm(results, "cross_condition", "ccw_on_cw"),
                    *([before("cross_condition", "ccw_on_cw")] if before is not None else []),
                    percent(THESIS["cross_condition"]),
                ],
            ],
        ),
        "",
        *_cross_per_floor(results, floors),
        *_levels_section(results, floors),
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
                        f"{_count(results['windows'][c][f][0])}/"
                        f"{_count(results['windows'][c][f][1])}"
                        for f in floors
                    ),
                    f"{_count(sum(v[0] for v in results['packets'][c].values()))} of "
                    f"{_count(sum(v[1] for v in results['packets'][c].values()))}",
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


def _cross_per_floor(results: Mapping[str, Any], floors: list[str]) -> list[str]:
    """Per floor, the fraction of the other direction's test windows each template set gets."""
    cross = results["cross_condition"]
    per = {k: cross.get(f"{k}_per_floor") for k in ("cw_on_ccw", "ccw_on_cw")}
    if not any(per.values()):
        return []
    rows = []
    for f in floors:
        rows.append(
            [
                f,
                *(
                    percent_pm(
                        (per[k] or {}).get(f),
                        spread_of(results, "cross_condition", f"{k}_per_floor", f),
                    )
                    for k in ("cw_on_ccw", "ccw_on_cw")
                ),
                *(_pm(results, "per_floor_correct", c, f) for c in ("anticlockwise", "clockwise")),
            ]
        )
    return [
        "Per floor: the cross-condition score beside the same direction's own templates.",
        "",
        md_table(
            [
                "floor",
                "clockwise templates on anticlockwise",
                "anticlockwise templates on clockwise",
                "anticlockwise own",
                "clockwise own",
            ],
            rows,
        ),
        "",
    ]


def _levels_section(results: Mapping[str, Any], floors: list[str]) -> list[str]:
    """Catches of the tip and loudness of the windows per direction and floor."""
    levels = results.get("levels") or {}
    if not levels:
        return []
    rows = []
    for c, per in levels.items():
        for f in floors:
            e = per.get(f) or {}
            rms = e.get("rms_v") or [None, None]
            rows.append(
                [
                    c,
                    f,
                    "—" if e.get("catches") is None else f"{e['catches']:.2f}",
                    percent(e.get("catch_fraction")),
                    percent(e.get("rail_fraction")),
                    "—" if e.get("contact_force_n") is None else f"{e['contact_force_n']:.3f}",
                    *("—" if v is None else f"{1e3 * v:.0f}" for v in rms),
                    "—" if e.get("spectrum_norm") is None else f"{e['spectrum_norm']:.0f}",
                ]
            )
    return [
        "### Catches and signal levels",
        "",
        "Per direction and floor (means over trials and seeds): catches of the tip per "
        "trial (stuck on the sliding floor for at least 50 ms) and the share of the "
        "recording caught, the share of samples at a sensor rail, the median contact force "
        "while sliding, the RMS about each window's mean (x, y) and the norm of the windows' "
        "DC-less magnitude spectrum, which the templates' squared error weighs.",
        "",
        md_table(
            [
                "direction",
                "floor",
                "catches / trial",
                "time caught",
                "at a rail",
                "contact force (N)",
                "RMS x (mV)",
                "RMS y (mV)",
                "spectrum norm",
            ],
            rows,
        ),
        "",
        *_loudness_line(levels, floors),
    ]


def _loudness_line(levels: Mapping[str, Any], floors: list[str]) -> list[str]:
    """How much louder the clockwise windows are than the anticlockwise ones, per floor."""
    cw, ccw = levels.get("clockwise") or {}, levels.get("anticlockwise") or {}
    ratios = {}
    for f in floors:
        a = (cw.get(f) or {}).get("spectrum_norm")
        b = (ccw.get(f) or {}).get("spectrum_norm")
        if a and b:
            ratios[f] = a / b
    if not ratios:
        return []
    louder = [f for f, r in ratios.items() if r > 1.0]
    return [
        "Spectrum norm clockwise / anticlockwise: "
        + ", ".join(f"{f} {r:.1f}x" for f, r in ratios.items())
        + f"; clockwise is the louder direction on {len(louder)} of {len(ratios)} floors. "
        "With a squared error, a window much quieter than its own floor's template is "
        "nearer the template of a quieter floor.",
        "",
    ]


def discussion(results: Mapping[str, Any]) -> str:
    """How this run compares with the thesis, every number computed from ``results``."""
    mc = results["mean_correct"]
    conds = [c for c in results["meta"]["conditions"] if mc.get(c) is not None]
    lines = []
    if conds:
        best = max(conds, key=mc.__getitem__)
        worst = min(conds, key=mc.__getitem__)
        lines.append(
            f"- Spectral templates do best turning **{best}** "
            f"({_pm(results, 'mean_correct', best)}) and worst in **{worst}** "
            f"({_pm(results, 'mean_correct', worst)}); the thesis: "
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
            f"{_pm(results, 'cross_condition', 'cw_on_ccw')} (clockwise on anticlockwise) "
            f"and {_pm(results, 'cross_condition', 'ccw_on_cw')} (back); the thesis: both "
            "about 52 %."
        )
    sat = results.get("saturated_trials") or {}
    hit = [(c, f, n) for c, per in sat.items() for f, n in per.items() if n]
    if hit:
        n_seeds = int(results["meta"].get("n_seeds", 1))
        lines.append(
            "- Trials whose sensor reached a rail (the whisker caught in the floor "
            "and whipped free)"
            + (f", mean per session of {n_seeds}" if n_seeds > 1 else "")
            + ": "
            + ", ".join(f"{f} {c} {_count(n)}" for c, f, n in hit)
            + "."
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
