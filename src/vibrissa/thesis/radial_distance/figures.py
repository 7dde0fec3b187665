"""Result figures of chapter 4: figures 4.2-4.12.

Input: the results of :func:`vibrissa.thesis.radial_distance.evaluation.run_chapter4`.

Every plotting function takes ``ax=None`` and returns the axes it drew on;
:func:`classifier_figure` composes several and returns its Figure.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from vibrissa.evaluate.figures.common import (
    PARAMETER_LABELS,
    SHORT_NAMES,
    check_parameter,
    new_axes,
    save_figure,
)

__all__ = [
    "chapter4_figures",
    "classifier_figure",
    "comparison_plot",
    "error_histogram",
    "error_scatter",
    "oracle_angle_speed_plot",
    "prediction_scatter",
    "static_beam_speed_plot",
    "training_size_plot",
]


def _predictions(results: Mapping[str, Any], name: str) -> tuple[dict, dict]:
    pr = results.get("predictions")
    if not pr or name not in pr.get("classifiers", {}):
        raise ValueError(
            f"results hold no predictions for classifier {name!r} "
            "(run_chapter4(..., keep_predictions=True))"
        )
    true = {
        "radius_mm": np.asarray(pr["radius_mm_true"], float),
        "speed_mm_s": np.asarray(pr["speed_mm_s_true"], float),
    }
    c = pr["classifiers"][name]
    pred = {k: (None if c.get(k) is None else np.asarray(c[k], float)) for k in true}
    return true, pred


def _bins(err: np.ndarray) -> np.ndarray | int:
    err = err[np.isfinite(err)]
    if err.size == 0:
        return 10
    lo, hi = np.floor(err.min()), np.ceil(err.max())
    span = hi - lo
    if span == 0:
        return np.array([lo - 0.5, lo + 0.5])
    step = max(1.0, float(np.ceil(span / 60)))
    return np.arange(lo - 0.5 * step, hi + step, step)


def error_histogram(
    errors: Any,
    *,
    parameter: str = "radius_mm",
    ax: Axes | None = None,
    bins: Any = None,
    title: str | None = None,
) -> Axes:
    """Histogram of signed classification errors (figures 4.2a-4.11a/b).

    Parameters
    ----------
    errors : array-like
        Signed errors ``predicted - true`` of one parameter (mm or mm/s).
    parameter : {"radius_mm", "speed_mm_s"}
        Which parameter (for the axis label).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure if omitted.
    bins : optional
        Passed to ``hist``; default one bin per unit (wider for wide spreads).
    title : str, optional
        Axes title.

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_parameter(parameter)
    err = np.asarray(errors, dtype=float).ravel()
    ax = new_axes(ax)
    # matplotlib's stubs type ``bins`` as int, str or Sequence[float]; an ndarray works
    ax.hist(err, bins=_bins(err) if bins is None else bins, color="0.35")  # type: ignore[arg-type]
    ax.axvline(0.0, color="C3", lw=0.8)
    ax.set_xlabel(f"{PARAMETER_LABELS[parameter]} error")
    ax.set_ylabel("trials (count)")
    if title:
        ax.set_title(title)
    return ax


def error_scatter(
    radius_errors: Any, speed_errors: Any, *, ax: Axes | None = None, title: str | None = None
) -> Axes:
    """Scatter of radial-distance error against speed error per test trial (figures 4.5c-4.11c).

    Parameters
    ----------
    radius_errors, speed_errors : array-like
        Signed errors, mm and mm/s, one per trial.
    ax : matplotlib.axes.Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    r = np.asarray(radius_errors, float).ravel()
    s = np.asarray(speed_errors, float).ravel()
    if r.shape != s.shape:
        raise ValueError(f"radius_errors and speed_errors differ in length: {r.size} vs {s.size}")
    ax = new_axes(ax)
    ax.scatter(s, r, s=6, alpha=0.3, color="C0", edgecolors="none")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("speed error (mm/s)")
    ax.set_ylabel("radial distance error (mm)")
    if title:
        ax.set_title(title)
    return ax


def prediction_scatter(
    y_true: Any,
    y_pred: Any,
    *,
    parameter: str = "radius_mm",
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Predicted against true value of one parameter, with the identity line.

    Marker area grows with the number of trials at each (true, predicted) pair,
    since grid values repeat.

    Parameters
    ----------
    y_true, y_pred : array-like
        True and predicted values (mm or mm/s).
    parameter : {"radius_mm", "speed_mm_s"}
    ax : matplotlib.axes.Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_parameter(parameter)
    t = np.asarray(y_true, float).ravel()
    p = np.asarray(y_pred, float).ravel()
    if t.shape != p.shape:
        raise ValueError(f"y_true and y_pred differ in length: {t.size} vs {p.size}")
    ax = new_axes(ax)
    pairs, counts = np.unique(np.column_stack([t, p]), axis=0, return_counts=True)
    ax.scatter(
        pairs[:, 0],
        pairs[:, 1],
        s=4 + 6 * np.sqrt(counts),
        alpha=0.5,
        color="C0",
        edgecolors="none",
    )
    if t.size:
        lo, hi = float(min(t.min(), np.nanmin(p))), float(max(t.max(), np.nanmax(p)))
        ax.plot([lo, hi], [lo, hi], color="C3", lw=0.8)
    label = PARAMETER_LABELS[parameter]
    ax.set_xlabel(f"true {label}")
    ax.set_ylabel(f"predicted {label}")
    if title:
        ax.set_title(title)
    return ax


def _entry(results: Mapping[str, Any], name: str) -> dict[str, Any]:
    try:
        return results["classifiers"][name]
    except KeyError:
        known = sorted(results.get("classifiers", {}))
        raise ValueError(f"no results for classifier {name!r} (have {known})") from None


def static_beam_speed_plot(
    results: Mapping[str, Any],
    name: str = "static_beam_fitted",
    *,
    errorbar: Literal["std", "sem"] = "std",
    ax: Axes | None = None,
) -> Axes:
    """Mean radial-distance error per contact speed, with error bars (figures 4.2b, 4.3b).

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    name : str, default="static_beam_fitted"
        Classifier (any classifier has ``radius_error_by_speed``).
    errorbar : {"std", "sem"}, default="std"
        Spread of the per-trial errors or standard error of their mean.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    if errorbar not in ("std", "sem"):
        raise ValueError(f"errorbar must be 'std' or 'sem', got {errorbar!r}")
    rows = _entry(results, name)["radius_error_by_speed"]
    s = np.array([r["speed_mm_s"] for r in rows], float)
    m = np.array([np.nan if r["mean"] is None else r["mean"] for r in rows], float)
    e = np.array([0.0 if r[errorbar] is None else r[errorbar] for r in rows], float)
    ax = new_axes(ax)
    ax.errorbar(s, m, yerr=e, fmt="o-", ms=3, capsize=2, color="C0")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("contact speed (mm/s)")
    ax.set_ylabel("radial distance error (mm)")
    ax.set_title(f"{SHORT_NAMES.get(name, name)}: error per speed")
    return ax


def oracle_angle_speed_plot(
    results: Mapping[str, Any],
    name: str = "static_beam_measured",
    *,
    errorbar: Literal["std", "sem"] = "std",
    ax: Axes | None = None,
) -> Axes:
    """Radial error per speed of a static beam: its own angle and the author's oracle angle.

    Parameters
    ----------
    results : dict
        Results of a chapter-4 run with the ``oracle_angle`` section
        (:func:`~vibrissa.thesis.radial_distance.evaluation.run_oracle_angle`).
    name : str, default="static_beam_measured"
        Static-beam classifier.
    errorbar : {"std", "sem"}, default="std"
        Spread of the per-trial errors or standard error of their mean.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    if errorbar not in ("std", "sem"):
        raise ValueError(f"errorbar must be 'std' or 'sem', got {errorbar!r}")
    oracle = (results.get("oracle_angle") or {}).get("classifiers", {})
    if name not in oracle:
        raise ValueError(f"results hold no oracle-angle row for {name!r} (have {sorted(oracle)})")
    ax = new_axes(ax)
    series = (
        ("fixed speed (ours)", _entry(results, name)["radius_error_by_speed"], "C0", 0.0),
        ("author's oracle angle", oracle[name]["radius_error_by_speed"], "C3", 1.5),
    )
    for label, rows, color, shift in series:
        s = np.array([r["speed_mm_s"] for r in rows], float)
        m = np.array([np.nan if r["mean"] is None else r["mean"] for r in rows], float)
        e = np.array([0.0 if r[errorbar] is None else r[errorbar] for r in rows], float)
        ax.errorbar(s + shift, m, yerr=e, fmt="o-", ms=3, capsize=2, color=color, label=label)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("contact speed (mm/s)")
    ax.set_ylabel(f"radial distance error (mm), mean ± {errorbar}")
    ax.set_title(f"{SHORT_NAMES.get(name, name)}: error per speed")
    ax.legend(fontsize=8)
    return ax


def training_size_plot(
    results: Mapping[str, Any],
    name: str,
    parameter: str = "radius_mm",
    *,
    ax: Axes | None = None,
) -> Axes:
    """Mean signed error against training-set size, error bars one std (figures 4.4-4.10).

    The 100 % point is the full-training-set result; the others average over seeds.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    name : str
        Classifier.
    parameter : {"radius_mm", "speed_mm_s"}
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_parameter(parameter)
    pts: dict[float, tuple[float, float]] = {}
    full = _entry(results, name).get(parameter)
    if full is not None and full.get("mean") is not None:
        pts[100.0] = (full["mean"], full.get("std") or 0.0)
    for key, per in results.get("training_fractions", {}).items():
        e = (per.get(name) or {}).get(parameter)
        if e is not None and e.get("mean") is not None:
            pts[100.0 * float(key)] = (e["mean"], e.get("std") or 0.0)
    ax = new_axes(ax)
    ax.set_xscale("log")
    if pts:
        x = np.array(sorted(pts))
        m = np.array([pts[k][0] for k in x])
        s = np.array([pts[k][1] for k in x])
        ax.errorbar(x, m, yerr=s, fmt="o-", ms=4, capsize=3, color="C0")
        ax.minorticks_off()
        ax.set_xticks(x)
        ax.set_xticklabels([f"{v:g}" for v in x])
    else:
        ax.text(0.5, 0.5, "not estimated", ha="center", va="center", transform=ax.transAxes)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("training set size (% of full set)")
    ax.set_ylabel(f"{PARAMETER_LABELS[parameter]} error")
    ax.set_title(SHORT_NAMES.get(name, name))
    return ax


def comparison_plot(
    results: Mapping[str, Any],
    parameter: str = "radius_mm",
    *,
    names: Sequence[str] | None = None,
    thesis: Mapping[str, Any] | None = None,
    ax: Axes | None = None,
) -> Axes:
    """Mean signed error of each classifier with one-std error bars (figure 4.12).

    With ``thesis``, the thesis' values (table 4.7) are drawn beside ours as
    hatched bars.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    parameter : {"radius_mm", "speed_mm_s"}
    names : sequence of str, optional
        Classifiers in plotting order (default: all, in the results' order);
        radius-only classifiers are skipped for speed.
    thesis : mapping, optional
        Classifier name -> ``{parameter: {"mean", "std"}}`` of the thesis (e.g. table
        4.7 under our names); classifiers without an entry get no thesis bar.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    check_parameter(parameter)
    names = list(results["classifiers"]) if names is None else list(names)
    xs, ms, ss, labels = [], [], [], []
    for i, n in enumerate(names):
        e = _entry(results, n).get(parameter)
        if e is None or e.get("mean") is None:
            continue
        xs.append(i)
        ms.append(e["mean"])
        ss.append(e.get("std") or 0.0)
        labels.append(SHORT_NAMES.get(n, n))
    ax = new_axes(ax, figsize=(6.5, 4.0))
    width = 0.4 if thesis else 0.8
    shift = width / 2 if thesis else 0.0
    ax.bar(
        np.asarray(xs) - shift,
        ms,
        width,
        yerr=ss,
        capsize=3,
        color="0.6",
        edgecolor="0.2",
        label="this run",
    )
    if thesis:
        tx, tm, ts = [], [], []
        for i, n in zip(xs, (names[i] for i in xs), strict=True):
            t = (thesis.get(n) or {}).get(parameter)
            if t and t.get("mean") is not None:
                tx.append(i + shift)
                tm.append(t["mean"])
                ts.append(t.get("std") or 0.0)
        if tx:
            ax.bar(
                tx,
                tm,
                width,
                yerr=ts,
                capsize=3,
                color="white",
                edgecolor="0.2",
                hatch="///",
                label="thesis (table 4.7)",
            )
        ax.legend(fontsize=8)
    ax.axhline(0.0, color="0.3", lw=0.6)
    ax.set_xticks(xs)
    ax.set_xticklabels(labels, rotation=30, ha="right")
    ax.set_ylabel(f"{PARAMETER_LABELS[parameter]} error, mean ± std")
    return ax


def classifier_figure(results: Mapping[str, Any], name: str) -> Figure:
    """The per-classifier error figure (figures 4.2/4.3 for the static beam, 4.5-4.11 else).

    Panels: (a) radial-distance error histogram; then for a classifier that
    estimates speed (b) speed error histogram, (c) radius error against speed
    error, (d, e) predicted against true radius and speed; for a radius-only
    classifier (b) the error per speed and (c) predicted against true radius.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4` with predictions.
    name : str
        Classifier.

    Returns
    -------
    matplotlib.figure.Figure
    """
    true, pred = _predictions(results, name)
    entry = _entry(results, name)
    label = SHORT_NAMES.get(name, name)
    r_err = pred["radius_mm"] - true["radius_mm"]
    if entry.get("speed_mm_s") is None or pred["speed_mm_s"] is None:
        fig = Figure(figsize=(12.0, 3.8), layout="constrained")
        a, b, c = fig.subplots(1, 3)
        error_histogram(r_err, parameter="radius_mm", ax=a, title=f"(a) {label}")
        static_beam_speed_plot(results, name, ax=b)
        b.set_title("(b) error per speed")
        prediction_scatter(
            true["radius_mm"],
            pred["radius_mm"],
            parameter="radius_mm",
            ax=c,
            title="(c) predicted vs true",
        )
        return fig
    s_err = pred["speed_mm_s"] - true["speed_mm_s"]
    fig = Figure(figsize=(15.0, 6.5), layout="constrained")
    axs = fig.subplots(2, 3)
    error_histogram(r_err, parameter="radius_mm", ax=axs[0, 0], title=f"(a) {label}: radius")
    error_histogram(s_err, parameter="speed_mm_s", ax=axs[0, 1], title="(b) speed")
    error_scatter(r_err, s_err, ax=axs[0, 2], title="(c) errors per trial")
    prediction_scatter(
        true["radius_mm"],
        pred["radius_mm"],
        parameter="radius_mm",
        ax=axs[1, 0],
        title="(d) radius: predicted vs true",
    )
    prediction_scatter(
        true["speed_mm_s"],
        pred["speed_mm_s"],
        parameter="speed_mm_s",
        ax=axs[1, 1],
        title="(e) speed: predicted vs true",
    )
    axs[1, 2].set_axis_off()
    return fig


def _slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def _figure(results: Mapping[str, Any], kind: str, name: str | None) -> Figure:
    """One figure of :func:`chapter4_figures`: ``errors``, ``training_size`` or ``comparison``."""
    if kind == "errors":
        assert name is not None, "an errors figure is one classifier's"
        return classifier_figure(results, name)
    if kind == "oracle_angle":
        names = list(results["oracle_angle"]["classifiers"])
        fig = Figure(figsize=(5.5 * len(names), 3.8), layout="constrained")
        for ax, n in zip(np.atleast_1d(fig.subplots(1, len(names))), names, strict=True):
            oracle_angle_speed_plot(results, n, ax=ax)
        return fig
    fig = Figure(
        figsize=(10.0, 3.8) if kind == "training_size" else (11.0, 4.0), layout="constrained"
    )
    a, b = fig.subplots(1, 2)
    if kind == "training_size":
        assert name is not None, "a training_size figure is one classifier's"
        training_size_plot(results, name, "radius_mm", ax=a)
        training_size_plot(results, name, "speed_mm_s", ax=b)
        a.set_title(f"(a) {SHORT_NAMES.get(name, name)}: radius")
        b.set_title("(b) speed")
        return fig
    from vibrissa.thesis.radial_distance.values import THESIS_CHAPTER4, THESIS_COLUMNS

    t47 = THESIS_CHAPTER4["table_4_7"]
    thesis = {n: t47[c] for n, (c, _) in THESIS_COLUMNS.items() if c in t47}
    comparison_plot(results, "radius_mm", thesis=thesis, ax=a)
    comparison_plot(results, "speed_mm_s", thesis=thesis, ax=b)
    a.set_title("(a) radial distance")
    b.set_title("(b) speed")
    return fig


def _draw(
    arrays: Any, *, results: Mapping[str, Any], kind: str, name: str | None, path: Path, dpi: int
) -> Path:
    """Draw one figure and write it (a job of :func:`vibrissa.evaluate.jobs.run_jobs`)."""
    return save_figure(_figure(results, kind, name), path, dpi)


def chapter4_figures(
    results: Mapping[str, Any],
    out_dir: str | os.PathLike[str],
    dpi: int = 200,
    workers: int | None = 1,
) -> dict[str, Path]:
    """Write every results figure of chapter 4 as PNG into ``out_dir``.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.thesis.radial_distance.evaluation.run_chapter4`.
    out_dir : path-like
        Directory (created if needed).
    dpi : int, default=200
    workers : int or None, default=1
        Processes that draw the figures (``None``: every core).

    Returns
    -------
    dict of str to pathlib.Path
        Keys ``"errors/<name>"`` (per-classifier error figure, if predictions
        are present), ``"training_size/<name>"`` (if reduced sets were run),
        ``"comparison"`` (figure 4.12), ``"oracle_angle"`` (the static beam's error
        per speed with the author's oracle angle, if the results have it).
    """
    from vibrissa.evaluate.jobs import SharedArrays, resolve_workers, run_jobs

    out = Path(out_dir)
    jobs: dict[str, tuple[str, str | None, Path]] = {}
    for name in results["classifiers"]:
        if results.get("predictions"):
            jobs[f"errors/{name}"] = ("errors", name, out / f"errors_{_slug(name)}.png")
        if results.get("training_fractions"):
            jobs[f"training_size/{name}"] = (
                "training_size",
                name,
                out / f"training_size_{_slug(name)}.png",
            )
    jobs["comparison"] = ("comparison", None, out / "comparison.png")
    if (results.get("oracle_angle") or {}).get("classifiers"):
        jobs["oracle_angle"] = ("oracle_angle", None, out / "oracle_angle.png")
    with SharedArrays(resolve_workers(workers)) as none:
        paths = run_jobs(
            _draw,
            [
                {"results": results, "kind": kind, "name": name, "path": path, "dpi": dpi}
                for kind, name, path in jobs.values()
            ],
            none,
        )
    return dict(zip(jobs, paths, strict=True))
