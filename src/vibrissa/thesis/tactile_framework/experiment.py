"""Thesis 2.5 as a running system: where, reposition, what and a map, on a whisking robot.

The framework of figure 2.17 closes the loop over chapters 4-6 (see
:mod:`vibrissa.thesis.tactile_framework.protocol`): a whisking head in a box world, its Hall
stream through :class:`vibrissa.framework.TactilePipeline`, three policies (passive, active
repositioning, tip oracle) and a map of what was touched.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.reproduce.registry import Evaluation, Experiment, register
from vibrissa.thesis.tactile_framework.protocol import framework_protocol


@register
class TactileFramework(Experiment):
    """Thesis 2.5 (see the module docstring)."""

    name = "tactile-framework"
    chapter = 2
    title = "Section 2.5: the tactile framework as a closed loop on a whisking robot"
    description = (
        "a whisking head in a box world: tip/shaft from radial distance, repositioning after "
        "shaft contacts, angle and texture accumulated over contacts and whiskers, a texture "
        "map; passive, active and tip-oracle policies"
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """The full session, or the quick one."""
        return framework_protocol(quick=quick, seed=seed)

    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, int],
        workers: int | None = None,
    ) -> Evaluation:
        """Score the episodes, the curves and the maps."""
        from vibrissa.thesis.tactile_framework.evaluation import evaluate_framework

        return Evaluation(evaluate_framework(ds))

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
        """The curves and, with the dataset, one episode, the radial distances and the maps."""
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.thesis.tactile_framework.evaluation import build_touch_map
        from vibrissa.thesis.tactile_framework.figures import (
            POLICIES,
            curves_figure,
            episode_figure,
            radial_figure,
            touch_map_figure,
        )

        if not figures:
            return {}
        fig_dir = Path(out_dir) / "figures"
        out = {"curves": save_figure(curves_figure(results["curves"]), fig_dir / "curves.png")}
        if dataset is not None:
            counts = dataset["ep_episode"].to_series().value_counts()
            episode = int(counts.index[0]) if len(counts) else 0
            out["episode"] = save_figure(episode_figure(dataset, episode), fig_dir / "episode.png")
            out["radial"] = save_figure(radial_figure(dataset), fig_dir / "radial.png")
            maps = {n: build_touch_map(dataset, p).texture_labels() for p, n in enumerate(POLICIES)}
            out["touch_map"] = save_figure(
                touch_map_figure(
                    dataset["gt_texture_code"].values,
                    maps,
                    dataset.attrs["gt_origin_mm"],
                    float(dataset.attrs["gt_cell_mm"]),
                ),
                fig_dir / "touch_map.png",
            )
        return out

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """The report's Markdown body; ``baseline`` is not used."""
        from vibrissa.thesis.tactile_framework.report import markdown_framework

        return markdown_framework(results, figures)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Per policy: tip fraction, texture decisions at 0.99, the map; the transfer rows."""
        out: dict[str, Any] = {}
        for name, rows in results["curves"].items():
            at = next((r for r in rows if abs(r["threshold"] - 0.99) < 1e-9), rows[-1])
            out[name] = {
                "tip_fraction": results["policies"][name]["tip_fraction"],
                "texture_accuracy_at_0.99": at["accuracy"],
                "contacts_to_decision_at_0.99": at["contacts_to_decision"],
                "texture_accuracy_with_deadline_at_0.99": at.get("accuracy_with_deadline"),
                "contacts_with_deadline_at_0.99": at.get("contacts_with_deadline"),
                "texture_map_accuracy": results["maps"][name]["texture_accuracy"],
            }
        out["active_beats_passive_everywhere"] = results["comparison"][
            "active_beats_passive_everywhere"
        ]
        tr = results.get("transfer")
        if tr:
            out["transfer"] = {
                k: {m: tr[k][m] for m in ("tip_shaft_accuracy", "texture_accuracy")}
                for k in ("calibration", "xy_robot")
            }
        return out
