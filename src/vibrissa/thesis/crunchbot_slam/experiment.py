"""Chapter 6.5: CrunchBot's tactile SLAM, twenty runs of six minutes in three mapping modes.

The robot (:mod:`vibrissa.thesis.crunchbot_slam.protocol`) runs the 6.5.3 FSM in the SLAM arena;
each run's sensor log is mapped by the particle filter in the modes ``blob``,
``geometric`` and ``template`` (:mod:`vibrissa.thesis.crunchbot_slam.evaluation`; the
modes share the log, since the behaviour never reads the map), scored by eq. 6.3 against
the smoothed ground truth, by the trajectory error against the true pose, with the radial-distance
errors, the floor-texture accuracy of an extra run in the tiled arena and the
classifiers' latencies beside the thesis' numbers.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from vibrissa.evaluate.spread import spread_leaf
from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.reproduce.registry import Evaluation, Experiment, Option, register
from vibrissa.slam.error import arena_mask
from vibrissa.thesis.crunchbot_slam.values import MAP_SIZE_M, THESIS

#: Defaults of the options left empty: (full, quick).
#: (full, quick) defaults. A quick session has fewer runs, each of the thesis' 6 minutes:
#: a 40 s run ends FWD_2 only once or twice, all in the start's transient, and its map
#: is too small to score (3 x 40 s: FWD_2 ended once in HIT_2 and once in ABORT).
_DEFAULTS = {"runs": (20, 3), "seconds": (360, 360), "particles": (100, 100)}


def _positive_int(flag: str, value: tuple[float, ...], default: int) -> int:
    if not value:
        return default
    if len(value) != 1 or not float(value[0]).is_integer() or value[0] <= 0:
        shown = ",".join(f"{v:g}" for v in value)
        raise ValueError(f"--{flag} must be a positive integer, got {shown}")
    return int(value[0])


def resolved_options(quick: bool, options: Mapping[str, Any]) -> dict[str, int]:
    """``runs``, ``seconds``, ``particles`` with the defaults of a full or quick run.

    Raises
    ------
    ValueError
        One naming the flag: not exactly one positive integer.
    """
    return {
        k: _positive_int(k, tuple(options.get(k, ()) or ()), d[1 if quick else 0])
        for k, d in _DEFAULTS.items()
    }


def _dig(d: Mapping[str, Any], *keys: str) -> Any:
    for k in keys:
        if not isinstance(d, Mapping) or k not in d:
            return None
        d = d[k]
    return d


@register
class CrunchbotSlam(Experiment):
    """Thesis 6.5 (see the module docstring)."""

    name = "crunchbot-slam"
    chapter = 6
    title = "Chapter 6.5 reproduction: tactile SLAM on CrunchBot"
    description = (
        "CrunchBot's FSM runs in the SLAM arena mapped by a particle filter in "
        "blob, geometric and template modes: map error (eq. 6.3, figure 6.14), "
        "trajectory error, radial distance, floor texture (6.11), latencies"
    )
    options = (
        Option("runs", "", "Runs in the SLAM arena (default 20; quick 3).", numbers=True),
        Option("seconds", "", "Robot seconds per run (default 360, also quick).", numbers=True),
        Option("particles", "", "Particles of each filter (default 100).", numbers=True),
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """CrunchBot's session: 20 runs of 6 minutes (``quick``: 3 runs of 6 minutes)."""
        from vibrissa.thesis.crunchbot_slam.protocol import crunchbot_protocol

        return crunchbot_protocol(quick=quick, seed=seed)

    def protocol_for(
        self, quick: bool, seed: int, options: Mapping[str, Any]
    ) -> SimulationProtocol:
        """CrunchBot's session with ``--runs`` and ``--seconds`` checked and applied."""
        from vibrissa.thesis.crunchbot_slam.protocol import crunchbot_protocol

        o = resolved_options(quick, options)
        return crunchbot_protocol(
            quick=quick, seed=seed, n_runs=o["runs"], seconds=float(o["seconds"])
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
        """Map the SLAM runs in three modes; score maps, trajectories, sensors, latencies."""
        from vibrissa.thesis.crunchbot_slam.evaluation import (
            evaluate_crunchbot,
            floor_texture_accuracy,
            json_ready,
            latency_stats,
            ordering_over_runs,
            radial_distance_errors_mm,
            sum_outcomes,
        )
        from vibrissa.thesis.crunchbot_slam.protocol import sensor_logs

        proto = json.loads(ds.attrs["protocol_params"])
        particles = resolved_options(False, options)["particles"]
        logs = sensor_logs(ds, "slam")
        truth_grid = ds["ground_truth"].values
        arena_info = json.loads(ds.attrs["arena"])
        n_cells = int(truth_grid.shape[0])
        cell_m = MAP_SIZE_M / n_cells
        offset_m = max(0.0, round((MAP_SIZE_M - arena_info["size_m"]) / 2 / cell_m) * cell_m)
        ev = evaluate_crunchbot(
            logs,
            truth_grid,
            particles=particles,
            seed=seed,
            workers=workers,
            progress=progress,
            arena_mask=arena_mask(n_cells, cell_m, offset_m, float(arena_info["size_m"])),
        )
        fsm_runs = [r["fsm"] for r in ev.per_run]
        slam_runs = ds["kind"].values == "slam"
        names = [str(w) for w in ds["whisker"].values]
        est = ds["radial_distance_m"].values[slam_runs].reshape(-1, len(names))
        tru = ds["contact_true_m"].values[slam_runs].reshape(-1, len(names))
        radial = radial_distance_errors_mm([est], [tru], names)
        textures = json.loads(ds.attrs["textures"])
        floor_acc = floor_texture_accuracy(
            ds["floor_texture_true"].values, ds["floor_texture_pred"].values
        )
        lat = latency_stats(
            {
                str(c).removeprefix("latency_").removesuffix("_s"): ds[c].values
                for c in ds.data_vars
                if str(c).startswith("latency_")
            }
        )
        rtf = float(ds["seconds"].values.sum() / ds["wall_seconds"].values.sum())
        robot = str(ds.attrs["robot"])
        modes = ("blob", "geometric", "template")
        means = {m: ev.map_error[m]["mean"] for m in modes}
        arena_err = ev.map_error_arena or {}
        per_run_err = {
            region: {m: [r[m][key] for r in ev.per_run] for m in modes}
            for region, key in (("grid", "map_error"), ("arena", "map_error_arena"))
        }
        spread = {
            "map_error": {m: {"mean": spread_leaf(per_run_err["grid"][m])} for m in modes},
            "map_error_arena": {m: {"mean": spread_leaf(per_run_err["arena"][m])} for m in modes},
        }
        artifacts = {
            "mean_maps": ev.mean_maps,
            "estimates": ev.estimates,
            "dead_reckoning": ev.dead_reckoning,
            "truth": ev.truth,
            "true_pose": logs[0].true_pose,
        }
        return Evaluation(
            json_ready(
                {
                    "meta": {
                        "robot": robot,
                        "synthetic": robot != "simulated-physics",
                        "real_time_factor": rtf,
                        "n_runs": len(logs),
                        "seconds_per_run": float(proto["seconds"]),
                        "particles": particles,
                        "arena": json.loads(ds.attrs["arena"])["name"],
                        "texture_arena": (json.loads(ds.attrs["texture_arena"]) or {}).get("name"),
                        "modes_share_sensor_log": True,
                        "textures": textures,
                        "random_map": "map_error.random: each cell Bernoulli(0.5), unsmoothed "
                        "(expectation exactly 0.5); random_smoothed: the same "
                        "maps through the 5 x 5 filter",
                    },
                    "parameters": {},
                    "classifiers": {},
                    "map_error": {
                        **{m: ev.map_error[m] for m in means},
                        "random": ev.map_error["random"],
                        "random_smoothed": ev.map_error["random_smoothed"],
                        "empty": ev.map_error["empty"],
                    },
                    "map_error_arena": arena_err,
                    "fsm_outcomes": sum_outcomes(fsm_runs),
                    "trajectory_error_mm": ev.trajectory_error_mm,
                    "radial_distance_error_mm": {k: radial[k] for k in (*names, "combined")},
                    "radial_distance_contacts": radial["n_contacts"],
                    "radial_distance_fit_residual_mm": json.loads(
                        ds.attrs.get("radial_fit_residual_mm", "null")
                    ),
                    "floor_texture": {"accuracy": floor_acc},
                    "classifier_latency_ms": lat,
                    "ordering": {
                        "template_lt_geometric_lt_blob": bool(
                            means["template"] < means["geometric"] < means["blob"]
                        ),
                        "order": sorted(means, key=means.__getitem__),
                        **ordering_over_runs(per_run_err, ev.map_error, arena_err),
                    },
                    "spread": spread,
                    "per_run": ev.per_run,
                    "thesis": THESIS,
                }
            ),
            artifacts,
        )

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
        """Draw the maps, trajectory (with ``artifacts``), radial distances, texture trace."""
        from vibrissa.evaluate.figures.common import save_figure
        from vibrissa.thesis.crunchbot_slam.figures import (
            average_maps_figure,
            radial_distance_figure,
            texture_trace_figure,
            trajectory_figure,
        )

        if not figures or dataset is None:
            return {}
        fig_dir = Path(out_dir) / "figures"
        out: dict[str, Path] = {}
        data = artifacts or {}
        if "mean_maps" in data:  # the maps of this evaluation (not of a redrawn report)
            errs = {m: results["map_error"][m]["mean"] for m in data["mean_maps"]}
            out["maps"] = save_figure(
                average_maps_figure(data["truth"], data["mean_maps"], errs),
                fig_dir / "average_maps.png",
            )
            est = {**data["estimates"], "dead reckoning": data["dead_reckoning"]}
            out["trajectory"] = save_figure(
                trajectory_figure(data["true_pose"], est, data["truth"]), fig_dir / "trajectory.png"
            )
        slam_runs = dataset["kind"].values == "slam"
        names = [str(w) for w in dataset["whisker"].values]
        if np.isfinite(dataset["contact_true_m"].values[slam_runs]).any():
            out["radial"] = save_figure(
                radial_distance_figure(
                    dataset["radial_distance_m"].values[slam_runs].reshape(-1, len(names)),
                    dataset["contact_true_m"].values[slam_runs].reshape(-1, len(names)),
                    names,
                    results["radial_distance_error_mm"],
                ),
                fig_dir / "radial_distance.png",
            )
        tex_runs = np.flatnonzero(dataset["kind"].values == "texture")
        textures = json.loads(dataset.attrs["textures"])
        if tex_runs.size and textures:
            r = int(tex_runs[0])
            n = int(dataset["n_steps"].values[r])
            out["texture"] = save_figure(
                texture_trace_figure(
                    dataset["step_end_s"].values[r, :n],
                    dataset["floor_texture_true"].values[r, :n],
                    dataset["floor_texture_pred"].values[r, :n],
                    textures,
                    [str(f) for f in dataset["floor_whisker"].values],
                ),
                fig_dir / "texture_trace.png",
            )
        return out

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """CrunchBot's report Markdown body; ``baseline`` is not used."""
        from vibrissa.thesis.crunchbot_slam.report import markdown_crunchbot

        return markdown_crunchbot(results, figures)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Map, trajectory, radial and texture errors, latency median and p99, and ``meta``."""
        meta = results["meta"]
        return {
            "map_error": results["map_error"],
            "trajectory_error_mm": results["trajectory_error_mm"],
            "radial_distance_error_mm": results["radial_distance_error_mm"],
            "radial_distance_fit_residual_mm": results.get("radial_distance_fit_residual_mm"),
            "floor_texture": results["floor_texture"],
            "classifier_latency_ms": {
                c: {k: v[k] for k in ("median", "p99")}
                for c, v in results["classifier_latency_ms"].items()
            },
            "meta": dict(meta),
        }

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        """Map and trajectory error per mode beside the thesis', and the random map's."""
        from rich.table import Table

        from vibrissa.evaluate.report_common import fmt

        table = Table(title=f"Tactile SLAM (thesis 6.5), robot {summary['meta']['robot']}")
        for col in ("mode", "map error", "thesis", "trajectory error (mm)"):
            table.add_column(col, justify="left" if col == "mode" else "right")
        for m in ("blob", "geometric", "template"):
            table.add_row(
                m,
                fmt(_dig(summary, "map_error", m, "mean"), 3),
                fmt(THESIS["map_error"][m]),
                fmt(_dig(summary, "trajectory_error_mm", m, "mean"), 1),
            )
        table.add_row(
            "random", fmt(summary["map_error"]["random"], 3), fmt(THESIS["map_error"]["random"]), ""
        )
        return table
