"""Figures of the tactile framework: one episode per policy, the touch maps, the curves."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure

from vibrissa.data.schema import TEXTURE_CODES

__all__ = ["curves_figure", "episode_figure", "radial_figure", "touch_map_figure"]

#: One colour per texture code (smooth to coarse) and the policies' colours.
TEXTURE_COLOURS = ("#9e9e9e", "#4c9be8", "#f2a93b", "#b8403a")
POLICY_COLOURS = {"passive": "#7f7f7f", "active": "#1f77b4", "oracle": "#2ca02c"}
POLICIES = ("passive", "active", "oracle")


def _draw_world(ax: Any, world: Mapping[str, Any]) -> None:
    """The boxes and the room, each face in its texture's colour."""
    faces = []
    for b in world.get("boxes", []):
        v = np.asarray(b["vertices_mm"], dtype=float)
        ax.fill(v[:, 0], v[:, 1], color="#eeeeee", zorder=0)
        for k, tex in enumerate(b["textures"]):
            faces.append((v[k], v[(k + 1) % len(v)], tex))
    room = world.get("room")
    if room is not None:
        x0, y0, x1, y1 = room
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        for k, tex in enumerate(world.get("wall_textures", ["aluminium"] * 4)):
            faces.append((np.asarray(corners[k]), np.asarray(corners[(k + 1) % 4]), tex))
    for a, b, tex in faces:
        ax.plot([a[0], b[0]], [a[1], b[1]], color=TEXTURE_COLOURS[TEXTURE_CODES[tex]], lw=3)


def episode_figure(ds: xr.Dataset, episode: int) -> Figure:
    """One episode under each policy: path, contacts (tip / shaft) and repositioning moves."""
    world = json.loads(ds.attrs["world"])
    fig = Figure(figsize=(13.0, 4.6), layout="constrained")
    axes = fig.subplots(1, 3, sharex=True, sharey=True)
    pol = ds["ep_policy"].values
    ep = ds["ep_episode"].values
    mp, me = ds["move_policy"].values, ds["move_episode"].values
    for p, (ax, name) in enumerate(zip(axes, POLICIES, strict=True)):
        _draw_world(ax, world)
        m = (mp == p) & (me == episode)
        x, y, kind = ds["move_x_mm"].values[m], ds["move_y_mm"].values[m], ds["move_kind"].values[m]
        ax.plot(x, y, "-", color="k", lw=0.8, label="base path")
        rep = np.flatnonzero(kind == 1)
        for j in rep:
            if j > 0:
                ax.annotate(
                    "",
                    (x[j], y[j]),
                    (x[j - 1], y[j - 1]),
                    arrowprops={"arrowstyle": "->", "color": "#d62728", "lw": 1.2},
                )
        c = (pol == p) & (ep == episode)
        tip = ds["ep_tip"].values[c].astype(bool)
        px, py = ds["ep_point_x_mm"].values[c], ds["ep_point_y_mm"].values[c]
        ax.scatter(px[tip], py[tip], s=18, color="#1f77b4", label="called tip", zorder=3)
        ax.scatter(
            px[~tip], py[~tip], s=22, marker="x", color="#d62728", label="called shaft", zorder=3
        )
        if x.size:
            pad = 250.0
            ax.set_xlim(
                min(x.min(), px.min(initial=x.min())) - pad,
                max(x.max(), px.max(initial=x.max())) + pad,
            )
            ax.set_ylim(
                min(y.min(), py.min(initial=y.min())) - pad,
                max(y.max(), py.max(initial=y.max())) + pad,
            )
        ax.set_aspect("equal")
        ax.set_title(f"{name}: {int(c.sum())} contacts, {len(rep)} repositions")
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"Episode {episode}: red arrows are repositioning moves (2.5.1's microsaccade)")
    return fig


def touch_map_figure(
    truth_texture: np.ndarray,
    maps: Mapping[str, np.ndarray],
    origin_mm: Sequence[float],
    cell_mm: float,
) -> Figure:
    """Ground-truth wall textures beside each policy's touched-cell textures."""
    n = 1 + len(maps)
    fig = Figure(figsize=(3.6 * n, 3.8), layout="constrained")
    axes = fig.subplots(1, n, sharex=True, sharey=True)
    cmap = ListedColormap(["white", *TEXTURE_COLOURS])
    ext = (
        origin_mm[0],
        origin_mm[0] + truth_texture.shape[0] * cell_mm,
        origin_mm[1],
        origin_mm[1] + truth_texture.shape[1] * cell_mm,
    )
    panels = [("ground truth (faces)", truth_texture), *maps.items()]
    for ax, (title, grid) in zip(axes, panels, strict=True):
        ax.imshow(
            np.asarray(grid).T + 1,
            origin="lower",
            extent=ext,
            cmap=cmap,
            vmin=0,
            vmax=4,
            interpolation="nearest",
        )
        ax.set_title(title)
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    handles = [
        axes[0].plot([], [], "s", color=c, label=name)[0]
        for name, c in zip(TEXTURE_CODES, TEXTURE_COLOURS, strict=True)
    ]
    fig.legend(handles=handles, loc="outside right center", fontsize=8)
    return fig


def curves_figure(curves: Mapping[str, Sequence[Mapping[str, Any]]]) -> Figure:
    """Speed-accuracy: accuracy against contacts to decision, per threshold.

    Solid lines score every episode (one that has not reached the threshold decides when its
    budget runs out); dashed lines only the episodes that reached the threshold.
    """
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    for name in POLICIES:
        col = POLICY_COLOURS[name]
        dl = [r for r in curves.get(name, []) if r.get("accuracy_with_deadline") is not None]
        if dl:
            ax_a.plot(
                [r["contacts_with_deadline"] for r in dl],
                [r["accuracy_with_deadline"] for r in dl],
                "o-",
                color=col,
                label=f"{name}, with the deadline",
            )
        rows = [r for r in curves.get(name, []) if r["accuracy"] is not None]
        if not rows:
            continue
        ax_a.plot(
            [r["contacts_to_decision"] for r in rows],
            [r["accuracy"] for r in rows],
            "s--",
            color=col,
            alpha=0.6,
            markersize=4,
            label=f"{name}, decided episodes only",
        )
        ax_b.plot(
            [r["threshold"] for r in rows],
            [r["decided_fraction"] for r in rows],
            "o-",
            color=col,
            label=name,
        )
    ax_a.set(
        xlabel="contacts to decision (mean)",
        ylabel="texture accuracy at decision",
        title="(a) speed-accuracy over decision thresholds",
        ylim=(0, 1.05),
    )
    ax_b.set(
        xlabel="decision threshold",
        ylabel="episodes that reached the threshold",
        title="(b) episodes deciding before the deadline",
        ylim=(0, 1.05),
        xscale="logit",
    )
    ax_a.legend(fontsize=7)
    ax_b.legend(fontsize=8)
    return fig


def radial_figure(ds: xr.Dataset) -> Figure:
    """Where: each episode contact's estimated radial distance against the truth, and p_tip."""
    kind = ds["ep_truth_kind"].values
    sel = kind > 0
    true_r = ds["ep_truth_radial_mm"].values[sel]
    est_r = ds["ep_est_radial_mm"].values[sel]
    p_tip = ds["ep_p_tip"].values[sel]
    tip = kind[sel] == 1
    params = json.loads(ds.attrs.get("protocol_params", "{}"))
    length = float(json.loads(ds.attrs["whisker"])["length_mm"])
    tip_r = length - float(params.get("tip_zone_mm", 5.0))
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax_a, ax_b = fig.subplots(1, 2)
    rng = np.random.default_rng(0)  # a little jitter so that equal classes stay visible
    jitter = rng.uniform(-1.5, 1.5, est_r.size)
    ax_a.scatter(true_r[~tip], est_r[~tip] + jitter[~tip], s=12, color="#d62728", label="corner")
    ax_a.scatter(true_r[tip], est_r[tip] + jitter[tip], s=12, color="#1f77b4", label="face (tip)")
    lo = float(min(true_r.min(initial=length), est_r.min(initial=length))) - 10.0
    ax_a.plot([lo, length + 5], [lo, length + 5], color="k", lw=0.8)
    ax_a.axhline(tip_r, color="k", ls=":", lw=0.8)
    ax_a.set(
        xlabel="true radial distance (mm)",
        ylabel="estimated radial distance (mm)",
        title="(a) where: radial distance of each contact",
    )
    ax_a.legend(fontsize=8)
    bins = np.linspace(0.0, 1.0, 21)
    ax_b.hist(p_tip[~tip], bins=bins, color="#d62728", alpha=0.7, label="corner")
    ax_b.hist(p_tip[tip], bins=bins, color="#1f77b4", alpha=0.7, label="face (tip)")
    ax_b.axvline(0.5, color="k", ls=":", lw=0.8)
    ax_b.set(xlabel="p_tip", ylabel="contacts", title="(b) the tip-or-shaft posterior")
    ax_b.legend(fontsize=8)
    return fig
