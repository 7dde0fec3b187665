"""`vibrissa reproduce ...`: the thesis' chapters end to end (the main job)."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from vibrissa.cli._common import echo_json, user_errors

reproduce_app = typer.Typer(
    help="Reproduce a thesis chapter end to end: simulate the data, run every classifier "
    "and the evaluation protocol, write tables, figures and a report.",
    no_args_is_help=True,
)

_CONTRACT_KEYS = ("radius_mm", "speed_mm_s", "classify_seconds")


def _summary(entry: dict | None) -> dict | None:
    if entry is None:
        return None
    out = {}
    for k in _CONTRACT_KEYS:
        v = entry.get(k)
        out[k] = {"mean": v["mean"], "std": v["std"]} if isinstance(v, dict) else v
    return out


def register(app: typer.Typer) -> None:
    """Register ``vibrissa reproduce`` on the top-level ``app``."""
    app.add_typer(reproduce_app, name="reproduce")


@reproduce_app.command("radial-distance")
@user_errors
def radial_distance(
    quick: bool = typer.Option(False, "--quick", help="Small grid: about a minute."),
    json_out: bool = typer.Option(False, "--json", help="Print the results as one JSON object."),
    out: Path = typer.Option(
        Path("vibrissa-out/radial-distance"), "--out", help="Output directory (report, data)."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the simulated session and splits."),
    n_seeds: int = typer.Option(5, "--n-seeds", help="Repeats of each reduced training set."),
    workers: int = typer.Option(None, "--workers", help="Generation processes (default all)."),
    figures: bool = typer.Option(True, "--figures/--no-figures", help="Draw the figures."),
    baseline: Path = typer.Option(
        None, "--baseline",
        help="An earlier run's results.json (or a compact one, e.g. docs/runs/...): the "
        "report shows its numbers as 'before' beside the thesis' and this run's.",
    ),
) -> None:
    """Chapter 4: radial distance and speed from one whisker deflection, five classifiers.

    Generates (or reuses) the XY-robot dataset (101 radial distances x 26 speeds x 4
    sets; --quick: 5 x 4 x 4), evaluates the static beam, frequency, template, feature
    and naive Bayes classifiers with full and reduced training sets, and writes
    report.md, results.json, results.csv and figures/ into --out.
    """
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
    from rich.table import Table

    from vibrissa.evaluate.baseline import load_baseline
    from vibrissa.evaluate.report import THESIS_CHAPTER4
    from vibrissa.evaluate.reproduce import reproduce_radial_distance

    before = load_baseline(baseline) if baseline is not None else None

    console = Console(stderr=json_out)
    show = os.environ.get("CI") is None
    with Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}"),
        TimeElapsedColumn(),
        console=console,
        disable=not show,
    ) as bar:
        tasks: dict[str, int] = {}

        def progress(stage: str, done: int, total: int) -> None:
            if stage not in tasks:
                label = "simulating trials" if stage == "generate" else "evaluating classifiers"
                tasks[stage] = bar.add_task(label, total=total)
            bar.update(tasks[stage], completed=done, total=total)

        res = reproduce_radial_distance(
            out, quick=quick, seed=seed, n_seeds=n_seeds, workers=workers,
            progress=progress, figures=figures, baseline=before,
        )  # fmt: skip
    summary = {
        "chapter": 4,
        "protocol": "radial-distance",
        "quick": quick,
        "out": str(out),
        "report": str(out / "report.md"),
        "meta": res["meta"],
        "classifiers": {k: _summary(v) for k, v in res["classifiers"].items()},
        "training_fractions": {
            frac: {k: _summary(v) for k, v in per.items()}
            for frac, per in res["training_fractions"].items()
        },
    }
    if json_out:
        echo_json(summary)
        return
    thesis = THESIS_CHAPTER4.get("table_4_7", {})
    table = Table(title="Table 4.7: signed error, full training set (ours | thesis)")
    for col in (
        "classifier",
        "radius mean",
        "radius std",
        "speed mean",
        "speed std",
        "classify s",
        "thesis radius std",
        "thesis speed std",
    ):
        table.add_column(col, justify="right" if col != "classifier" else "left")

    def f(x: object) -> str:
        return "-" if x is None else f"{x:.2f}"

    thesis_name = {
        "static_beam_measured": "static_beam",
        "naive_bayes_velocity": "naive_bayes",
    }
    for name, e in summary["classifiers"].items():
        th = thesis.get(thesis_name.get(name, name)) or {}
        sp = e["speed_mm_s"]
        table.add_row(
            name, f(e["radius_mm"]["mean"]), f(e["radius_mm"]["std"]),
            f(sp["mean"] if sp else None), f(sp["std"] if sp else None),
            f(e["classify_seconds"]),
            f((th.get("radius_mm") or {}).get("std")), f((th.get("speed_mm_s") or {}).get("std")),
        )  # fmt: skip
    Console().print(table)
    typer.echo(f"report: {out / 'report.md'}")


@reproduce_app.command("angle-texture")
@user_errors
def angle_texture(
    quick: bool = typer.Option(False, "--quick", help="Small grid: under a minute."),
    json_out: bool = typer.Option(False, "--json", help="Print the results as one JSON object."),
    out: Path = typer.Option(
        Path("vibrissa-out/angle-texture"), "--out", help="Output directory (report, data)."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the simulated session and splits."),
    workers: int = typer.Option(None, "--workers", help="Generation processes (default all)."),
    figures: bool = typer.Option(True, "--figures/--no-figures", help="Draw the figures."),
    baseline: Path = typer.Option(
        None, "--baseline",
        help="An earlier run's results.json (or a compact one, e.g. docs/runs/...): the "
        "report shows its numbers as 'before' beside the thesis' and this run's.",
    ),
) -> None:
    """Chapter 5: surface angle, contact speed and texture, simultaneously.

    Generates (or reuses) the angle-texture dataset (8 angles x 11 speeds x 4 textures x
    4 sets at 4 kHz; --quick: 3 x 3 x 4 x 4), runs the chapter-5 classifiers and the
    extensions (joint-likelihood naive Bayes, MiniRocket, sequential evidence over
    contacts) and writes report.md, results.json and figures/ into --out.
    """
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
    from rich.table import Table

    from vibrissa.evaluate.baseline import load_baseline
    from vibrissa.evaluate.chapter5 import reproduce_angle_texture

    before = load_baseline(baseline) if baseline is not None else None

    console = Console(stderr=json_out)
    with Progress(
        TextColumn("[bold]{task.description}"), BarColumn(),
        TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
        console=console, disable=os.environ.get("CI") is not None,
    ) as bar:  # fmt: skip
        tasks: dict[str, int] = {}

        def progress(stage: str, done: int, total: int) -> None:
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
            bar.update(tasks[stage], completed=done, total=total)

        res = reproduce_angle_texture(
            out, quick=quick, seed=seed, progress=progress, workers=workers, figures=figures,
            baseline=before,
        )
    summary = {
        "chapter": 5,
        "protocol": "angle-texture",
        "quick": quick,
        "out": str(out),
        "report": str(out / "report.md"),
        "meta": res["meta"],
        "classifiers": {
            k: {"kappa": v["kappa"], "classify_seconds": v["classify_seconds"]}
            for k, v in res["classifiers"].items()
        },
        "sequential": res["sequential"],
    }
    if json_out:
        echo_json(summary)
        return
    table = Table(title="Cohen's kappa (simultaneous; texture alone)")
    for col in ("classifier", "angle", "speed", "texture", "texture alone", "classify s"):
        table.add_column(col, justify="left" if col == "classifier" else "right")
    for name, e in summary["classifiers"].items():
        k = e["kappa"]
        table.add_row(name, *(f"{k[p]:.2f}" if k.get(p) is not None else "-"
                              for p in ("angle", "speed", "texture", "texture_alone")),
                      f"{e['classify_seconds']:.2f}")  # fmt: skip
    Console().print(table)
    typer.echo(
        "sequential texture kappa: "
        + ", ".join(
            f"{n} contacts {v:.2f}" for n, v in summary["sequential"].items() if v is not None
        )
    )
    typer.echo(f"report: {out / 'report.md'}")
