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

from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.reproduce.registry import Evaluation, Experiment, Option, register
from vibrissa.whisker.floors import floor_names


@register
class FloorTexture(Experiment):
    """Thesis 6.2 (see the module docstring)."""

    name = "floor-texture"
    chapter = 6
    title = "Thesis 6.2 reproduction: floor-texture discrimination on a Roomba"
    description = (
        "a whisker on a turning Roomba over four floors: spectral-template "
        "confusion matrices per movement condition, cross-condition, naive Bayes"
    )
    options = (
        Option(
            "floors",
            ",".join(floor_names()),
            "Floor textures to simulate and tell apart, comma-separated (thesis: all four).",
            minimum=2,
            choices=tuple(floor_names()),
            item="floor texture",
        ),
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """The Roomba session over all four floors (``quick``: fewer, shorter trials)."""
        from vibrissa.thesis.floor_texture.protocol import floor_protocol

        return floor_protocol(quick=quick, seed=seed)

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """The Roomba session over the floors chosen with ``--floors``."""
        from vibrissa.thesis.floor_texture.protocol import floor_protocol

        chosen = set(options.get("floors") or floor_names())
        return floor_protocol(
            quick=quick, seed=seed, floors=tuple(f for f in floor_names() if f in chosen)
        )

    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, Any],
        workers: int | None = None,
    ) -> Evaluation:
        """Run spectral templates, the cross-condition test and naive Bayes on ``ds``."""
        # a few fits on a few hundred windows: this process (``workers`` is not used)
        from vibrissa.thesis.floor_texture.evaluation import run_floor_texture

        return Evaluation(run_floor_texture(ds, seed=seed, progress=progress))

    def write_outputs(
        self,
        results: Mapping[str, Any],
        out_dir: Path,
        *,
        dataset: xr.Dataset | None,
        figures: bool,
        workers: int | None = None,
        artifacts: Mapping[str, Any] | None = None,
    ) -> dict[str, Path]:
        """Draw the results figures and, with ``dataset``, example signals and tip paths."""
        if not figures:
            return {}
        from vibrissa.thesis.floor_texture.figures import floor_figures
        from vibrissa.thesis.floor_texture.protocol import tip_paths

        signals, paths, fs = None, None, None
        if dataset is not None:
            fs = float(dataset.attrs["sample_rate_hz"])
            signals = _example_signals(dataset)
            paths = tip_paths(dataset)
        return floor_figures(
            results, Path(out_dir) / "figures", signals=signals, sample_rate_hz=fs, paths=paths
        )

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """The floor-texture Markdown body; ``baseline`` is not used."""
        from vibrissa.thesis.floor_texture.report import markdown_floor_texture

        return markdown_floor_texture(results, figures, baseline)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Confusion matrices, mean correct, both cross-condition scores and naive Bayes'."""
        cross = results["cross_condition"]
        return {
            "confusion": results["confusion"],
            "mean_correct": results["mean_correct"],
            "cross_condition": {
                "cw_on_ccw": cross.get("cw_on_ccw"),
                "ccw_on_cw": cross.get("ccw_on_cw"),
            },
            "naive_bayes": {"mean_correct": results["naive_bayes"]["mean_correct"]},
        }

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        """Mean correct per condition (templates, thesis, naive Bayes), cross-condition."""
        from rich.table import Table

        from vibrissa.thesis.floor_texture.report import percent
        from vibrissa.thesis.floor_texture.values import THESIS

        table = Table(title="Mean correct (thesis 6.2)")
        for col in ("condition", "spectral templates", "thesis", "naive Bayes"):
            table.add_column(col, justify="left" if col == "condition" else "right")
        for c, v in summary["mean_correct"].items():
            table.add_row(
                c,
                percent(v),
                percent(THESIS["mean_correct"].get(c)),
                percent(summary["naive_bayes"]["mean_correct"].get(c)),
            )
        cross = summary["cross_condition"]
        table.add_row(
            "cw on ccw / ccw on cw",
            f"{percent(cross['cw_on_ccw'])} / {percent(cross['ccw_on_cw'])}",
            percent(THESIS["cross_condition"]),
            "",
        )
        return table


def _example_signals(ds: xr.Dataset, condition: str = "clockwise") -> dict[str, np.ndarray]:
    """The first trial of each floor in ``condition`` (figure 6.2)."""
    out: dict[str, np.ndarray] = {}
    for i in np.flatnonzero(ds["condition"].values == condition):
        f = str(ds["floor"].values[i])
        out.setdefault(f, ds["signal"].values[i])
    return out
