"""Thesis 6.2: floor-texture discrimination with a whisker on a Roomba.

A SCRATCHbot whisker dragged over rough carpet, vinyl, smooth carpet and tarmac
while the base turns clockwise, anticlockwise or runs its 'spot' spiral; 4 trials of
16 s at 2 kHz per floor and condition; quiet packets dropped, 800-sample windows,
odd train / even test; spectral templates (tables 6.1-6.3), the cross-condition test
and stationary naive Bayes.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.reproduce.registry import Experiment, Option, register
from vibrissa.whisker.floors import floor_names


@register
class FloorTexture(Experiment):
    """Thesis 6.2 (see the module docstring)."""

    name = "floor-texture"
    chapter = 6
    title = "Thesis 6.2 reproduction: floor-texture discrimination on a Roomba"
    description = ("a whisker on a turning Roomba over four floors: spectral-template "
                   "confusion matrices per movement condition, cross-condition, naive Bayes")
    options = (Option("floors", ",".join(floor_names()),
                      "Floor textures to simulate and tell apart, comma-separated (thesis: "
                      "all four).", minimum=2, choices=tuple(floor_names()),
                      item="floor texture"),)

    def protocol(self, quick: bool, seed: int) -> Any:
        from vibrissa.experiments.floor import floor_protocol

        return floor_protocol(quick=quick, seed=seed)

    def protocol_for(self, quick: bool, seed: int, options: Mapping[str, Any]) -> Any:
        from vibrissa.experiments.floor import floor_protocol

        chosen = set(options.get("floors") or floor_names())
        return floor_protocol(quick=quick, seed=seed,
                              floors=tuple(f for f in floor_names() if f in chosen))

    def evaluate(self, ds: xr.Dataset, *, seed: int, progress: Callable | None,
                 options: Mapping[str, Any], workers: int | None = None) -> dict[str, Any]:
        # a few fits on a few hundred windows: this process (``workers`` is not used)
        from vibrissa.evaluate.floor_texture import run_floor_texture

        return run_floor_texture(ds, seed=seed, progress=progress)

    def write_outputs(self, results: Mapping[str, Any], out_dir: Path, *,
                      dataset: xr.Dataset | None, figures: bool,
                      workers: int | None = None) -> dict[str, Path]:
        if not figures:
            return {}
        from vibrissa.evaluate.figures.floor_texture import floor_figures

        signals, paths, fs = None, None, None
        if dataset is not None:
            fs = float(dataset.attrs["sample_rate_hz"])
            signals = _example_signals(dataset)
            paths = _tip_paths(dataset)
        return floor_figures(results, Path(out_dir) / "figures", signals=signals,
                             sample_rate_hz=fs, paths=paths)

    def report_sections(self, results: Mapping[str, Any], figures: Mapping[str, Path],
                        baseline: Mapping[str, Any] | None) -> str:
        from vibrissa.evaluate.floor_texture_report import markdown_floor_texture

        return markdown_floor_texture(results, figures, baseline)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        cross = results["cross_condition"]
        return {
            "confusion": results["confusion"],
            "mean_correct": results["mean_correct"],
            "cross_condition": {"cw_on_ccw": cross.get("cw_on_ccw"),
                                "ccw_on_cw": cross.get("ccw_on_cw")},
            "naive_bayes": {"mean_correct": results["naive_bayes"]["mean_correct"]},
        }

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        from rich.table import Table

        from vibrissa.evaluate.floor_texture import THESIS
        from vibrissa.evaluate.floor_texture_report import percent

        table = Table(title="Mean correct (thesis 6.2)")
        for col in ("condition", "spectral templates", "thesis", "naive Bayes"):
            table.add_column(col, justify="left" if col == "condition" else "right")
        for c, v in summary["mean_correct"].items():
            table.add_row(c, percent(v), percent(THESIS["mean_correct"].get(c)),
                          percent(summary["naive_bayes"]["mean_correct"].get(c)))
        cross = summary["cross_condition"]
        table.add_row("cw on ccw / ccw on cw",
                      f"{percent(cross['cw_on_ccw'])} / {percent(cross['ccw_on_cw'])}",
                      percent(THESIS["cross_condition"]), "")
        return table


def _example_signals(ds: xr.Dataset, condition: str = "clockwise") -> dict[str, np.ndarray]:
    """The first trial of each floor in ``condition`` (figure 6.2)."""
    out = {}
    for i in np.flatnonzero(ds["condition"].values == condition):
        f = str(ds["floor"].values[i])
        out.setdefault(f, ds["signal"].values[i])
    return out


def _tip_paths(ds: xr.Dataset) -> dict[str, dict[str, np.ndarray]]:
    """The tip's path in the first trial of each condition, from the same random stream
    the simulation drew the base's motion from, with each point's packet kept or not."""
    import json

    from vibrissa.experiments.streams import TRIALS, stream
    from vibrissa.robots.roomba import Roomba, base_motion, tip_path
    from vibrissa.signal import PACKET_SAMPLES, active_packets

    params = json.loads(ds.attrs["protocol_params"])
    roomba = Roomba(**{k: tuple(v) if isinstance(v, list) else v
                       for k, v in params["roomba"].items()})
    length = float(json.loads(ds.attrs["whisker"])["length_mm"])
    fs = float(ds.attrs["sample_rate_hz"])
    paths: dict[str, dict[str, np.ndarray]] = {}
    for i, c in enumerate(ds["condition"].values.tolist()):
        if c in paths:
            continue
        rng = np.random.default_rng(stream(int(params["seed"]), TRIALS, i))
        t, fwd, yaw = base_motion(roomba, c, float(params["duration_s"]), rng)
        x, y = tip_path(roomba, length, t, fwd, yaw)
        keep = active_packets(ds["signal"].values[i])
        k = np.minimum((t * fs).astype(int) // PACKET_SAMPLES, keep.size - 1)
        paths[c] = {"x_mm": x, "y_mm": y, "kept": keep[k]}
    return paths
