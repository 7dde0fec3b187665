"""Figures of the thesis' chapters 3-5, drawn from datasets and evaluation results.

Every plotting function takes ``ax=None`` (or ``axes``/``fig``) and returns the
axes it drew on; with ``ax=None`` it creates a standalone
:class:`matplotlib.figure.Figure` (no pyplot state, no GUI backend, nothing is
shown). :func:`save_figure` writes PNGs atomically.

Results figures (input: the dict of :func:`vibrissa.evaluate.chapter4.run_chapter4`):

- :func:`error_histogram`, :func:`error_scatter`, :func:`prediction_scatter` and
  :func:`classifier_figure` - figures 4.2, 4.3, 4.5, 4.7, 4.9, 4.11;
- :func:`training_size_plot` - figures 4.4, 4.6, 4.8, 4.10;
- :func:`static_beam_speed_plot` - figures 4.2b, 4.3b;
- :func:`comparison_plot` - figure 4.12;
- :func:`chapter4_figures` - all of them into a directory.

Dataset figures (input: an :class:`xarray.Dataset` of the package schema):

- :func:`deflection_traces`, :func:`typical_traces_figure` - figure 3.7 (and 6.5);
- :func:`angle_texture_traces` - figure 5.2;
- :func:`feature_grid`, :func:`feature_contours` - figure 4.1.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from vibrissa._atomic import atomic_path

__all__ = [
    "PARAMETER_LABELS",
    "angle_texture_traces",
    "chapter4_figures",
    "classifier_figure",
    "comparison_plot",
    "deflection_traces",
    "error_histogram",
    "error_scatter",
    "feature_contours",
    "feature_grid",
    "prediction_scatter",
    "save_figure",
    "static_beam_speed_plot",
    "training_size_plot",
    "typical_traces_figure",
]

#: Axis labels of the result parameters.
PARAMETER_LABELS = {"radius_mm": "radial distance (mm)", "speed_mm_s": "speed (mm/s)"}

#: Short names of the chapter-4 classifiers, as in the legend of figure 4.12.
SHORT_NAMES = {
    "static_beam_measured": "Static (meas.)",
    "static_beam_fitted": "Static (fit)",
    "frequency": "Freq",
    "template": "Temp",
    "feature": "Feat",
    "naive_bayes_raw": "NB (raw)",
    "naive_bayes_velocity": "NB (vel.)",
}


def _axes(ax: Axes | None, figsize: tuple[float, float] = (5.0, 4.0)) -> Axes:
    if ax is not None:
        return ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def _check_parameter(parameter: str) -> str:
    if parameter not in PARAMETER_LABELS:
        raise ValueError(f"parameter must be one of {sorted(PARAMETER_LABELS)}, got {parameter!r}")
    return parameter


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: int = 200) -> Path:
    """Write ``fig`` as a PNG atomically (never a half-written file at ``path``).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (e.g. ``ax.figure``).
    path : path-like
        Destination; parent directories are created.
    dpi : int, default=200
        Resolution.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    return Path(path)


# ----------------------------------------------------------------------------- results
def _predictions(results: Mapping[str, Any], name: str) -> tuple[dict, dict]:
    pr = results.get("predictions")
    if not pr or name not in pr.get("classifiers", {}):
        raise ValueError(
            f"results hold no predictions for classifier {name!r} "
            "(run_chapter4(..., keep_predictions=True))"
        )
    true = {"radius_mm": np.asarray(pr["radius_mm_true"], float),
            "speed_mm_s": np.asarray(pr["speed_mm_s_true"], float)}
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
    _check_parameter(parameter)
    err = np.asarray(errors, dtype=float).ravel()
    ax = _axes(ax)
    ax.hist(err, bins=_bins(err) if bins is None else bins, color="0.35")
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
    ax = _axes(ax)
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
    _check_parameter(parameter)
    t = np.asarray(y_true, float).ravel()
    p = np.asarray(y_pred, float).ravel()
    if t.shape != p.shape:
        raise ValueError(f"y_true and y_pred differ in length: {t.size} vs {p.size}")
    ax = _axes(ax)
    pairs, counts = np.unique(np.column_stack([t, p]), axis=0, return_counts=True)
    ax.scatter(pairs[:, 0], pairs[:, 1], s=4 + 6 * np.sqrt(counts), alpha=0.5, color="C0",
               edgecolors="none")
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
        Output of :func:`~vibrissa.evaluate.chapter4.run_chapter4`.
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
    ax = _axes(ax)
    ax.errorbar(s, m, yerr=e, fmt="o-", ms=3, capsize=2, color="C0")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("contact speed (mm/s)")
    ax.set_ylabel("radial distance error (mm)")
    ax.set_title(f"{SHORT_NAMES.get(name, name)}: error per speed")
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
        Output of :func:`~vibrissa.evaluate.chapter4.run_chapter4`.
    name : str
        Classifier.
    parameter : {"radius_mm", "speed_mm_s"}
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    _check_parameter(parameter)
    pts: dict[float, tuple[float, float]] = {}
    full = _entry(results, name).get(parameter)
    if full is not None and full.get("mean") is not None:
        pts[100.0] = (full["mean"], full.get("std") or 0.0)
    for key, per in results.get("training_fractions", {}).items():
        e = (per.get(name) or {}).get(parameter)
        if e is not None and e.get("mean") is not None:
            pts[100.0 * float(key)] = (e["mean"], e.get("std") or 0.0)
    ax = _axes(ax)
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
        Output of :func:`~vibrissa.evaluate.chapter4.run_chapter4`.
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
    _check_parameter(parameter)
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
    ax = _axes(ax, figsize=(6.5, 4.0))
    width = 0.4 if thesis else 0.8
    shift = width / 2 if thesis else 0.0
    ax.bar(np.asarray(xs) - shift, ms, width, yerr=ss, capsize=3, color="0.6",
           edgecolor="0.2", label="this run")
    if thesis:
        tx, tm, ts = [], [], []
        for i, n in zip(xs, (names[i] for i in xs), strict=True):
            t = (thesis.get(n) or {}).get(parameter)
            if t and t.get("mean") is not None:
                tx.append(i + shift)
                tm.append(t["mean"])
                ts.append(t.get("std") or 0.0)
        if tx:
            ax.bar(tx, tm, width, yerr=ts, capsize=3, color="white", edgecolor="0.2",
                   hatch="///", label="thesis (table 4.7)")
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
        Output of :func:`~vibrissa.evaluate.chapter4.run_chapter4` with predictions.
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
        prediction_scatter(true["radius_mm"], pred["radius_mm"], parameter="radius_mm", ax=c,
                           title="(c) predicted vs true")
        return fig
    s_err = pred["speed_mm_s"] - true["speed_mm_s"]
    fig = Figure(figsize=(15.0, 6.5), layout="constrained")
    axs = fig.subplots(2, 3)
    error_histogram(r_err, parameter="radius_mm", ax=axs[0, 0], title=f"(a) {label}: radius")
    error_histogram(s_err, parameter="speed_mm_s", ax=axs[0, 1], title="(b) speed")
    error_scatter(r_err, s_err, ax=axs[0, 2], title="(c) errors per trial")
    prediction_scatter(true["radius_mm"], pred["radius_mm"], parameter="radius_mm",
                       ax=axs[1, 0], title="(d) radius: predicted vs true")
    prediction_scatter(true["speed_mm_s"], pred["speed_mm_s"], parameter="speed_mm_s",
                       ax=axs[1, 1], title="(e) speed: predicted vs true")
    axs[1, 2].set_axis_off()
    return fig


def _slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def chapter4_figures(
    results: Mapping[str, Any], out_dir: str | os.PathLike[str], dpi: int = 200
) -> dict[str, Path]:
    """Write every results figure of chapter 4 as PNG into ``out_dir``.

    Parameters
    ----------
    results : dict
        Output of :func:`~vibrissa.evaluate.chapter4.run_chapter4`.
    out_dir : path-like
        Directory (created if needed).
    dpi : int, default=200

    Returns
    -------
    dict of str to pathlib.Path
        Keys ``"errors/<name>"`` (per-classifier error figure, if predictions
        are present), ``"training_size/<name>"`` (if reduced sets were run),
        ``"comparison"`` (figure 4.12).
    """
    out = Path(out_dir)
    written: dict[str, Path] = {}
    has_pred = bool(results.get("predictions"))
    has_fractions = bool(results.get("training_fractions"))
    for name in results["classifiers"]:
        if has_pred:
            fig = classifier_figure(results, name)
            written[f"errors/{name}"] = save_figure(fig, out / f"errors_{_slug(name)}.png", dpi)
        if has_fractions:
            fig = Figure(figsize=(10.0, 3.8), layout="constrained")
            a, b = fig.subplots(1, 2)
            training_size_plot(results, name, "radius_mm", ax=a)
            training_size_plot(results, name, "speed_mm_s", ax=b)
            a.set_title(f"(a) {SHORT_NAMES.get(name, name)}: radius")
            b.set_title("(b) speed")
            written[f"training_size/{name}"] = save_figure(
                fig, out / f"training_size_{_slug(name)}.png", dpi
            )
    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    a, b = fig.subplots(1, 2)
    from vibrissa.evaluate.chapter4_report import THESIS_CHAPTER4, THESIS_COLUMNS

    t47 = THESIS_CHAPTER4["table_4_7"]
    thesis = {n: t47[c] for n, (c, _) in THESIS_COLUMNS.items() if c in t47}
    comparison_plot(results, "radius_mm", thesis=thesis, ax=a)
    comparison_plot(results, "speed_mm_s", thesis=thesis, ax=b)
    a.set_title("(a) radial distance")
    b.set_title("(b) speed")
    written["comparison"] = save_figure(fig, out / "comparison.png", dpi)
    return written


# ----------------------------------------------------------------------------- datasets
def _channel_index(ds: xr.Dataset, channel: int | str) -> int:
    if isinstance(channel, str):
        names = [str(c) for c in ds["channel"].values] if "channel" in ds.coords else []
        if channel not in names:
            raise ValueError(f"channel {channel!r} not in dataset channels {names}")
        return names.index(channel)
    n = ds.sizes.get("channel", 0)
    if isinstance(channel, bool) or not 0 <= int(channel) < n:
        raise ValueError(f"channel must lie in [0, {n - 1}], got {channel!r}")
    return int(channel)


def _require(ds: xr.Dataset, *coords: str) -> None:
    if not isinstance(ds, xr.Dataset) or "signal" not in ds.data_vars:
        raise ValueError("dataset must be an xarray.Dataset with a 'signal' variable")
    missing = [c for c in coords if c not in ds.coords and c not in ds.data_vars]
    if missing:
        raise ValueError(
            "dataset lacks the per-trial coordinate(s) " + ", ".join(repr(m) for m in missing)
        )


def _signal(ds: xr.Dataset) -> np.ndarray:
    return np.asarray(ds["signal"].transpose("trial", "channel", "time").values, dtype=float)


def _time_ms(ds: xr.Dataset) -> np.ndarray:
    if "time" in ds.coords:
        return 1000.0 * np.asarray(ds["time"].values, dtype=float)
    fs = float(ds.attrs.get("sample_rate_hz", 1000.0))
    return 1000.0 * np.arange(ds.sizes["time"]) / fs


def _nearest(values: np.ndarray, targets: Sequence[float]) -> list[float]:
    u = np.unique(values)
    return [float(u[np.argmin(np.abs(u - t))]) for t in targets]


def _spread(values: np.ndarray, k: int = 3) -> list[float]:
    u = np.unique(values)
    idx = np.unique(np.round(np.linspace(0, len(u) - 1, min(k, len(u)))).astype(int))
    return [float(u[i]) for i in idx]


def _median_value(values: np.ndarray) -> float:
    u = np.unique(values)
    return float(u[len(u) // 2])


def deflection_traces(
    ds: xr.Dataset,
    *,
    radial_distances_mm: Sequence[float] | None = None,
    speeds_mm_s: Sequence[float] | None = None,
    channel: int | str = 0,
    set_value: Any = None,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Typical deflection traces for a few radial distances and speeds (figure 3.7).

    One trace (the first trial, optionally of one recorded set) is drawn for each
    combination of the requested values; values snap to the nearest on the grid.

    Parameters
    ----------
    ds : xarray.Dataset
        Needs ``signal`` and the coordinates ``radial_distance_mm`` and ``speed_mm_s``.
    radial_distances_mm : sequence of float, optional
        Default: the smallest, middle and largest radial distance.
    speeds_mm_s : sequence of float, optional
        Default: the median speed.
    channel : int or str, default=0
        Channel index or name (e.g. ``"x"``).
    set_value : optional
        Restrict to trials whose ``set`` equals this.
    ax : matplotlib.axes.Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    _require(ds, "radial_distance_mm", "speed_mm_s")
    ch = _channel_index(ds, channel)
    r = np.asarray(ds["radial_distance_mm"].values, float)
    s = np.asarray(ds["speed_mm_s"].values, float)
    keep = np.ones(r.shape, bool)
    if set_value is not None:
        if "set" not in ds.coords:
            raise ValueError("set_value given but the dataset has no 'set' coordinate")
        keep = np.asarray(ds["set"].values) == set_value
        if not keep.any():
            raise ValueError(f"no trials with set == {set_value!r}")
    radii = _spread(r) if radial_distances_mm is None else _nearest(r, radial_distances_mm)
    speeds = [_median_value(s)] if speeds_mm_s is None else _nearest(s, speeds_mm_s)
    x = _signal(ds)
    t = _time_ms(ds)
    ax = _axes(ax, figsize=(6.0, 4.0))
    i = 0
    for sp in speeds:
        for rd in radii:
            idx = np.flatnonzero(keep & np.isclose(r, rd) & np.isclose(s, sp))
            if idx.size == 0:
                continue
            ax.plot(t, x[idx[0], ch], lw=1.0, color=f"C{i % 10}",
                    label=f"R = {rd:g} mm, S = {sp:g} mm/s")
            i += 1
    ax.set_xlabel("time from peak deflection (ms)")
    units = ds["signal"].attrs.get("units", "V")
    ax.set_ylabel(f"sensor output ({units})")
    if i:
        ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return ax


def typical_traces_figure(ds: xr.Dataset, *, channel: int | str = 0) -> Figure:
    """Figure 3.7 style pair: (a) three radial distances at the median speed, (b) three
    speeds at the median radial distance.

    Parameters
    ----------
    ds : xarray.Dataset
        Needs ``signal``, ``radial_distance_mm`` and ``speed_mm_s``.
    channel : int or str, default=0

    Returns
    -------
    matplotlib.figure.Figure
    """
    _require(ds, "radial_distance_mm", "speed_mm_s")
    r = np.asarray(ds["radial_distance_mm"].values, float)
    s = np.asarray(ds["speed_mm_s"].values, float)
    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    a, b = fig.subplots(1, 2)
    deflection_traces(ds, speeds_mm_s=[_median_value(s)], channel=channel, ax=a,
                      title="(a) radial distances at the median speed")
    deflection_traces(ds, radial_distances_mm=[_median_value(r)], speeds_mm_s=_spread(s),
                      channel=channel, ax=b, title="(b) speeds at the median radial distance")
    return fig


def angle_texture_traces(
    ds: xr.Dataset,
    *,
    speeds_mm_s: Sequence[float] | None = None,
    channel: int | str = 0,
    fig: Figure | None = None,
) -> np.ndarray:
    """Typical deflections per angle (rows) and texture (columns), colour by speed (figure 5.2).

    Parameters
    ----------
    ds : xarray.Dataset
        Needs ``signal`` and the coordinates ``angle_deg``, ``texture`` and ``speed_mm_s``.
    speeds_mm_s : sequence of float, optional
        Speeds drawn (nearest on the grid); default three spread over the range
        (the thesis shows 36, 72 and 108 mm/s).
    channel : int or str, default=0
    fig : matplotlib.figure.Figure, optional
        Figure to draw into (a new one if omitted).

    Returns
    -------
    numpy.ndarray of matplotlib.axes.Axes, shape (n_angles, n_textures)
    """
    _require(ds, "angle_deg", "texture", "speed_mm_s")
    ch = _channel_index(ds, channel)
    ang = np.asarray(ds["angle_deg"].values, float)
    tex = np.asarray(ds["texture"].values).astype(str)
    s = np.asarray(ds["speed_mm_s"].values, float)
    angles = np.unique(ang)
    textures = list(dict.fromkeys(tex.tolist()))  # order of first appearance
    speeds = _spread(s) if speeds_mm_s is None else _nearest(s, speeds_mm_s)
    x = _signal(ds)
    t = _time_ms(ds)
    if fig is None:
        fig = Figure(figsize=(2.6 * len(textures) + 1, 1.4 * len(angles) + 1),
                     layout="constrained")
    axs = np.asarray(fig.subplots(len(angles), len(textures), sharex=True, sharey=True,
                                  squeeze=False))
    for i, a in enumerate(angles):
        for j, tx in enumerate(textures):
            ax = axs[i, j]
            for k, sp in enumerate(speeds):
                idx = np.flatnonzero(np.isclose(ang, a) & (tex == tx) & np.isclose(s, sp))
                if idx.size:
                    ax.plot(t, x[idx[0], ch], lw=0.8, color=f"C{k % 10}",
                            label=f"{sp:g} mm/s")
            if i == 0:
                ax.set_title(tx)
            if j == 0:
                ax.set_ylabel(f"{a:g}°")
    axs[-1, 0].set_xlabel("time (ms)")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    if handles:
        axs[0, -1].legend(handles, labels, fontsize="x-small")
    return axs


def feature_grid(
    ds: xr.Dataset,
    *,
    channel: int | str = 0,
    threshold_v: float = 0.05,
    rest_v: float | None = 2.5,
) -> dict[str, np.ndarray]:
    """Mean peak deflection f1 (V) and contact duration f2 (ms) per grid cell (figure 4.1).

    Uses :func:`vibrissa.signal.peak_magnitude` (eq. 4.5) and
    :func:`vibrissa.signal.contact_duration` (eqs. 4.6-4.8) on one channel, and
    averages over the trials (sets) of each (radial distance, speed) cell.

    Parameters
    ----------
    ds : xarray.Dataset
        Needs ``signal``, ``radial_distance_mm``, ``speed_mm_s`` and ``sample_rate_hz``
        in its attrs.
    channel : int or str, default=0
    threshold_v : float, default=0.05
        Threshold ``gamma`` of the duration, V (thesis: 0.05 V).
    rest_v : float or None, default=2.5
        Sensor rest output, V.

    Returns
    -------
    dict
        ``radial_distance_mm`` (n_r,), ``speed_mm_s`` (n_s,), ``peak_v`` and
        ``duration_ms`` (n_r, n_s), NaN where a cell has no trial.
    """
    from vibrissa import signal as vsig

    _require(ds, "radial_distance_mm", "speed_mm_s")
    if "sample_rate_hz" not in ds.attrs:
        raise ValueError("dataset lacks the attr 'sample_rate_hz'")
    ch = _channel_index(ds, channel)
    x = _signal(ds)[:, ch]
    peak = vsig.peak_magnitude(x, rest_v=rest_v)
    dur = 1000.0 * vsig.contact_duration(
        x, float(ds.attrs["sample_rate_hz"]), threshold_v=threshold_v, rest_v=rest_v
    )
    r = np.asarray(ds["radial_distance_mm"].values, float)
    s = np.asarray(ds["speed_mm_s"].values, float)
    radii, ri = np.unique(r, return_inverse=True)
    speeds, si = np.unique(s, return_inverse=True)
    shape = (radii.size, speeds.size)
    n = np.zeros(shape)
    np.add.at(n, (ri, si), 1.0)
    out = {"radial_distance_mm": radii, "speed_mm_s": speeds}
    for key, v in (("peak_v", peak), ("duration_ms", dur)):
        acc = np.zeros(shape)
        np.add.at(acc, (ri, si), v)
        with np.errstate(invalid="ignore", divide="ignore"):
            out[key] = np.where(n > 0, acc / n, np.nan)
    return out


def feature_contours(
    ds: xr.Dataset,
    *,
    channel: int | str = 0,
    threshold_v: float = 0.05,
    axes: Sequence[Axes] | None = None,
    levels: int = 15,
) -> np.ndarray:
    """Contour maps of peak deflection (a) and contact duration (b) over speed x radius
    (figure 4.1).

    Parameters
    ----------
    ds : xarray.Dataset
        See :func:`feature_grid`.
    channel : int or str, default=0
    threshold_v : float, default=0.05
        Duration threshold, V.
    axes : pair of matplotlib.axes.Axes, optional
        Where to draw (a new two-panel figure if omitted).
    levels : int, default=15
        Contour levels.

    Returns
    -------
    numpy.ndarray of two matplotlib.axes.Axes
    """
    g = feature_grid(ds, channel=channel, threshold_v=threshold_v)
    if axes is None:
        fig = Figure(figsize=(11.0, 4.2), layout="constrained")
        axes = fig.subplots(1, 2)
    axes = np.asarray(axes, dtype=object).ravel()
    if axes.size != 2:
        raise ValueError(f"axes must hold two axes, got {axes.size}")
    s, r = g["speed_mm_s"], g["radial_distance_mm"]
    for ax, key, label, title in (
        (axes[0], "peak_v", "peak deflection f1 (V)", "(a) peak deflection magnitude"),
        (axes[1], "duration_ms", "contact duration f2 (ms)", "(b) deflection duration"),
    ):
        z = np.ma.masked_invalid(g[key])
        if r.size >= 2 and s.size >= 2:
            im = ax.contourf(s, r, z, levels=levels, cmap="gray")
        else:
            im = ax.pcolormesh(s, r, z, cmap="gray", shading="nearest")
        ax.figure.colorbar(im, ax=ax, label=label)
        ax.set_xlabel("contact speed (mm/s)")
        ax.set_ylabel("radial distance (mm)")
        ax.set_title(title)
    return axes
