"""Chapter 5: surface angle, contact speed and texture, classified simultaneously (5.2-5.4).

The XY robot's contacts with four surfaces (aluminium, P600, P180, P80) at 8
angles x 11 speeds, recorded at 4 kHz; every method of 5.3 plus the extensions
(joint-likelihood naive Bayes, MiniRocket, evidence accumulated over contacts),
scored by Cohen's kappa per parameter and of texture alone.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from vibrissa.experiments.contract import SimulationProtocol
from vibrissa.experiments.protocols import get_protocol
from vibrissa.reproduce.registry import Evaluation, Experiment, register


@register
class AngleTexture(Experiment):
    """Chapter 5 (see the module docstring)."""

    name = "angle-texture"
    chapter = 5
    title = "Chapter 5 reproduction: surface angle, contact speed and texture"
    description = (
        "XY robot, textured surfaces: angle, speed and texture at once, Cohen's "
        "kappa of every chapter-5 method, evidence over contacts"
    )

    def protocol(self, quick: bool, seed: int) -> SimulationProtocol:
        """The ``angle-texture`` protocol: the XY robot's textured-surface grid (chapter 5)."""
        return get_protocol("angle-texture", quick=quick, seed=seed)

    def evaluate(
        self,
        ds: xr.Dataset,
        *,
        seed: int,
        progress: Callable | None,
        options: Mapping[str, int],
        workers: int | None = None,
    ) -> Evaluation:
        """Run every chapter-5 classifier on ``ds``, notched at the whisker's resonance."""
        # chapter 5's evaluation runs in this process (``workers`` is not used)
        from vibrissa.classify import chapter5_classifiers, dataset_sample_rate, resonance_hz
        from vibrissa.data import whisker_params
        from vibrissa.thesis.angle_texture.evaluation import run_chapter5

        notch = resonance_hz(whisker_params(ds))
        clfs = chapter5_classifiers(dataset_sample_rate(ds), notch_hz=notch)
        results = run_chapter5(ds, clfs, seed=seed, progress=progress)
        results["meta"]["notch_hz"] = notch
        return Evaluation(results)

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
        """Draw the chapter-5 figures into ``out_dir/figures`` (if ``figures``)."""
        # chapter 5's figures are drawn in this process (``workers`` is not used)
        from vibrissa.thesis.angle_texture.report import write_outputs

        return write_outputs(results, out_dir, figures=figures)

    def report_sections(
        self,
        results: Mapping[str, Any],
        figures: Mapping[str, Path],
        baseline: Mapping[str, Any] | None,
    ) -> str:
        """The chapter-5 Markdown body; ``baseline`` adds a kappa table (figure 5.15)."""
        from vibrissa.thesis.angle_texture.report import markdown_chapter5

        return markdown_chapter5(results, figures, baseline)

    def summary(self, results: Mapping[str, Any]) -> dict[str, Any]:
        """Each classifier's kappas and classify seconds, and the sequential texture kappas."""
        return {
            "classifiers": {
                k: {"kappa": v["kappa"], "classify_seconds": v["classify_seconds"]}
                for k, v in results["classifiers"].items()
            },
            "sequential": results["sequential"],
        }

    def console_table(self, summary: Mapping[str, Any]) -> Any:
        """Kappas per classifier and parameter, and the sequential texture kappas."""
        from rich.console import Group
        from rich.table import Table
        from rich.text import Text

        table = Table(title="Cohen's kappa (simultaneous; texture alone)")
        for col in ("classifier", "angle", "speed", "texture", "texture alone", "classify (s)"):
            table.add_column(col, justify="left" if col == "classifier" else "right")
        for name, e in summary["classifiers"].items():
            k = e["kappa"]
            table.add_row(
                name,
                *(
                    f"{k[p]:.2f}" if k.get(p) is not None else "-"
                    for p in ("angle", "speed", "texture", "texture_alone")
                ),
                f"{e['classify_seconds']:.2f}",
            )
        seq = ", ".join(
            f"{n} contacts {v:.2f}" for n, v in summary["sequential"].items() if v is not None
        )
        return Group(table, Text(f"sequential texture kappa: {seq}")) if seq else table
