"""Chapter-5 report sections and figures beside the thesis' values (5.4).

:data:`THESIS_CHAPTER5` transcribes Cohen's kappa of every classifier (5.4.1-5.4.5,
figure 5.15) and the mean and spread of the signed errors (tables 5.1-5.11) from
Evans (2011). Texture errors there are in texture indices (1-4, order as ours:
smooth aluminium, P600, P180, P80, i.e. :data:`vibrissa.data.TEXTURE_CODES`).
Every number the report's prose quotes is computed from the results (:func:`discussion`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from vibrissa.evaluate.report_common import fmt, md_table
from vibrissa.thesis.angle_texture.evaluation import PARAMETERS5
from vibrissa.thesis.angle_texture.values import THESIS_CHAPTER5

__all__ = [
    "THESIS_CHAPTER5",
    "discussion",
    "markdown_chapter5",
    "write_outputs",
]


_UNITS = {"angle_deg": "deg", "speed_mm_s": "mm/s", "texture": "grades"}


def markdown_chapter5(
    results: Mapping[str, Any],
    figures: Mapping[str, Path] | None = None,
    baseline: Mapping[str, Any] | None = None,
) -> str:
    """The Markdown report body of chapter-5 results.

    Parameters
    ----------
    results : dict
        The results of :func:`~vibrissa.thesis.angle_texture.evaluation.run_chapter5`.
    figures : mapping of str to relative path, optional
        Figure links (``confusion/<name>``, ``kappa``, ``sequential``).
    baseline : dict, optional
        An earlier run's results (:func:`vibrissa.evaluate.baseline.load_baseline`):
        adds a table of kappas thesis / before / this run (figure 5.15).

    Returns
    -------
    str
    """
    meta = results.get("meta", {})
    sp = meta.get("split", {})
    out = [
        f"Trials: {meta.get('n_trials')} ({meta.get('n_channels')} channels x "
        f"{meta.get('n_timepoints')} samples at {meta.get('sample_rate_hz')} Hz); "
        f"training sets {sp.get('train_sets')} ({sp.get('n_train')} trials), test sets "
        f"{sp.get('test_sets')} ({sp.get('n_test')} trials); angles {meta.get('angles_deg')} deg, "
        f"speeds {meta.get('speeds_mm_s')} mm/s, texture codes {meta.get('texture_codes')}.",
        "",
        "## Cohen's kappa (ours / thesis)",
        "",
        "Simultaneous classification of angle, speed and texture; *texture alone*: "
        "trained and tested per speed-angle combination, pooled (5.3.6). Thesis values "
        "from 5.4.1-5.4.5 and figure 5.15.",
        "",
    ]
    rows = []
    for name, r in results.get("classifiers", {}).items():
        th = THESIS_CHAPTER5.get(name, {}).get("kappa", {})
        k = r.get("kappa", {})
        rows.append(
            [f"`{name}`"]
            + [f"{fmt(k.get(p))} / {fmt(th.get(p))}" for p in (*PARAMETERS5, "texture_alone")]
            + [f"{r.get('classify_seconds', 0):.2f}"]
        )
    out.append(
        md_table(["classifier", "angle", "speed", "texture", "texture alone", "classify s"], rows)
    )
    if baseline is not None:
        out += [
            "",
            "## Cohen's kappa: thesis / before / this run (figure 5.15)",
            "",
            f"*before*: {baseline.get('meta', {}).get('label', 'an earlier run')}.",
            "",
        ]
        rows = []
        old = baseline.get("classifiers", {})
        for name, r in results.get("classifiers", {}).items():
            th = THESIS_CHAPTER5.get(name, {}).get("kappa", {})
            kb = old.get(name, {}).get("kappa", {})
            k = r.get("kappa", {})
            rows.append(
                [f"`{name}`"]
                + [
                    f"{fmt(th.get(p))} / {fmt(kb.get(p))} / {fmt(k.get(p))}"
                    for p in (*PARAMETERS5, "texture_alone")
                ]
            )
        out.append(md_table(["classifier", "angle", "speed", "texture", "texture alone"], rows))
    out += ["", "## Weighted kappa (linear / quadratic; suggested in 5.5)", ""]
    rows = []
    for name, r in results.get("classifiers", {}).items():
        wk = r.get("weighted_kappa", {})
        rows.append(
            [f"`{name}`"]
            + [
                f"{fmt(wk.get(p, {}).get('linear'))} / {fmt(wk.get(p, {}).get('quadratic'))}"
                for p in PARAMETERS5
            ]
        )
    out.append(md_table(["classifier", "angle", "speed", "texture"], rows))
    out += ["", "## Signed error, mean (std) - ours / thesis (tables 5.1-5.11)", ""]
    rows = []
    for name, r in results.get("classifiers", {}).items():
        th = THESIS_CHAPTER5.get(name, {}).get("errors") or {}
        cells = []
        for unit in ("angle_deg", "speed_mm_s", "texture"):
            e = r.get("errors", {}).get(unit, {})
            t = th.get(unit, {})
            cells.append(
                f"{fmt(e.get('mean'))} ({fmt(e.get('std'))}) / "
                f"{fmt(t.get('mean'))} ({fmt(t.get('std'))})"
            )
        rows.append([f"`{name}`"] + cells)
    out.append(md_table(["classifier", "angle (deg)", "speed (mm/s)", "texture (grades)"], rows))
    seq = results.get("sequential") or {}
    det = results.get("sequential_detail") or {}
    if seq:
        out += [
            "",
            "## Sequential contacts (beyond the thesis)",
            "",
            f"Texture kappa after accumulating the posteriors of `{det.get('base')}` over "
            f"n contacts with the same surface (stop at posterior "
            f">= {det.get('threshold')}).",
            "",
        ]
        used = det.get("mean_contacts_used", {})
        out.append(
            md_table(
                ["contacts", "texture kappa", "mean contacts used"],
                [[n, fmt(k), fmt(used.get(n))] for n, k in seq.items()],
            )
        )
    out += ["", "## Discussion", "", discussion(results)]
    if figures:
        out += ["", "## Figures", ""]
        for k, p in figures.items():
            out += [f"![{_caption(k)}]({p.as_posix() if isinstance(p, Path) else p})", ""]
    return "\n".join(out) + "\n"


def _caption(key: str) -> str:
    if key.startswith("confusion/"):
        return f"Confusion matrices of {key.split('/', 1)[1]} (cf. figures 5.3-5.14)"
    return {
        "kappa": "Cohen's kappa per classifier, ours beside the thesis' (figure 5.15)",
        "sequential": "Texture kappa against the number of contacts (beyond the thesis)",
    }.get(key, key)


def discussion(results: Mapping[str, Any]) -> str:
    """How this run compares with the thesis, every number computed from ``results``."""
    cl = results.get("classifiers", {})
    lines = []
    for par, label in (("angle", "angle"), ("speed", "speed"), ("texture", "texture")):
        ours = {
            n: e["kappa"][par] for n, e in cl.items() if e.get("kappa", {}).get(par) is not None
        }
        th = {
            n: e["kappa"][par]
            for n, e in THESIS_CHAPTER5.items()
            if e.get("kappa", {}).get(par) is not None
        }
        both = sorted(set(ours) & set(th))
        if not ours:
            continue
        best = max(ours, key=ours.__getitem__)
        th_best = max(th, key=th.__getitem__) if th else None
        above = sum(ours[n] > th[n] for n in both)
        text = (
            f"- **{label}**: best kappa {fmt(ours[best])} (`{best}`)"
            + (f"; thesis best {fmt(th[th_best])} (`{th_best}`, 5.4)" if th_best else "")
            + (
                f"; {above} of the {len(both)} methods the thesis reports score higher "
                "here than there."
                if both
                else "."
            )
        )
        lines.append(text)
    seq = results.get("sequential") or {}
    vals = [(int(k), v) for k, v in seq.items() if v is not None]
    if vals:
        (n0, k0), (n1, k1) = vals[0], vals[-1]
        base = (results.get("sequential_detail") or {}).get("base")
        lines.append(
            f"- **Evidence over contacts** (beyond the thesis): texture kappa "
            f"{fmt(k0)} after {n0} contact(s) of `{base}`, {fmt(k1)} after {n1}."
        )
    return "\n".join(lines) if lines else "No classifier results to compare."


def write_outputs(
    results: Mapping[str, Any],
    out_dir: str | os.PathLike[str],
    *,
    figures: bool = True,
    dpi: int = 200,
) -> dict[str, Path]:
    """Write the chapter-5 figures into ``out_dir/figures`` (atomically); return their paths.

    Returns
    -------
    dict of str to pathlib.Path
        ``confusion/<name>``, ``kappa`` and (if any) ``sequential``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    from vibrissa.thesis.angle_texture.figures import chapter5_figures

    return chapter5_figures(results, out / "figures", dpi) if figures else {}
