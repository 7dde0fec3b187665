"""`vibrissa fit-pipeline`: a tactile pipeline fitted on recorded datasets, saved to one file.

The file is what ``vibrissa live --pipeline`` runs. ``--where`` is a Dataset of single contacts
labelled ``radial_distance_mm, speed_mm_s`` (chapter 4's, simulated or imported), ``--what`` one
labelled ``angle_deg, speed_mm_s, texture`` (chapter 5's); either or both
(:func:`vibrissa.framework.calibrate.fit_pipeline_from_datasets`). Every option is checked
before any work: the datasets are regular files that load, the output can be written,
numbers are in range.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import typer

from vibrissa._atomic import check_writable
from vibrissa._validate import in_range, non_negative
from vibrissa.cli._common import user_errors

__all__ = ["register"]


def register(app: typer.Typer) -> None:
    """Register ``vibrissa fit-pipeline`` on the top-level ``app``."""
    app.command("fit-pipeline")(fit_pipeline_cmd)


def _dataset(option: str, path: Path | None) -> Any:
    if path is None:
        return None
    if not path.exists():
        raise ValueError(f"{option}: {path} does not exist")
    if not path.is_file():
        raise ValueError(f"{option}: {path} is not a regular file")
    from vibrissa.data import load_dataset

    try:
        return load_dataset(path)
    except (ValueError, OSError, KeyError) as exc:
        raise ValueError(f"{option}: {path}: {exc}") from None


@user_errors
def fit_pipeline_cmd(
    out: Path = typer.Option(..., "--out", help="The pipeline file to write."),
    where: Path | None = typer.Option(
        None, "--where", help="Dataset of single contacts labelled by radial distance and speed."
    ),
    what: Path | None = typer.Option(
        None, "--what", help="Dataset of single contacts labelled by angle, speed and texture."
    ),
    tip_zone_mm: float = typer.Option(
        5.0, "--tip-zone-mm", help="Radial distances this close to the length are tip contacts."
    ),
    decision_threshold: float = typer.Option(
        0.99, "--decision-threshold", help="Posterior at which a surface is decided."
    ),
    json_out: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
) -> None:
    """Fit a tactile pipeline on recorded datasets and save it for `vibrissa live`."""
    from vibrissa.framework.calibrate import check_datasets, fit_pipeline_from_datasets

    if where is None and what is None:
        raise ValueError("--where/--what: give at least one dataset")
    non_negative("--tip-zone-mm", tip_zone_mm)
    in_range("--decision-threshold", decision_threshold, 0.0, 1.0)
    if decision_threshold <= 0.0:
        raise ValueError("--decision-threshold must be > 0")
    target = check_writable(out)
    ds_where = _dataset("--where", where)
    ds_what = _dataset("--what", what)
    check_datasets(ds_where, ds_what)
    n = sum(int(d.sizes["trial"]) for d in (ds_where, ds_what) if d is not None)
    print(
        f"fit-pipeline: {n} trials through the detector, then the fits -> {target}", file=sys.stderr
    )
    pipe, summary = fit_pipeline_from_datasets(
        ds_where, ds_what, tip_zone_mm=tip_zone_mm, decision_threshold=decision_threshold
    )
    pipe.save(target)
    summary["out"] = str(target)
    if json_out:
        print(json.dumps(summary, indent=2))
    else:
        parts = [
            f"{k}: {v['contacts']} contacts ({v['missed']} trials without one)"
            for k, v in summary.items()
            if isinstance(v, dict)
        ]
        print(f"pipeline: {target} ({'; '.join(parts)}, {summary['sample_rate_hz']:g} Hz)")
