"""Thesis 6.2: floor-texture discrimination with a whisker on a Roomba.

A SCRATCHbot whisker dragged over rough carpet, vinyl, smooth carpet and tarmac
while the base turns clockwise, anticlockwise or runs its 'spot' spiral; 4 trials of
16 s at 2 kHz per floor and condition; quiet packets dropped, 800-sample windows,
odd train / even test; spectral templates (tables 6.1-6.3), the cross-condition test
and stationary naive Bayes. The session is repeated with ``--n-seeds`` seeds (seed ..
seed + n - 1; ``--quick`` at most :data:`QUICK_MAX_SEEDS`) and every figure is the mean
over them with its spread (results key ``spread``).
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

#: Sessions of a ``--quick`` run at most (each quick session takes ~35 s on 2 cores).
QUICK_MAX_SEEDS = 2


def sessions(quick: bool, n_seeds: int) -> int:
    """Sessions a run simulates: ``n_seeds``, at most :data:`QUICK_MAX_SEEDS` if ``quick``."""
    return min(int(n_seeds), QUICK_MAX_SEEDS) if quick else int(n_seeds)


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
        Option(
            "n_seeds",
            5,
            "Sessions, with seeds seed .. seed+n-1: each figure is their mean, with its "
            f"spread (--quick: at most {QUICK_MAX_SEEDS}).",
        ),
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """One Roomba session over all four floors (``quick``: fewer, shorter trials).

        One session: ``vibrissa reproduce --list`` counts the trials of one seed.
        """
        from vibrissa.thesis.floor_texture.protocol import floor_protocol

        return floor_protocol(quick=quick, seed=seed)

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """The Roomba sessions over the floors chosen with ``--floors``, ``--n-seeds`` of them."""
        from vibrissa.thesis.floor_texture.protocol import floor_protocol

        chosen = set(options.get("floors") or floor_names())
        return floor_protocol(
            quick=quick,
            seed=seed,
            floors=tuple(f for f in floor_names() if f in chosen),
            n_seeds=sessions(quick, options.get("n_seeds", 1)),
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
        """Spectral templates, the cross-condition test and naive Bayes, session by session."""
        # a few fits on a few hundred windows: this process (``workers`` is not used)
        from vibrissa.thesis.floor_texture.evaluation import run_floor_texture_seeds

        return Evaluation(run_floor_texture_seeds(ds, progress=progress))

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
        """Confusion matrices, mean correct, both cross-condition scores and naive Bayes'.

        Means over the sessions; ``std`` holds the standard deviations of the mean-correct
        and cross-condition figures (``None`` with one session).
        """
        cross = results["cross_condition"]
        spread = results.get("spread") or {}

        def std(*path: str) -> float | None:
            node: Any = spread
            for p in path:
                node = node.get(p) if isinstance(node, Mapping) else None
            return node.get("std") if isinstance(node, Mapping) else None

        return {
            "n_seeds": results["meta"].get("n_seeds", 1),
            "confusion": results["confusion"],
            "mean_correct": results["mean_correct"],
            "cross_condition": {
                "cw_on_ccw": cross.get("cw_on_ccw"),
                "ccw_on_cw": cross.get("ccw_on_cw"),
            },
            "naive_bayes": {"mean_correct": results["naive_bayes"]["mean_correct"]},
            "std": {
                "mean_correct": {c: std("mean_correct", c) for c in results["mean_correct"]},
                "cross_condition": {
                    k: std("cross_condition", k) for k in ("cw_on_ccw", "ccw_on_cw")
                },
            },
        }

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        """Mean correct per condition (templates, thesis, naive Bayes), cross-condition."""
        from rich.table import Table

        from vibrissa.thesis.floor_texture.report import percent, percent_pm
        from vibrissa.thesis.floor_texture.values import THESIS

        n = summary.get("n_seeds", 1)
        std = summary.get("std", {})
        table = Table(title=f"Mean correct (thesis 6.2), mean ± std over {n} seed(s)")
        for col in ("condition", "spectral templates", "thesis", "naive Bayes"):
            table.add_column(col, justify="left" if col == "condition" else "right")
        for c, v in summary["mean_correct"].items():
            table.add_row(
                c,
                percent_pm(v, std.get("mean_correct", {}).get(c)),
                percent(THESIS["mean_correct"].get(c)),
                percent(summary["naive_bayes"]["mean_correct"].get(c)),
            )
        cross = summary["cross_condition"]
        cstd = std.get("cross_condition", {})
        table.add_row(
            "cw on ccw / ccw on cw",
            f"{percent_pm(cross['cw_on_ccw'], cstd.get('cw_on_ccw'))} / "
            f"{percent_pm(cross['ccw_on_cw'], cstd.get('ccw_on_cw'))}",
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
