"""CrunchBot's report sections (thesis 6.5).

Map and trajectory errors beside the thesis' and the baselines, radial distance, floor
texture, latencies and the discussion; every number from the results.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vibrissa.evaluate.report_common import fmt, md_table

__all__ = ["markdown_crunchbot"]


def markdown_crunchbot(results: Mapping[str, Any], figures: Mapping[str, Path]) -> str:
    """The report's Markdown body for CrunchBot results and the figures written."""
    meta, th = results["meta"], results["thesis"]
    me, te = results["map_error"], results["trajectory_error_mm"]
    modes = ("blob", "geometric", "template")
    out: list[str] = []
    if meta.get("synthetic"):
        out += [
            f"> **Synthetic robot ({meta['robot']}).** These runs come from the "
            "exact-contact oracle with synthetic whisker signals, not from the "
            "simulated whisker physics: contacts and radial distances are exact and "
            "no real-time classifier ran. The map and trajectory errors test the "
            "filter, not the whiskers.",
            "",
        ]
    out += [
        f"CrunchBot (thesis 6.5) ran {meta['n_runs']} times for "
        f"{fmt(meta['seconds_per_run'], 0)} s in the `{meta['arena']}` arena; each run's "
        f"sensor log was mapped by a particle filter of {meta['particles']} particles in "
        "three modes. The three modes share each run's sensor log: the robot's behaviour "
        "(the FSM of 6.5.3) never reads the map, so one log per run serves them all.",
        "",
        "## Map error (eq. 6.3)",
        "",
        md_table(
            ["mode", "thesis", "this run (mean +/- std over runs)", "trajectory error (mm)"],
            [
                [
                    m,
                    fmt(th["map_error"][m]),
                    f"{fmt(me[m]['mean'], 3)} +/- {fmt(me[m]['std'], 3)}",
                    f"{fmt(te[m]['mean'], 1)} +/- {fmt(te[m]['std'], 1)}",
                ]
                for m in modes
            ]
            + [
                [
                    "random (Bernoulli 0.5)",
                    fmt(th["map_error"]["random"]),
                    fmt(me["random"], 3),
                    "—",
                ],
                ["random, smoothed 5 x 5", "—", fmt(me["random_smoothed"], 3), "—"],
                ["empty (nothing explored, all 0.3)", "—", fmt(me["empty"], 3), "—"],
                [
                    "dead reckoning",
                    "—",
                    "—",
                    f"{fmt(te['dead_reckoning']['mean'], 1)} +/- "
                    f"{fmt(te['dead_reckoning']['std'], 1)}",
                ],
            ],
        ),
        "",
        _discussion(results),
        "",
        "`map_error.random` is the cell-wise Bernoulli(0.5) map, whose expected error is "
        "exactly 0.5 whatever the truth (|B - g| averages 0.5(1 - g) + 0.5 g); the "
        "thesis' 0.47 is not reproducible that way. The smoothed variant passes each "
        "random map through the same 5 x 5 filter as the truth. The empty map, which "
        "explored nothing, is the floor a mode must beat to have mapped anything: most "
        "of the 2.5 m map lies outside the arena, where the truth is 0 and an "
        "unexplored cell counts 0.3.",
        "",
    ]
    out += _arena_section(results) + _fsm_section(results)
    if "maps" in figures:
        out += [f"![average maps (figure 6.14)]({figures['maps']})", ""]
    if "trajectory" in figures:
        out += [
            "Run 0: the true path and the filter's pose estimate per mode "
            "(the thesis could not measure this):",
            "",
            f"![trajectory]({figures['trajectory']})",
            "",
        ]
    out += [
        "## Per run",
        "",
        md_table(
            [
                "run",
                "FSM steps",
                *[f"{m} map error" for m in modes],
                *[f"{m} trajectory (mm)" for m in modes],
                "dead reckoning (mm)",
            ],
            [
                [
                    r["run"],
                    r["n_steps"],
                    *[fmt(r[m]["map_error"], 3) for m in modes],
                    *[fmt(r[m]["trajectory_error_mm"], 1) for m in modes],
                    fmt(r["dead_reckoning_error_mm"], 1),
                ]
                for r in results["per_run"]
            ],
        ),
        "",
    ]
    rd = results["radial_distance_error_mm"]
    n_c = results["radial_distance_contacts"]
    keys = [k for k in rd if k != "combined"]
    fit = results.get("radial_distance_fit_residual_mm") or {}
    out += [
        "## Radial distance (6.5.4)",
        "",
        "The thesis' table (6.5.6.2) gives the standard error of each whisker's "
        "regression on its training contacts (figure 6.12's error bars). Beside it: "
        "the same residual of our fitted lines on their training contacts, and the "
        "error of the estimates the robot reported in its SLAM runs against the "
        "simulator's true contact point, which the thesis could not measure.",
        "",
        md_table(
            [
                "whisker",
                "thesis std (mm)",
                "training-fit residual std (mm)",
                "in-run error std (mm)",
                "in-run contact steps",
            ],
            [
                [
                    k,
                    fmt(th["radial_distance_error_mm"].get(k)),
                    fmt(fit.get(k)),
                    fmt(rd[k]),
                    n_c.get(k, ""),
                ]
                for k in keys
            ]
            + [
                [
                    "combined",
                    fmt(th["radial_distance_error_mm"]["combined"]),
                    "",
                    fmt(rd["combined"]),
                    sum(n_c.values()),
                ]
            ],
        ),
        "",
    ]
    if "radial" in figures:
        out += [f"![radial distance (figure 6.12)]({figures['radial']})", ""]
    acc = results["floor_texture"]["accuracy"]
    out += [
        "## Floor texture (6.5.2) and real-time classifiers",
        "",
        f"Floor-texture accuracy over the floor whiskers' steps on a tile, in the "
        f"`{meta.get('texture_arena')}` arena: {fmt(acc, 3)}.",
        "",
    ]
    if "texture" in figures:
        out += [f"![texture trace (figure 6.11)]({figures['texture']})", ""]
    lat = results["classifier_latency_ms"]
    out += [
        md_table(
            ["classifier", "median (ms)", "p99 (ms)", "calls"],
            [[c, fmt(v["median"], 3), fmt(v["p99"], 3), v["n_calls"]] for c, v in lat.items()],
        ),
        "",
        f"Real-time factor (simulated seconds per wall second of the robot): "
        f"{fmt(meta['real_time_factor'], 1)}.",
        "",
    ]
    return "\n".join(out)


def _discussion(results: Mapping[str, Any]) -> str:
    """Whether the thesis' ordering template < geometric < blob holds in this run."""
    me, te = results["map_error"], results["trajectory_error_mm"]
    order = results["ordering"]["order"]
    holds = results["ordering"]["template_lt_geometric_lt_blob"]
    spread = max(me[m]["mean"] for m in order) - min(me[m]["mean"] for m in order)
    noise = max(me[m]["std"] for m in order) / math.sqrt(max(results["meta"]["n_runs"], 1))
    beats = [m for m in order if me[m]["mean"] < me["random"]]
    useful = [m for m in order if me[m]["mean"] < me["empty"]]
    best_traj = min(order, key=lambda m: te[m]["mean"])
    text = (
        f"The thesis' ordering template < geometric < blob "
        f"{'holds' if holds else 'does not hold'} here: from best to worst "
        f"{' < '.join(order)}, a spread of {spread:.3f} against a standard error of the "
        f"mean of about {noise:.3f}"
    )
    text += " (within the run-to-run noise)." if spread < 2 * noise else "."
    text += (
        f" {len(beats)} of 3 modes beat the random map and {len(useful)} of 3 the "
        f"empty map ({me['empty']:.3f}). The best trajectory is "
        f"{best_traj}'s ({te[best_traj]['mean']:.1f} mm), dead reckoning "
        f"{te['dead_reckoning']['mean']:.1f} mm."
    )
    return text


def _arena_section(results: Mapping[str, Any]) -> list[str]:
    """Eq. 6.3 over the arena's cells only, beside its empty and random maps."""
    ma = results.get("map_error_arena") or {}
    if not ma:
        return []
    ordering = results.get("ordering", {})
    arena = ordering.get("arena", {})
    beats = ordering.get("beats_empty", {}).get("arena", {})
    modes = ("blob", "geometric", "template")
    rows = [
        [
            m,
            f"{fmt(ma[m]['mean'], 3)} +/- {fmt(ma[m]['std'], 3)}",
            fmt((beats.get(m) or {}).get("runs_below"), 2),
        ]
        for m in modes
    ]
    rows += [
        ["random (Bernoulli 0.5)", fmt(ma["random"], 3), ""],
        ["random, smoothed 5 x 5", fmt(ma["random_smoothed"], 3), ""],
        ["empty (all 0.3)", fmt(ma["empty"], 3), ""],
    ]
    order = arena.get("order") or []
    return [
        "## Map error over the arena only",
        "",
        "The same error over the cells of the arena and its walls (the thesis averages "
        "over the whole 50 x 50 grid, three quarters of which lies outside the arena). "
        f"From best to worst: {' < '.join(order)}; the thesis' ordering "
        f"{'holds' if arena.get('template_lt_geometric_lt_blob') else 'does not hold'} "
        "on the means here, and holds run by run in "
        f"{fmt(arena.get('runs_template_lt_geometric_lt_blob'), 2)} of the runs.",
        "",
        md_table(["mode", "mean +/- std over runs", "runs below the empty map"], rows),
        "",
    ]


def _fsm_section(results: Mapping[str, Any]) -> list[str]:
    """How the FSM's episodes ended (6.5.3), summed and per run."""
    tot = results.get("fsm_outcomes")
    if not tot:
        return []
    ends = tot["fwd2_ends"]
    after = tot["abort_after"]
    return [
        "## The FSM's outcomes (6.5.3)",
        "",
        "FWD_2 ends in HIT_2 when a second whisker touches and in ABORT when a "
        "whisker's strain passes the safety threshold; the thesis' robot reached HIT_2 "
        'normally and aborted "in some cases" (6.5.5.2). Summed over '
        f"{tot['runs']} runs: {ends['hit_2']} FWD_2 runs ended in HIT_2 and "
        f"{ends['abort']} in ABORT; all aborts: {tot['abort']} ({after['FWD_1']} in FWD_1, "
        f"{after['FWD_2']} in FWD_2, {after['TURN']} while turning). The surface-angle "
        f"templates gave an angle at {tot.get('hit_2_with_surface_angle', '-')} of the "
        f"{tot['hit_2']} HIT_2s.",
        "",
        md_table(
            ["run", "HIT_1", "HIT_2", "ABORT", "of which in FWD_2", "TURN", "BACK steps"],
            [
                [
                    r["run"],
                    r["fsm"]["hit_1"],
                    r["fsm"]["hit_2"],
                    r["fsm"]["abort"],
                    r["fsm"]["abort_after"]["FWD_2"],
                    r["fsm"]["turn"],
                    r["fsm"]["back_steps"],
                ]
                for r in results["per_run"]
                if "fsm" in r
            ],
        ),
        "",
    ]
