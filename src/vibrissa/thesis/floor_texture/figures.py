"""Figures of the Roomba floor-texture experiment (thesis 6.2).

Confusion matrices beside the thesis' tables 6.1-6.3, the spectral templates
(figure 6.3), example recordings with the dropped packets marked (figure 6.2) and
the tip's path over the floor in each movement condition. Every function takes
``axes=None`` (a new Figure) and returns what it drew on.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa.evaluate.figures.common import save_figure
from vibrissa.signal import PACKET_SAMPLES, active_packets
from vibrissa.thesis.floor_texture.values import THESIS

__all__ = [
    "confusion_figure",
    "floor_figures",
    "signals_figure",
    "templates_figure",
    "trajectories_figure",
]


def _axes(axes: Any, rows: int, cols: int, figsize: tuple[float, float]) -> np.ndarray:
    if axes is not None:
        arr = np.atleast_1d(np.asarray(axes, dtype=object)).ravel()
        if arr.size != rows * cols:
            raise ValueError(f"need {rows * cols} axes, got {arr.size}")
        return arr.reshape(rows, cols)
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return np.asarray(fig.subplots(rows, cols, squeeze=False), dtype=object)


def _short(name: str) -> str:
    return {"rough-carpet": "rough c.", "smooth-carpet": "smooth c."}.get(name, name)


def confusion_figure(results: Mapping[str, Any], axes: Any = None) -> np.ndarray:
    """Row-normalised confusion matrices: this run (top row) and the thesis (bottom)."""
    conds = list(results["meta"]["conditions"])
    floors = list(results["meta"]["floors"])
    axs = _axes(axes, 2, len(conds), (3.1 * len(conds), 6.0))
    for j, c in enumerate(conds):
        for i, (cm, who, mc) in enumerate(
            (
                (results["confusion"].get(c), "this run", results["mean_correct"].get(c)),
                (THESIS["confusion"].get(c), "thesis", THESIS["mean_correct"].get(c)),
            )
        ):
            ax = axs[i, j]
            if cm is None:
                ax.set_axis_off()
                continue
            m = np.asarray(cm, dtype=float)
            n = m.sum(axis=1, keepdims=True)
            p = np.divide(m, n, out=np.zeros_like(m), where=n > 0)
            ax.imshow(p, cmap="gray_r", vmin=0, vmax=1)
            for (a, b), v in np.ndenumerate(p):
                ax.text(
                    b,
                    a,
                    f"{100 * v:.0f}",
                    ha="center",
                    va="center",
                    fontsize=7,
                    color="white" if v > 0.5 else "black",
                )
            ticks = np.arange(len(floors))
            ax.set_xticks(ticks, [_short(f) for f in floors], fontsize=7, rotation=45)
            ax.set_yticks(ticks, [_short(f) for f in floors], fontsize=7)
            ax.set_title(
                f"{c}, {who}: {100 * mc:.0f} %" if mc is not None else f"{c}, {who}", fontsize=9
            )
            if j == 0:
                ax.set_ylabel("true floor")
            if i == 1:
                ax.set_xlabel("predicted")
    return axs


def templates_figure(
    results: Mapping[str, Any], condition: str = "clockwise", axes: Any = None
) -> np.ndarray:
    """The spectral templates of one condition (figure 6.3), per channel."""
    tpl = results["templates"][condition]
    f = np.asarray(tpl["frequency_hz"])
    axs = _axes(axes, 1, 2, (9.0, 3.4)).ravel()
    for ch, ax in enumerate(axs):
        for floor, spec in tpl["spectra"].items():
            ax.semilogy(f[1:], np.asarray(spec)[ch][1:], lw=0.8, label=floor)
        ax.set_xlabel("frequency (Hz)")
        ax.set_title(f"channel {'xy'[ch]}", fontsize=9)
    axs[0].set_ylabel("mean |DFT| (V)")
    axs[0].legend(fontsize=7)
    return axs


def signals_figure(
    signals: Mapping[str, np.ndarray], sample_rate_hz: float, axes: Any = None
) -> np.ndarray:
    """One recording per floor (``signals[floor]``: (2, n) volts), dropped packets grey."""
    axs = _axes(axes, len(signals), 1, (8.0, 1.7 * len(signals) + 0.5)).ravel()
    for ax, (floor, x) in zip(axs, signals.items(), strict=True):
        t = np.arange(x.shape[1]) / sample_rate_hz
        for ch, colour in ((0, "C0"), (1, "C1")):
            ax.plot(t, x[ch], lw=0.4, color=colour, label="xy"[ch])
        keep = active_packets(x)
        for k in np.flatnonzero(~keep):
            ax.axvspan(
                k * PACKET_SAMPLES / sample_rate_hz,
                (k + 1) * PACKET_SAMPLES / sample_rate_hz,
                color="0.85",
                lw=0,
            )
        ax.set_ylabel(f"{_short(floor)} (V)", fontsize=8)
    axs[0].legend(fontsize=7, loc="upper right")
    axs[-1].set_xlabel("time (s)")
    return axs


def trajectories_figure(
    paths: Mapping[str, Mapping[str, np.ndarray]], axes: Any = None
) -> np.ndarray:
    """The tip's path over the floor, per condition.

    ``paths[c]`` holds ``x_mm``, ``y_mm`` (floor frame) and ``kept`` (bool per point: its
    packet was kept).
    """
    axs = _axes(axes, 1, len(paths), (3.2 * len(paths), 3.4)).ravel()
    for ax, (c, p) in zip(axs, paths.items(), strict=True):
        x, y, kept = (np.asarray(p[k]) for k in ("x_mm", "y_mm", "kept"))
        ax.plot(x, y, color="0.75", lw=3.0)
        ax.plot(np.where(kept, x, np.nan), np.where(kept, y, np.nan), color="C2", lw=1.2)
        ax.plot(x[:1], y[:1], "k^", ms=5)
        ax.set_aspect("equal")
        ax.set_title(c, fontsize=9)
        ax.set_xlabel("x (mm)")
    axs[0].set_ylabel("y (mm)")
    return axs


def floor_figures(
    results: Mapping[str, Any],
    out_dir: str | os.PathLike[str],
    *,
    signals: Mapping[str, np.ndarray] | None = None,
    sample_rate_hz: float | None = None,
    paths: Mapping[str, Mapping[str, np.ndarray]] | None = None,
    dpi: int = 150,
) -> dict[str, Path]:
    """Draw every figure into ``out_dir`` (PNG, atomically); return key -> path."""
    out = Path(out_dir)
    figs: dict[str, Path] = {}
    figs["confusion"] = save_figure(
        confusion_figure(results)[0, 0].figure, out / "confusion.png", dpi
    )
    if "clockwise" in results.get("templates", {}):
        figs["templates"] = save_figure(
            templates_figure(results)[0].figure, out / "templates.png", dpi
        )
    if signals and sample_rate_hz:
        figs["signals"] = save_figure(
            signals_figure(signals, sample_rate_hz)[0].figure, out / "signals.png", dpi
        )
    if paths:
        figs["trajectories"] = save_figure(
            trajectories_figure(paths)[0].figure, out / "trajectories.png", dpi
        )
    return figs
