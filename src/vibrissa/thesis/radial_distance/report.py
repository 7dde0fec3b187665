"""Chapter-4 report sections, CSV tables and figures beside the thesis' values.

:data:`THESIS_CHAPTER4` holds the numbers of the thesis' tables 4.1-4.7 (and the
static-beam figures quoted in the text of 4.4.1), transcribed from the seed
text. :func:`write_outputs` writes ``results.csv``, ``radius_error_by_speed.csv``
and the figures; :func:`markdown_report` is the report body that sets each of
our tables beside the thesis' table, and its discussion
(:func:`discussion`) computes every number it quotes from the results.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa._atomic import atomic_write_text
from vibrissa.evaluate.report_common import fmt, fmt_seconds, md_table
from vibrissa.thesis.radial_distance.evaluation import ORACLE_ANGLE_LABEL, fraction_key
from vibrissa.thesis.radial_distance.values import (
    TABLE_FRACTIONS,
    THESIS_CHAPTER4,
    THESIS_COLUMNS,
)

__all__ = [
    "CSV_COLUMNS",
    "THESIS_CHAPTER4",
    "THESIS_COLUMNS",
    "discussion",
    "markdown_report",
    "oracle_angle_gap",
    "results_csv",
    "write_csv",
    "write_outputs",
]

#: Columns of :func:`results_csv`.
CSV_COLUMNS = (
    "fraction",
    "seed",
    "classifier",
    "parameter",
    "mean",
    "std",
    "sem",
    "mean_abs",
    "rmse",
    "exact_hit",
    "kappa",
    "kappa_linear",
    "kappa_quadratic",
    "n",
    "n_train",
    "fit_seconds",
    "classify_seconds",
)


# ----------------------------------------------------------------------------- CSV
def _rows(frac: str, seed: Any, name: str, entry: Mapping[str, Any]) -> list[dict[str, Any]]:
    rows = []
    for par in ("radius_mm", "speed_mm_s", "joint"):
        e = entry.get(par)
        if e is None:
            continue
        row = {
            "fraction": frac,
            "seed": seed,
            "classifier": name,
            "parameter": par,
            "n_train": entry.get("n_train"),
            "fit_seconds": entry.get("fit_seconds"),
            "classify_seconds": entry.get("classify_seconds"),
        }
        for k in CSV_COLUMNS:
            if k not in row:
                row[k] = e.get(k)
        rows.append(row)
    return rows


def results_csv(results: Mapping[str, Any], per_seed: bool = True) -> str:
    """The results as one long CSV table.

    One row per (training fraction, seed, classifier, parameter); ``fraction`` is
    ``"1.0"`` and ``seed`` empty for the full training set; seed ``"mean"`` rows
    hold the averages over seeds; parameter ``joint`` rows have only
    ``exact_hit`` and ``kappa``. Empty cells are undefined values.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    per_seed : bool, default=True
        Include one row per seed as well as the means.

    Returns
    -------
    str
    """
    rows: list[dict[str, Any]] = []
    for name, entry in results.get("classifiers", {}).items():
        rows += _rows("1.0", "", name, entry)
    for frac, per in results.get("training_fractions", {}).items():
        for name, entry in per.items():
            if entry is None:  # skipped: the subset was too small to train on
                continue
            rows += _rows(frac, "mean", name, entry)
            if per_seed:
                for run in entry.get("per_seed", []):
                    seed = run.get("seed")
                    seed = "/".join(str(s) for s in seed) if isinstance(seed, list) else seed
                    rows += _rows(frac, seed, name, run)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=CSV_COLUMNS, lineterminator="\n")
    w.writeheader()
    for row in rows:
        w.writerow({k: ("" if row.get(k) is None else row[k]) for k in CSV_COLUMNS})
    return buf.getvalue()


def _by_speed_csv(results: Mapping[str, Any]) -> str:
    buf = io.StringIO()
    cols = ("classifier", "speed_mm_s", "mean", "std", "sem", "exact_hit", "n")
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for name, entry in results.get("classifiers", {}).items():
        for row in entry.get("radius_error_by_speed", []):
            w.writerow(
                {
                    "classifier": name,
                    **{k: ("" if row.get(k) is None else row[k]) for k in cols[1:]},
                }
            )
    return buf.getvalue()


def write_csv(results: Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """Write :func:`results_csv` to ``path`` atomically and return the path."""
    return atomic_write_text(path, results_csv(results))


# ----------------------------------------------------------------------------- Markdown
def _ours(results: Mapping[str, Any], name: str, frac: str) -> dict[str, Any] | None:
    if frac == "1.0" and name in results.get("classifiers", {}):
        return results["classifiers"][name]
    return (results.get("training_fractions", {}).get(frac) or {}).get(name)


def _get(entry: Mapping[str, Any] | None, par: str, stat: str) -> Any:
    if entry is None or entry.get(par) is None:
        return None
    return entry[par].get(stat)


def _fraction_table(results: Mapping[str, Any], name: str, table: str | None) -> str:
    fr = {fraction_key(float(f)) for f in results.get("training_fractions", {})}
    fr.add("1.0")
    if table is not None:
        fr |= set(TABLE_FRACTIONS)
    fracs = sorted(fr, key=float)
    header = ["parameter", "statistic", "source", *[f"{100 * float(f):g} %" for f in fracs]]
    thesis = THESIS_CHAPTER4.get(table) if table else None
    rows = []
    for par, plabel in (("speed_mm_s", "speed (mm/s)"), ("radius_mm", "radius (mm)")):
        if thesis is None and all(
            _get(_ours(results, name, f), par, "mean") is None for f in fracs
        ):
            continue  # e.g. the speed of a radius-only classifier
        for stat in ("mean", "std"):
            rows.append(
                [
                    plabel,
                    stat,
                    "ours",
                    *[fmt(_get(_ours(results, name, f), par, stat)) for f in fracs],
                ]
            )
            if thesis is not None and table is not None:
                rows.append(
                    [
                        plabel,
                        stat,
                        f"thesis {table[6:].replace('_', '.')}",
                        *[fmt(thesis[par][stat].get(f)) for f in fracs],
                    ]
                )
        for stat in ("exact_hit", "kappa"):
            rows.append(
                [
                    plabel,
                    stat,
                    "ours",
                    *[fmt(_get(_ours(results, name, f), par, stat)) for f in fracs],
                ]
            )
    return md_table(header, rows)


def _static_beam_section(results: Mapping[str, Any]) -> list[str]:
    out: list[str] = []
    cl = results.get("classifiers", {})
    t41 = THESIS_CHAPTER4["table_4_1"]
    sbt = THESIS_CHAPTER4["static_beam_text"]
    keys = [("measured", "static_beam_measured"), ("fitted", "static_beam_fitted")]
    if not any(n in cl for _, n in keys):
        return out
    out += ["## Table 4.1: static beam parameters", ""]
    rows = []
    for label, name in keys:
        fp = cl.get(name, {}).get("fitted_parameters", {}) if name in cl else {}
        th = t41[label]
        rows.append(
            [
                label,
                "thesis 4.1",
                fmt(th["youngs_modulus_gpa"], 1),
                fmt(th["base_radius_mm"], 1),
                fmt(th["length_mm"], 0),
                f"S_f = {th['scale_factor']:g}",
            ]
        )
        if name in cl:
            rows.append(
                [
                    label,
                    "ours",
                    fmt(fp.get("youngs_modulus_gpa"), 2),
                    fmt(fp.get("base_radius_mm"), 2),
                    fmt(fp.get("length_mm"), 1),
                    f"x {fmt(fp.get('moment_scale'), 3)}",
                ]
            )
    out += [
        md_table(
            ["parameters", "source", "E (GPa)", "r_base (mm)", "L (mm)", "moment scale"], rows
        ),
        "",
        "Our moment scale multiplies the modelled base moment (1 = measured sensor "
        "calibration); the thesis' S_f converts volts to moment, so only its ratio "
        "between the fitted and measured rows "
        f"({fmt(t41['fitted']['scale_factor'] / t41['measured']['scale_factor'])}) "
        "compares.",
        "",
    ]
    out += ["## Static beam radial-distance error (text of 4.4.1)", ""]
    rows = []
    for label, name in keys:
        if name not in cl:
            continue
        e = cl[name]
        by = [r for r in e.get("radius_error_by_speed", []) if r.get("mean") is not None]
        med = by[len(by) // 2] if by else None
        ext = max(by, key=lambda r: abs(r["mean"])) if by else None
        th = sbt[label]
        rows.append(
            [
                label,
                "ours",
                fmt(_get(e, "radius_mm", "mean")),
                fmt(_get(e, "radius_mm", "std")),
                fmt(med and med["mean"]),
                fmt(med and med["std"]),
                fmt(ext and ext["mean"]),
                fmt(ext and ext["std"]),
                fmt(_get(e, "radius_mm", "exact_hit")),
                fmt(_get(e, "radius_mm", "kappa")),
            ]
        )
        rows.append(
            [
                label,
                "thesis 4.4.1",
                fmt(th["mean"], 3),
                fmt(th["std"]),
                fmt(th["median_speed"]["mean"], 3),
                fmt(th["median_speed"]["std"]),
                fmt(th["extreme_speed"]["mean"]),
                fmt(th["extreme_speed"]["std"]),
                "—",
                "—",
            ]
        )
    out += [
        md_table(
            [
                "parameters",
                "source",
                "mean (mm)",
                "std (mm)",
                "median-speed mean",
                "median-speed std",
                "worst-speed mean",
                "worst-speed std",
                "exact hit",
                "kappa",
            ],
            rows,
        ),
        "",
        "Ours: worst speed = the speed with the largest |mean error|; the thesis "
        "quotes the most extreme speed.",
        "",
    ]
    return out


def markdown_report(
    results: Mapping[str, Any],
    *,
    figures: Mapping[str, str | os.PathLike[str]] | None = None,
    baseline: Mapping[str, Any] | None = None,
) -> str:
    """Markdown report body putting our tables 4.1-4.7 beside the thesis' values.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4` (or the results
        envelope of a chapter-4 run).
    figures : mapping of str to path, optional
        Figure key (as returned by :func:`write_outputs`) to a path *relative to the
        report*; embedded as images.
    baseline : dict, optional
        An earlier run's results (:func:`vibrissa.evaluate.baseline.load_baseline`);
        table 4.7 then shows its values as "before" beside ours.

    Returns
    -------
    str
        The report body (GitHub-flavoured Markdown), without the common header.
    """
    figures = {k: Path(v).as_posix() for k, v in (figures or {}).items()}
    cl = results.get("classifiers", {})
    meta = results.get("meta", {})
    split = meta.get("split", {})
    out = [
        "Thesis: M. H. Evans, *Tactile Discrimination with Whiskers* (Sheffield 2011), "
        "chapter 4. Errors are signed (predicted − true); *std* is the standard deviation "
        'of the per-trial errors (the thesis\' "Std Err"); reduced training sets average '
        f"over {meta.get('n_seeds', '?')} random subsets.",
        "",
        f"- trials: {meta.get('n_trials', '?')}, sets {meta.get('sets', '?')}; training "
        f"set(s) {split.get('train_set', '?')} ({split.get('n_train', '?')} trials), test set "
        f"{split.get('test_set', '?')} ({split.get('n_test', '?')} trials), seed "
        f"{meta.get('seed', '?')}",
        f"- grid: {len(meta.get('radii_mm', []))} radial distances x "
        f"{len(meta.get('speeds_mm_s', []))} speeds; sample rate "
        f"{meta.get('sample_rate_hz', '?')} Hz",
        "",
    ]
    if "dataset/traces" in figures or "dataset/contours" in figures:
        out += ["## The data (figures 3.7 and 4.1)", ""]
        for key, cap in (
            ("dataset/traces", "Typical deflections (cf. figure 3.7)"),
            ("dataset/contours", "Peak deflection and duration (cf. figure 4.1)"),
        ):
            if key in figures:
                out += [f"![{cap}]({figures[key]})", ""]

    out += _static_beam_section(results)
    for name, entry in cl.items():
        if not entry.get("radius_only"):
            continue
        if f"errors/{name}" in figures:
            out += [f"![{name}: errors (cf. figures 4.2/4.3)]({figures[f'errors/{name}']})", ""]
    radius_only = [n for n, e in cl.items() if e.get("radius_only")]
    if radius_only and results.get("training_fractions"):
        out += [
            "## Radius-only classifiers vs training-set size (not tabled in the thesis: "
            '"the size of the training set is irrelevant", 4.3)',
            "",
        ]
        for name in radius_only:
            out += [f"**{name}**", "", _fraction_table(results, name, None), ""]
            key = f"training_size/{name}"
            if key in figures:
                out += [f"![{name}: mean error vs training-set size]({figures[key]})", ""]

    # tables 4.2-4.5 (and our extra classifiers)
    for name, entry in cl.items():
        if entry.get("radius_only"):
            continue
        _, table = THESIS_COLUMNS.get(name, (None, None))
        head = f"## Table {table[6:].replace('_', '.')}: {name}" if table else f"## {name}"
        out += [head + " vs training-set size", ""]
        if not table:
            out += ["No thesis counterpart for this variant.", ""]
        out += [_fraction_table(results, name, table), ""]
        for key, cap in (
            (f"training_size/{name}", "mean error vs training-set size"),
            (f"errors/{name}", "error histograms and scatter"),
        ):
            if key in figures:
                out += [f"![{name}: {cap}]({figures[key]})", ""]

    # table 4.6
    out += ["## Table 4.6: computing time (full training set, whole test set)", ""]
    rows = []
    for name, entry in cl.items():
        col, _ = THESIS_COLUMNS.get(name, (None, None))
        th = THESIS_CHAPTER4["table_4_6"].get(col) if col else None
        rows.append(
            [
                name,
                fmt_seconds(entry.get("fit_seconds")),
                fmt_seconds(entry.get("classify_seconds")),
                fmt_seconds(th),
            ]
        )
    out += [
        md_table(
            ["classifier", "fit (ours)", "classify (ours)", "train + classify 2626 (thesis 4.6)"],
            rows,
        ),
        "",
        "Thesis times: MATLAB on a 2.5 GHz Core 2 Duo; ours: this machine, wall time.",
        "",
    ]

    # table 4.7
    out += ["## Table 4.7: performance under ideal conditions (full training set)", ""]
    rows = []
    for name, entry in cl.items():
        col, _ = THESIS_COLUMNS.get(name, (None, None))
        th = THESIS_CHAPTER4["table_4_7"].get(col) if col else None
        rows.append(
            [
                name,
                "ours",
                fmt(_get(entry, "speed_mm_s", "mean")),
                fmt(_get(entry, "speed_mm_s", "std")),
                fmt(_get(entry, "radius_mm", "mean")),
                fmt(_get(entry, "radius_mm", "std")),
            ]
        )
        before = (baseline or {}).get("classifiers", {}).get(name)
        if before is not None:
            rows.append(
                [
                    name,
                    "before",
                    fmt(_get(before, "speed_mm_s", "mean")),
                    fmt(_get(before, "speed_mm_s", "std")),
                    fmt(_get(before, "radius_mm", "mean")),
                    fmt(_get(before, "radius_mm", "std")),
                ]
            )
        if th is not None:
            rows.append(
                [
                    name,
                    "thesis 4.7",
                    fmt(_get(th, "speed_mm_s", "mean")),
                    fmt(_get(th, "speed_mm_s", "std")),
                    fmt(_get(th, "radius_mm", "mean")),
                    fmt(_get(th, "radius_mm", "std")),
                ]
            )
    oracle = (results.get("oracle_angle") or {}).get("classifiers", {})
    for name, entry in oracle.items():
        rows.append(
            [
                f"{name}, {(results.get('oracle_angle') or {}).get('label', ORACLE_ANGLE_LABEL)}",
                "ours (extra row)",
                fmt(None),
                fmt(None),
                fmt(_get(entry, "radius_mm", "mean")),
                fmt(_get(entry, "radius_mm", "std")),
            ]
        )
    if baseline is not None:
        out += [f"*before*: {baseline.get('meta', {}).get('label', 'an earlier run')}.", ""]
    out += [
        md_table(
            ["classifier", "source", "speed mean", "speed std", "radius mean", "radius std"], rows
        ),
        "",
    ]
    if "comparison" in figures:
        out += [f"![Mean error per classifier (cf. figure 4.12)]({figures['comparison']})", ""]
    own = {n: e.get("train_sets") for n, e in cl.items() if e.get("train_sets") is not None}
    if own:
        out += [
            "Training sets per classifier (the split of the thesis author's code; "
            "see docs/methods.md): " + "; ".join(f"{n}: {v}" for n, v in own.items()) + ".",
            "",
        ]
    out += _oracle_angle_section(results, figures)
    other = results.get("other_split")
    if other:
        out += [f"### The other split: {other.get('description', '')}", ""]
        rows = []
        for name, entry in other.get("classifiers", {}).items():
            main = cl.get(name, {})
            rows.append(
                [
                    name,
                    fmt(_get(entry, "speed_mm_s", "std")),
                    fmt(_get(main, "speed_mm_s", "std")),
                    fmt(_get(entry, "radius_mm", "std")),
                    fmt(_get(main, "radius_mm", "std")),
                ]
            )
        out += [
            md_table(
                [
                    "classifier",
                    "speed std (one set)",
                    "speed std (main)",
                    "radius std (one set)",
                    "radius std (main)",
                ],
                rows,
            ),
            "",
        ]

    # kappa and exact hits (not in the thesis)
    out += ["## Exact hits and Cohen's kappa (full training set; not reported in the thesis)", ""]
    rows = []
    for name, entry in cl.items():
        rows.append(
            [
                name,
                fmt(_get(entry, "radius_mm", "exact_hit")),
                fmt(_get(entry, "radius_mm", "kappa")),
                fmt(_get(entry, "radius_mm", "kappa_linear")),
                fmt(_get(entry, "speed_mm_s", "exact_hit")),
                fmt(_get(entry, "speed_mm_s", "kappa")),
                fmt(_get(entry, "speed_mm_s", "kappa_linear")),
                fmt(_get(entry, "joint", "exact_hit")),
                fmt(_get(entry, "joint", "kappa")),
            ]
        )
    out += [
        md_table(
            [
                "classifier",
                "radius hit",
                "radius κ",
                "radius κ (linear)",
                "speed hit",
                "speed κ",
                "speed κ (linear)",
                "joint hit",
                "joint κ",
            ],
            rows,
        ),
        "",
    ]

    out += ["## Discussion", "", discussion(results), ""]
    return "\n".join(out)


def oracle_angle_gap(results: Mapping[str, Any], name: str) -> dict[str, Any] | None:
    """How much of a static beam's gap to the thesis' spread the author's angle explains.

    Parameters
    ----------
    results : dict
        Results of a chapter-4 run with the ``oracle_angle`` section.
    name : {"static_beam_measured", "static_beam_fitted"}
        The static-beam row; compared with the thesis' std of the same parameters
        (8.8 mm measured, table 4.7 and 4.4.1; 10.4 mm fitted, 4.4.1).

    Returns
    -------
    dict or None
        ``ours_std_mm`` (one assumed speed), ``oracle_std_mm`` (author's angle),
        ``thesis_std_mm``, ``gap_mm`` (ours - thesis) and ``explained`` (the share
        of the gap the angle closes, ``(ours - oracle) / gap``; ``None`` when ours is
        not above the thesis'); ``None`` when the run lacks either row.
    """
    label = {"static_beam_measured": "measured", "static_beam_fitted": "fitted"}.get(name)
    ours = _get((results.get("classifiers") or {}).get(name), "radius_mm", "std")
    entry = ((results.get("oracle_angle") or {}).get("classifiers") or {}).get(name)
    oracle = _get(entry, "radius_mm", "std")
    if label is None or ours is None or oracle is None:
        return None
    thesis = float(THESIS_CHAPTER4["static_beam_text"][label]["std"])
    gap = float(ours) - thesis
    return {
        "ours_std_mm": float(ours),
        "oracle_std_mm": float(oracle),
        "thesis_std_mm": thesis,
        "gap_mm": gap,
        "explained": (float(ours) - float(oracle)) / gap if gap > 0 else None,
    }


def _gap_sentence(results: Mapping[str, Any], name: str) -> str | None:
    g = oracle_angle_gap(results, name)
    if g is None:
        return None
    head = (
        f"**{name} with the author's angle**: radius std {fmt(g['oracle_std_mm'])} mm "
        f"against {fmt(g['ours_std_mm'])} mm with one assumed speed and "
        f"{fmt(g['thesis_std_mm'], 1)} mm in the thesis"
    )
    if g["explained"] is None:
        return head + "; ours is not above the thesis', so there is no gap to explain."
    share = 100.0 * g["explained"]
    if share >= 100.0:
        verdict = f"the angle closes the whole gap of {fmt(g['gap_mm'])} mm ({fmt(share, 0)} %)"
    elif share <= 0.0:
        verdict = f"the angle closes none of the gap of {fmt(g['gap_mm'])} mm ({fmt(share, 0)} %)"
    else:
        verdict = (
            f"the angle explains {fmt(share, 0)} % of the gap of {fmt(g['gap_mm'])} mm, "
            f"{fmt(g['oracle_std_mm'] - g['thesis_std_mm'])} mm remain"
        )
    return f"{head}: {verdict}."


def _oracle_angle_section(
    results: Mapping[str, Any], figures: Mapping[str, str | os.PathLike[str]]
) -> list[str]:
    """The static beam with the thesis author's oracle angle (issue 30): table and sentence."""
    section = results.get("oracle_angle") or {}
    oracle = section.get("classifiers") or {}
    if not oracle:
        return []
    cl = results.get("classifiers", {})
    other = ((results.get("other_split") or {}).get("oracle_angle")) or {}
    other_cl = (results.get("other_split") or {}).get("classifiers", {})
    out = [
        f"### Extra row: static beam, {section.get('label', ORACLE_ANGLE_LABEL)}",
        "",
        "The thesis author's code (ProtractionAngle.m) computes the protraction angle "
        "theta = speed x 0.3 s / radial distance from each test trial's TRUE speed and "
        "radius, which a classifier of unknown contacts cannot know. These rows redo the "
        "static beam that way (theta of the training trials too, so the fitted row "
        "searches its parameters under that angle), on the same splits; every other row "
        "is unchanged. Statistics as in table 4.7 (signed error), and of the absolute error.",
        "",
    ]
    rows = []
    for name, entry in oracle.items():
        for split, fixed, orc in (
            ("main", cl.get(name), entry),
            ("one set", other_cl.get(name), other.get(name)),
        ):
            if orc is None:
                continue
            rows.append(
                [
                    name,
                    split,
                    fmt(_get(fixed, "radius_mm", "std")),
                    fmt(_get(orc, "radius_mm", "mean")),
                    fmt(_get(orc, "radius_mm", "std")),
                    fmt(_get(orc, "abs_error_mm", "mean")),
                    fmt(_get(orc, "abs_error_mm", "std")),
                ]
            )
    out += [
        md_table(
            [
                "static beam",
                "split",
                "radius std, one assumed speed (mm)",
                "oracle: radius mean (mm)",
                "oracle: radius std (mm)",
                "oracle: mean absolute error (mm)",
                "oracle: SD of the absolute error (mm)",
            ],
            rows,
        ),
        "",
    ]
    for sentence in (_gap_sentence(results, n) for n in oracle):
        if sentence:
            out += [sentence, ""]
    fp = {k: (e.get("fitted_parameters") or {}) for k, e in oracle.items()}
    if fp.get("static_beam_fitted"):
        p = fp["static_beam_fitted"]
        out += [
            "Parameters the fitted row finds under the oracle angle: E "
            f"{fmt(p.get('youngs_modulus_gpa'), 2)} GPa, r_base {fmt(p.get('base_radius_mm'), 2)}"
            f" mm, L {fmt(p.get('length_mm'), 1)} mm, moment scale "
            f"x {fmt(p.get('moment_scale'), 3)}.",
            "",
        ]
    if "oracle_angle" in figures:
        out += [
            f"![Static beam error per speed, with the author's angle]({figures['oracle_angle']})",
            "",
        ]
    return out


def _speed_std(results: Mapping[str, Any]) -> tuple[float, float] | None:
    """Mean and std of the error of always answering the slowest speed, on this test set."""
    truth = (results.get("predictions") or {}).get("speed_mm_s_true")
    speeds = (results.get("meta") or {}).get("speeds_mm_s")
    if not truth or not speeds:
        return None
    err = min(speeds) - np.asarray(truth, dtype=float)
    return float(err.mean()), float(err.std(ddof=1)) if err.size > 1 else 0.0


def discussion(results: Mapping[str, Any]) -> str:
    """How this run differs from the thesis, with every number computed from ``results``.

    Settings and their sources are in ``docs/methods.md``; this text quotes only the
    run's own numbers and the thesis' tables.
    """
    cl = results.get("classifiers", {})
    t47 = THESIS_CHAPTER4["table_4_7"]
    lines: list[str] = []
    slow = _speed_std(results)
    th_f = t47.get("frequency") or {}
    if slow is not None and "frequency" in cl and th_f.get("speed_mm_s"):
        ours = cl["frequency"].get("speed_mm_s") or {}
        lines.append(
            "- **The thesis' frequency speed row is what always answering the slowest "
            "speed gives.** On this run's test set that answer has a signed speed error of "
            f"{fmt(slow[0])} mm/s with std {fmt(slow[1])} mm/s; table 4.7 gives "
            f"{fmt(th_f['speed_mm_s']['mean'])} / {fmt(th_f['speed_mm_s']['std'])}. In the "
            "author's code the frequency method returns a radius index that is read as a "
            "template index (docs/methods.md); our frequency classifier estimates speed "
            f"itself: {fmt(ours.get('mean'))} / {fmt(ours.get('std'))} mm/s."
        )

    def rank(par: str) -> list[tuple[str, float]]:
        vals = [
            (n, e[par]["std"])
            for n, e in cl.items()
            if isinstance(e.get(par), Mapping) and e[par].get("std") is not None
        ]
        return sorted(vals, key=lambda kv: kv[1])

    for par, unit, label in (
        ("radius_mm", "mm", "radial distance"),
        ("speed_mm_s", "mm/s", "speed"),
    ):
        r = rank(par)
        if not r:
            continue
        th = sorted(
            (
                (n, e[par]["std"])
                for n, e in t47.items()
                if e.get(par) and e[par].get("std") is not None
            ),
            key=lambda kv: kv[1],
        )
        ours_txt = ", ".join(f"{n} {fmt(v)}" for n, v in r[:3])
        th_txt = ", ".join(f"{n} {fmt(v)}" for n, v in th[:3])
        lines.append(
            f"- **Smallest {label} spread (std, {unit})**: this run {ours_txt}; "
            f"thesis table 4.7 {th_txt}."
        )
    for name in ("static_beam_measured", "static_beam_fitted"):
        by = [
            b
            for b in (cl.get(name) or {}).get("radius_error_by_speed", [])
            if b.get("mean") is not None
        ]
        if len(by) >= 2:
            lo, hi = by[0], by[-1]
            lines.append(
                f"- **{name}**: the mean radial error goes from {fmt(lo['mean'])} mm at "
                f"{fmt(lo['speed_mm_s'], 0)} mm/s to {fmt(hi['mean'])} mm at "
                f"{fmt(hi['speed_mm_s'], 0)} mm/s. The equation is static; it uses one "
                "assumed speed for every trial (the author's code used each test trial's "
                "true speed and radius, docs/methods.md)."
            )
    for name in (results.get("oracle_angle") or {}).get("classifiers", {}):
        sentence = _gap_sentence(results, name)
        if sentence:
            lines.append(f"- {sentence}")
    meta = results.get("meta") or {}
    if meta.get("saturated_fraction") is not None:
        lines.append(
            f"- {fmt(100 * meta['saturated_fraction'], 1)} % of this run's trials "
            "reach the Hall sensor's output limits."
        )
    if not lines:
        return "Nothing to compare: the run has no classifier with a thesis counterpart."
    return "\n".join(lines)


def write_outputs(
    results: Mapping[str, Any],
    out_dir: str | os.PathLike[str],
    *,
    figures: bool = True,
    dataset: Any = None,
    dpi: int = 200,
    workers: int | None = 1,
) -> dict[str, Path]:
    """Write the CSV tables and the figures of a chapter-4 run into ``out_dir``.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    out_dir : path-like
        Directory (created if needed). Files are replaced atomically:
        ``results.csv``, ``radius_error_by_speed.csv``, ``figures/*.png``.
    figures : bool, default=True
        Draw the results figures.
    dataset : xarray.Dataset, optional
        Also draw the data figures (typical traces, figure 3.7; feature contours,
        figure 4.1) from it.
    dpi : int, default=200
        Figure resolution.
    workers : int or None, default=1
        Processes that draw the results figures (``None``: every core).

    Returns
    -------
    dict of str to pathlib.Path
        Figure key -> path.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(results, out / "results.csv")
    atomic_write_text(out / "radius_error_by_speed.csv", _by_speed_csv(results))
    figs: dict[str, Path] = {}
    if figures:
        from vibrissa.evaluate import figures as vfig
        from vibrissa.thesis.radial_distance.figures import chapter4_figures

        figs.update(chapter4_figures(results, out / "figures", dpi=dpi, workers=workers))
        if dataset is not None:
            figs["dataset/traces"] = vfig.save_figure(
                vfig.typical_traces_figure(dataset), out / "figures" / "traces.png", dpi
            )
            ax = vfig.feature_contours(dataset)
            figs["dataset/contours"] = vfig.save_figure(
                ax[0].figure, out / "figures" / "contours.png", dpi
            )
    return figs
