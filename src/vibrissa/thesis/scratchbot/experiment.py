"""Chapter 6.3: radial distance and whisk speed on SCRATCHbot, a whisking robot.

A stationary head whisks one whisker into a vertical pole at 70, 100 and 130 mm
and 2, 4 and 6 Hz (:mod:`vibrissa.thesis.scratchbot.protocol`). Per condition the
peak deflection and the contact duration of every whisk (the chapter-4 features,
4.3.4: peak magnitude and the supra-0.05 V run about the peak); the chapter-4
feature and template classifiers trained on the odd whisks and tested on the
even ones. The report also draws figure 3.9 (rapid cessation of protraction
with two gains, :func:`vibrissa.robots.whisking.figure_3_9`). ``--n-seeds`` sessions
(default 5, seeds ``seed .. seed + n - 1``): every figure is the mean over them, with
its spread under the results' ``spread``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.reproduce.registry import Evaluation, Experiment, Option, register
from vibrissa.thesis.scratchbot.protocol import scratchbot_protocol

#: Sessions of a run unless ``--n-seeds`` says otherwise.
DEFAULT_N_SEEDS = 5


@register
class Scratchbot(Experiment):
    """Thesis 6.3 (see the module docstring)."""

    name = "scratchbot"
    chapter = 6
    title = "Chapter 6.3 reproduction: radial distance and whisk speed on SCRATCHbot"
    description = (
        "SCRATCHbot whisking into a pole at 3 distances x 3 whisk frequencies: "
        "peak deflection, contact duration, feature and template classifiers "
        "(figure 6.5); RCP gating (figure 3.9)"
    )

    options = (
        Option(
            "n_seeds",
            DEFAULT_N_SEEDS,
            "Sessions, with seeds seed..seed+n-1; every figure is the mean over them "
            "with its spread (default 5; they differ only in the sensor noise).",
        ),
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """SCRATCHbot's grid with 12 whisks per condition (``quick``: 4), in 5 sessions."""
        return scratchbot_protocol(quick=quick, seed=seed, n_seeds=DEFAULT_N_SEEDS)

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """SCRATCHbot's grid in ``--n-seeds`` sessions."""
        return scratchbot_protocol(
            quick=quick, seed=seed, n_seeds=int(options.get("n_seeds") or DEFAULT_N_SEEDS)
        )

    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, int],
        workers: int | None = None,
    ) -> Evaluation:
        """Evaluate ``ds`` and simulate figure 3.9's panels (kept as artifacts)."""
        from vibrissa.robots.whisking import HALF_RANGE_FRACTION, figure_3_9
        from vibrissa.thesis.scratchbot.evaluation import evaluate_scratchbot_sessions

        panels = figure_3_9()
        results = evaluate_scratchbot_sessions(
            ds,
            figure_3_9={k: p.summary() for k, p in panels.items()},
            half_range_fraction=HALF_RANGE_FRACTION,
            progress=progress,
        )
        return Evaluation(results, {"figure_3_9": panels})

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
        """Draw figures 6.5 and 3.9 and, with ``dataset``, whisk and closed-loop traces."""
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.evaluate.figures.whisking import whisk_trajectories_figure
        from vibrissa.robots.whisking import figure_3_9
        from vibrissa.thesis.scratchbot.figures import gating_figure, scratchbot_features_figure

        if not figures:
            return {}
        fig_dir = Path(out_dir) / "figures"
        out = {
            "features": save_figure(
                scratchbot_features_figure(results["conditions"]),
                fig_dir / "scratchbot_features.png",
            )
        }
        panels = []
        # figure 3.9's runs from this evaluation, or simulated again for a redrawn report
        for key, v in ((artifacts or {}).get("figure_3_9") or figure_3_9()).items():
            a = v.run
            panels.append(
                {
                    "title": f"({key}) sigma_z = {v.sigma_z:g}, tau_z = T_w x {v.tau_z_periods:g}",
                    "time_s": a.time_s,
                    "angle_deg": a.angle_deg,
                    "gating": a.gating,
                    "obstacle_deg": a.obstacle_deg,
                }
            )
        out["figure_3_9"] = save_figure(gating_figure(panels), fig_dir / "figure_3_9.png")
        if dataset is not None and "run_angle_deg" in dataset:
            p = dict(
                zip(
                    dataset["condition"].values.tolist(),
                    range(dataset.sizes["condition"]),
                    strict=True,
                )
            )
            conds = results["conditions"]
            pick = [i for i, c in enumerate(conds) if c["radial_distance_mm"] == 100.0] or list(
                range(min(3, len(conds)))
            )
            pick = [p[i] for i in pick][:3]
            t = dataset["run_time"].values
            fig = whisk_trajectories_figure(
                t,
                dataset["run_angle_deg"].values[pick],
                dataset["run_raw_v"].values[pick],
                dataset["run_force_n"].values[pick],
                [
                    f"R = {conds[i]['radial_distance_mm']:g} mm, S = "
                    f"{conds[i]['whisk_frequency_hz']:g} Hz"
                    for i in pick
                ],
            )
            out["trajectories"] = save_figure(fig, fig_dir / "whisk_trajectories.png")
        if dataset is not None and "rcp_gating" in dataset:
            from vibrissa.robots.whisking import HALF_RANGE_FRACTION

            n = dataset.sizes["rcp_setting"]
            fig = whisk_trajectories_figure(
                dataset["rcp_time"].values,
                dataset["rcp_angle_deg"].values,
                dataset["rcp_deflection"].values * HALF_RANGE_FRACTION * 5.0,
                dataset["rcp_force_n"].values,
                [
                    f"sigma_z = {dataset['rcp_sigma_z'].values[i]:g}, tau_z = T_w x "
                    f"{dataset['rcp_tau_z_periods'].values[i]:g}"
                    for i in range(n)
                ],
                gating=dataset["rcp_gating"].values,
                signal_label="Hall x from rest (V)",
            )
            out["closed_loop"] = save_figure(fig, fig_dir / "closed_loop.png")
        return out

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """SCRATCHbot's report Markdown body; ``baseline`` is not used."""
        from vibrissa.thesis.scratchbot.report import markdown_scratchbot

        return markdown_scratchbot(results, figures)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Each condition's features, the classifiers, the relations and the closed loop."""
        return {
            "conditions": [
                {
                    k: c[k]
                    for k in (
                        "radial_distance_mm",
                        "whisk_frequency_hz",
                        "peak_deflection_v",
                        "contact_duration_s",
                    )
                }
                for c in results["conditions"]
            ],
            "classifiers": results["classifiers"],
            "relations": results["relations"],
            "closed_loop": results.get("closed_loop"),
        }
