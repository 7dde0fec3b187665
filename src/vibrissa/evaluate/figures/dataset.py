"""Dataset figures: figures 3.7, 4.1 and 5.2.

The input is an :class:`xarray.Dataset` of the package schema, simulated or imported.

Every plotting function takes ``ax=None`` (or ``axes``) and returns the axes it drew on;
:func:`typical_traces_figure` composes several and returns its Figure.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from vibrissa.evaluate.figures.common import new_axes

__all__ = [
    "angle_texture_traces",
    "deflection_traces",
    "feature_contours",
    "feature_grid",
    "typical_traces_figure",
]


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
    ax = new_axes(ax, figsize=(6.0, 4.0))
    i = 0
    for sp in speeds:
        for rd in radii:
            idx = np.flatnonzero(keep & np.isclose(r, rd) & np.isclose(s, sp))
            if idx.size == 0:
                continue
            ax.plot(
                t,
                x[idx[0], ch],
                lw=1.0,
                color=f"C{i % 10}",
                label=f"R = {rd:g} mm, S = {sp:g} mm/s",
            )
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
    """Figure 3.7 style pair of panels over radial distance and speed.

    (a) three radial distances at the median speed, (b) three speeds at the median radial
    distance.

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
    deflection_traces(
        ds,
        speeds_mm_s=[_median_value(s)],
        channel=channel,
        ax=a,
        title="(a) radial distances at the median speed",
    )
    deflection_traces(
        ds,
        radial_distances_mm=[_median_value(r)],
        speeds_mm_s=_spread(s),
        channel=channel,
        ax=b,
        title="(b) speeds at the median radial distance",
    )
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
        fig = Figure(figsize=(2.6 * len(textures) + 1, 1.4 * len(angles) + 1), layout="constrained")
    axs = np.asarray(
        fig.subplots(len(angles), len(textures), sharex=True, sharey=True, squeeze=False)
    )
    for i, a in enumerate(angles):
        for j, tx in enumerate(textures):
            ax = axs[i, j]
            for k, sp in enumerate(speeds):
                idx = np.flatnonzero(np.isclose(ang, a) & (tex == tx) & np.isclose(s, sp))
                if idx.size:
                    ax.plot(t, x[idx[0], ch], lw=0.8, color=f"C{k % 10}", label=f"{sp:g} mm/s")
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
    """Contour maps of peak deflection (a) and contact duration (b) over speed x radius.

    Figure 4.1.

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
