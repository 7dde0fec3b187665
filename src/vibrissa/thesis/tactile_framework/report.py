"""The tactile-framework report: the claims of 2.5 tested, per-policy tables, curves, maps."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from vibrissa.evaluate.report_common import fmt, md_table
from vibrissa.thesis.tactile_framework.values import THESIS

__all__ = ["markdown_framework"]

POLICIES = ("passive", "active", "oracle")


def _pct(v: float | None) -> str:
    return "n/a" if v is None else f"{100.0 * v:.1f} %"


def _num(v: float | None, digits: int = 1) -> str:
    return "n/a" if v is None else fmt(v, digits)


def _join_mm(values: list[float]) -> str:
    return ", ".join(fmt(v, 0) for v in values)


def _figure(figures: Mapping[str, Path], key: str, caption: str) -> list[str]:
    if key not in figures:
        return []
    return [f"![{caption}](figures/{Path(figures[key]).name})", "", f"*{caption}*", ""]


def markdown_framework(results: Mapping[str, Any], figures: Mapping[str, Path]) -> str:
    """The report's Markdown body (every number from ``results``)."""
    cal = results["calibration"]
    pols = results["policies"]
    curves = results["curves"]
    maps = results["maps"]
    comp = results["comparison"]
    proto = results["meta"].get("protocol") or {}
    head = proto.get("head") or {}
    out = [
        "The thesis' tactile framework (2.5, figure 2.17) run as one closed loop: a whisking "
        f"head of {head.get('n_whiskers', '?')} `{head.get('whisker', '?')}` whiskers "
        f"({head.get('frequency_hz', '?')} Hz, {head.get('amplitude_deg', '?')} deg whisks, Hall "
        f"x and y at {head.get('sample_rate_hz', '?')} Hz) on a mobile base explores a box world "
        f"(`{proto.get('world', '?')}`) of square-cornered boxes whose faces carry the four "
        "chapter-5 textures. Each contact goes through `vibrissa.framework.TactilePipeline`: "
        "where (radial distance, tip or shaft), then, for tip contacts, what (surface angle "
        "class and texture), with evidence accumulated across contacts and whiskers.",
        "",
        "## The claims of 2.5",
        "",
        md_table(
            ["claim (thesis)", "this run"],
            [
                [THESIS["shaft_is_corner"], _shaft_claim(pols)],
                [THESIS["reposition"], _reposition_claim(pols)],
                [THESIS["tip_for_what"], _what_claim(comp)],
                [THESIS["map"], _map_claim(maps)],
            ],
        ),
        "",
        "## Calibration",
        "",
        f"The pipeline's classifiers were fitted on a calibration session on the same platform "
        f"(`{proto.get('calibration_world', '?')}` world, {proto.get('n_calibration', '?')} whisks "
        f"of passive patrols): {cal['contacts']} detected contacts, {cal['tip_contacts']} at the "
        f"tip and {cal['shaft_contacts']} on the shaft; {cal['what_classes']} joint (angle class, "
        f"texture) classes; radial classes {_join_mm(cal['radial_classes_mm'])} mm.",
        "",
        "## Policies",
        "",
        f"{proto.get('n_episodes', '?')} episodes per policy, {proto.get('n_whisks', '?')} "
        "whisk-and-step cycles each, the same starts and noise for every policy.",
        "",
        md_table(
            [
                "policy",
                "contacts",
                "true tip fraction",
                "tip/shaft call right",
                "shaft radial error (median)",
                "repositions",
                "used for what",
            ],
            [
                [
                    name,
                    pols[name]["contacts"],
                    _pct(pols[name]["tip_fraction"]),
                    _pct(pols[name]["tip_shaft_accuracy"]),
                    f"{_num(pols[name]['shaft_radial_error_mm'])} mm",
                    pols[name]["repositions"],
                    pols[name]["used_for_what"],
                ]
                for name in POLICIES
            ],
        ),
        "",
        "## Decisions over thresholds",
        "",
        "Texture decisions (the angle a contact reports is the surface's angle to the "
        "whisker, which changes as the base moves; the map carries the surface's direction "
        "in the world instead). *With the deadline* every episode decides: at the first "
        "contact past the threshold, or when its budget of whisks runs out, on the evidence "
        "it has (an episode with no contact fed to what names nothing and is wrong). "
        "Accuracy / mean contacts to decision (every contact of the episode up to the "
        "deciding one) / episodes that decided before the deadline:",
        "",
        _threshold_table(
            curves,
            "accuracy / contacts / at threshold",
            lambda r: (
                f"{_pct(r.get('accuracy_with_deadline'))} / "
                f"{_num(r.get('contacts_with_deadline'))} / {_pct(r['decided_fraction'])}"
            ),
        ),
        "",
        "Scored only over the episodes that reached the threshold (accuracy / contacts): a "
        "policy that seldom decides is scored on the episodes easy enough to decide.",
        "",
        _threshold_table(
            curves,
            "accuracy / contacts",
            lambda r: f"{_pct(r['accuracy'])} / {_num(r['contacts_to_decision'])}",
        ),
        "",
        *_paired_table(comp),
        "Active beats passive on both accuracy and contacts to decision (with the deadline) "
        f"at every threshold: **{'yes' if comp['active_beats_passive_everywhere'] else 'no'}**; "
        "over only the episodes that reached the threshold: "
        f"**{'yes' if comp.get('active_beats_passive_everywhere_decided_only') else 'no'}**.",
        "",
        *_figure(figures, "curves", "Speed-accuracy curves of the three policies"),
        *_figure(figures, "episode", "One episode under each policy"),
        *_figure(
            figures,
            "radial",
            "Where: estimated against true radial distance, and the tip-or-shaft posterior",
        ),
        *_transfer_section(results.get("transfer")),
        "## The touch map",
        "",
        md_table(
            [
                "policy",
                "eq. 6.3 grid",
                "empty map",
                "eq. 6.3 arena",
                "empty map (arena)",
                "texture cells",
                "texture accuracy",
                "surface direction error (median)",
            ],
            [
                [
                    name,
                    fmt(maps[name]["occupancy_error"], 3),
                    fmt(maps[name]["empty_map_error"], 3),
                    fmt(maps[name]["occupancy_error_arena"], 3),
                    fmt(maps[name]["empty_map_error_arena"], 3),
                    maps[name]["texture_cells"],
                    _pct(maps[name]["texture_accuracy"]),
                    f"{_num(maps[name]['direction_error_deg'])} deg",
                ]
                for name in POLICIES
            ],
        ),
        "",
        *_figure(figures, "touch_map", "Wall textures: ground truth and each policy's map"),
        "## Limits",
        "",
        "The base's pose in the map is its odometry (10 % noise per move, as CrunchBot's, "
        "6.5.4), not the SLAM filter of 6.5: an episode moves the base a few hundred "
        "millimetres from a known start.",
    ]
    return "\n".join(out)


def _transfer_section(tr: Mapping[str, Any] | None) -> list[str]:
    if not tr:
        return []
    c, x = tr["calibration"], tr["xy_robot"]
    return [
        "## Calibrated here, or on the XY robot",
        "",
        f"The same contacts of every episode ({c['contacts']}, {c['tip_contacts']} at the tip) "
        "called by the pipeline's models, fitted on this head's calibration session, and by the "
        "same estimator fitted on the XY robot's chapter-4 (where) and chapter-5 (what) quick "
        "sessions with the same whisker, windowed by the same detector:",
        "",
        md_table(
            [
                "trained on",
                "contacts",
                "tip/shaft right",
                "texture right (tip contacts)",
                "surface angle error (median)",
            ],
            [
                [
                    "this head's calibration session",
                    c["training_contacts"],
                    _pct(c["tip_shaft_accuracy"]),
                    _pct(c["texture_accuracy"]),
                    f"{_num(c['angle_error_deg'])} deg",
                ],
                [
                    "the XY robot (chapters 4 and 5)",
                    f"{x['training_contacts']['where']} + {x['training_contacts']['what']}",
                    _pct(x["tip_shaft_accuracy"]),
                    _pct(x["texture_accuracy"]),
                    f"{_num(x['angle_error_deg'])} deg",
                ],
            ],
        ),
        "",
        "The XY robot pushes a pole or a surface into a still whisker; here the whisker "
        "sweeps into a still object and the head's reflex ends the contact, so how far the "
        "XY classifiers carry over measures how much of a contact's signal is the whisker's "
        "and how much the robot's. The XY angle classes are 10-80 deg on the chapter-5 grid; "
        "this head's are 30 deg bins.",
        "",
    ]


def _shaft_claim(pols: Mapping[str, Any]) -> str:
    p = pols["passive"]
    return (
        f"passive: {_pct(p['tip_fraction'])} of matched contacts at the tip, the rest on the "
        f"shaft at corners; the pipeline calls tip/shaft right for {_pct(p['tip_shaft_accuracy'])}"
    )


def _reposition_claim(pols: Mapping[str, Any]) -> str:
    a, p, o = pols["active"], pols["passive"], pols["oracle"]
    return (
        f"true tip fraction passive {_pct(p['tip_fraction'])}, active {_pct(a['tip_fraction'])} "
        f"({a['repositions']} repositions), oracle {_pct(o['tip_fraction'])}"
    )


def _what_claim(comp: Mapping[str, Any]) -> str:
    rows = comp["per_threshold"]
    acc = sum(1 for r in rows if r["accuracy_active_beats_passive"])
    con = sum(1 for r in rows if r["contacts_active_beats_passive"])
    text = (
        f"with the deadline, active beats passive on accuracy at {acc} of {len(rows)} "
        f"thresholds and on contacts to decision at {con} of {len(rows)}"
    )
    if "accuracy_active_beats_passive_decided_only" in rows[0]:
        only = sum(1 for r in rows if r["accuracy_active_beats_passive_decided_only"])
        text += f"; over decided episodes only, on accuracy at {only} of {len(rows)}"
    return text


def _threshold_table(
    curves: Mapping[str, Any], what: str, cell: Callable[[Mapping[str, Any]], str]
) -> str:
    """One row per threshold, one ``cell`` per policy."""
    return md_table(
        ["threshold"] + [f"{n}: {what}" for n in POLICIES],
        [
            [fmt(rows[0]["threshold"], 3)] + [cell(r) for r in rows]
            for rows in zip(*(curves[n] for n in POLICIES), strict=True)
        ],
    )


def _interval(d: Mapping[str, float] | None, digits: int) -> str:
    if d is None:
        return "n/a"
    return f"{fmt(d['mean'], digits)} [{fmt(d['lo'], digits)}, {fmt(d['hi'], digits)}]"


def _paired_table(comp: Mapping[str, Any]) -> list[str]:
    rows = comp["per_threshold"]
    if not rows or "accuracy_gain_over_passive" not in rows[0]:
        return []
    return [
        "Active minus passive, episode by episode (same starts and noise), with the deadline; "
        "mean [95 % bootstrap interval over episodes]:",
        "",
        md_table(
            ["threshold", "accuracy gain", "contacts saved"],
            [
                [
                    fmt(r["threshold"], 3),
                    _interval(r["accuracy_gain_over_passive"], 2),
                    _interval(r["contacts_saved_over_passive"], 1),
                ]
                for r in rows
            ],
        ),
        "",
    ]


def _map_claim(maps: Mapping[str, Any]) -> str:
    a = maps["active"]
    return (
        f"active's map: texture right in {_pct(a['texture_accuracy'])} of "
        f"{a['texture_cells']} touched wall cells; eq. 6.3 {fmt(a['occupancy_error'], 3)} "
        f"against {fmt(a['empty_map_error'], 3)} for an empty map"
    )
