"""Result figures of chapter 5.

Input: the results of :func:`vibrissa.thesis.angle_texture.evaluation.run_chapter5`; the
figures: confusion matrices (figures 5.3-5.14), kappas beside the thesis' (figure 5.15)
and the evidence-over-contacts curve.

Every function takes ``ax=None`` / ``axes=None`` and returns what it drew on.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.data.schema import decode_texture
from vibrissa.evaluate.report_common import fmt
from vibrissa.thesis.angle_texture.evaluation import PARAMETERS5
from vibrissa.thesis.angle_texture.values import THESIS_CHAPTER5

__all__ = ["chapter5_figures", "confusion_figure", "kappa_figure", "sequential_figure"]


def _figure_axes(axes: Any, n: int, figsize: tuple[float, float], rows: int = 1) -> Any:
    """``axes`` as a flat array of ``n`` axes, or new ones on a standalone Figure."""
    if axes is not None:
        arr = np.atleast_1d(np.asarray(axes, dtype=object)).ravel()
        if arr.size != n:
            raise ValueError(f"need {n} axes, got {arr.size}")
        return arr
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return np.asarray(fig.subplots(rows, n // rows, squeeze=False), dtype=object).ravel()


def confusion_figure(entry: Mapping[str, Any], name: str, axes: Any = None) -> Any:
    """Confusion matrices of angle, speed and texture of one classifier (figures 5.3-5.14).

    Parameters
    ----------
    entry : dict
        ``results["classifiers"][name]``.
    name : str
    axes : sequence of matplotlib Axes, optional
        One per matrix (angle, speed, texture and, if present, texture alone);
        default: a new Figure.

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
    """
    conf = entry["confusion"]
    keys = [k for k in (*PARAMETERS5, "texture_alone") if conf.get(k)]
    axs = _figure_axes(axes, len(keys), (3.2 * len(keys), 3.4))
    units = {"angle": "deg", "speed": "mm/s", "texture": "", "texture_alone": ""}
    for ax, k in zip(axs, keys, strict=True):
        m = np.asarray(conf[k]["matrix"], dtype=float)
        lab = conf[k]["labels"]
        ax.imshow(m, cmap="gray_r", origin="upper")
        ticks = np.arange(len(lab))
        names = [_tick_label(k, v) for v in lab]
        ax.set_xticks(ticks, names, fontsize=7, rotation=90)
        ax.set_yticks(ticks, names, fontsize=7)
        unit = f" ({units[k]})" if units[k] else ""
        ax.set_xlabel(f"predicted{unit}")
        ax.set_ylabel(f"true{unit}")
        ax.set_title(f"{k.replace('_', ' ')} (kappa {fmt(entry['kappa'].get(k))})", fontsize=9)
    axs[0].figure.suptitle(f"{name}: trials per (true, predicted) class")
    return axs


def _tick_label(parameter: str, value: float) -> str:
    """Texture codes as names (``p180``), other labels as numbers."""
    if parameter.startswith("texture"):
        try:
            return str(decode_texture([value])[0])
        except ValueError:
            pass
    return f"{value:g}"


def kappa_figure(results: Mapping[str, Any], axes: Any = None) -> Any:
    """Cohen's kappa of angle, speed and texture per classifier, ours beside the thesis'.

    One panel per parameter; solid bars are this run, hatched bars the thesis'
    values (5.4.1-5.4.5, figure 5.15) where it reports the method.

    Parameters
    ----------
    results : dict
    axes : sequence of 3 matplotlib Axes, optional

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes
    """
    names = list(results["classifiers"])
    axs = _figure_axes(axes, 3, (max(7.0, 0.5 * len(names)), 7.5), rows=3)
    x = np.arange(len(names))
    colours = ("tab:blue", "tab:red", "goldenrod")
    for ax, p, colour in zip(axs, PARAMETERS5, colours, strict=True):
        ours = [results["classifiers"][n]["kappa"].get(p) for n in names]
        th = [THESIS_CHAPTER5.get(n, {}).get("kappa", {}).get(p) for n in names]
        ax.bar(
            x - 0.2, [np.nan if v is None else v for v in ours], 0.4, color=colour, label="this run"
        )
        ax.bar(
            x + 0.2,
            [np.nan if v is None else v for v in th],
            0.4,
            color="white",
            edgecolor=colour,
            hatch="///",
            label="thesis (fig. 5.15, 5.4)",
        )
        ax.set_ylabel(f"{p} kappa (-)")
        ax.set_xticks(x, names if ax is axs[-1] else [""] * len(names), rotation=70, fontsize=8)
        ax.axhline(0.0, color="black", lw=0.6)
        ax.set_ylim(min(-0.1, *(v for v in ours if v is not None)), 1.0)
        ax.legend(fontsize=7, loc="upper left", ncols=2)
    axs[-1].set_xlabel("classifier")
    return axs


def sequential_figure(results: Mapping[str, Any], ax: Any = None) -> Any:
    """Texture kappa against the number of contacts (beyond the thesis).

    Returns
    -------
    matplotlib.axes.Axes
    """
    seq = results.get("sequential") or {}
    ax = _figure_axes(None if ax is None else [ax], 1, (4.5, 3.5))[0]
    n = [int(k) for k in seq]
    ax.plot(
        n,
        [np.nan if v is None else v for v in seq.values()],
        "o-",
        label=f"accumulated ({(results.get('sequential_detail') or {}).get('base', '')})",
    )
    single = {
        k: v["kappa"].get("texture")
        for k, v in results.get("classifiers", {}).items()
        if v.get("kappa", {}).get("texture") is not None
    }
    if single:
        best = max(single, key=single.__getitem__)
        ax.axhline(
            single[best], color="grey", ls="--", lw=0.8, label=f"best single contact ({best})"
        )
    ax.legend(fontsize=7, loc="lower right")
    ax.set_xlabel("contacts with the same surface (count)")
    ax.set_ylabel("texture kappa (-)")
    ax.set_ylim(-0.05, 1.05)
    return ax


def chapter5_figures(
    results: Mapping[str, Any], out_dir: str | os.PathLike[str], dpi: int = 200
) -> dict[str, Path]:
    """Write every chapter-5 figure as PNG (atomically) and return their paths.

    Returns
    -------
    dict of str to pathlib.Path
        ``confusion/<name>``, ``kappa`` and (if any) ``sequential``.
    """
    from vibrissa.evaluate.figures import save_figure

    out = Path(out_dir)
    paths: dict[str, Path] = {}
    for name, entry in results["classifiers"].items():
        paths[f"confusion/{name}"] = save_figure(
            confusion_figure(entry, name)[0].figure, out / f"confusion_{name}.png", dpi
        )
    paths["kappa"] = save_figure(kappa_figure(results)[0].figure, out / "kappa.png", dpi)
    if results.get("sequential"):
        paths["sequential"] = save_figure(
            sequential_figure(results).figure, out / "sequential.png", dpi
        )
    return paths
