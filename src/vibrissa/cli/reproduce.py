"""`vibrissa reproduce NAME` and `vibrissa reproduce --list`: the thesis' experiments end to end.

One command per registered experiment (:mod:`vibrissa.reproduce`), all with the
same options plus the experiment's own.
"""

from __future__ import annotations

import inspect
import os
import shlex
import sys
from pathlib import Path
from typing import Any

import typer

from vibrissa._atomic import check_writable
from vibrissa.cli._common import (
    count_option,
    echo_json,
    free_space,
    generation_disk_bytes,
    option_renamer,
    print_table,
    seed_option,
    user_errors,
)
from vibrissa.cli._interrupt import interruptible
from vibrissa.cli.generate import work_statement
from vibrissa.reproduce import Experiment, experiments

reproduce_app = typer.Typer(
    help="Reproduce a thesis experiment end to end: simulate the data, run every classifier "
    "and the evaluation protocol, write results.json, tables, figures and a report "
    "(report.md and a self-contained report.html).",
    invoke_without_command=True,
)


def register(app: typer.Typer) -> None:
    """Register ``vibrissa reproduce`` on the top-level ``app``."""
    app.add_typer(reproduce_app, name="reproduce")


@reproduce_app.callback()
def _group(
    ctx: typer.Context,
    list_: bool = typer.Option(False, "--list", help="List the experiments and exit."),
    json_out: bool = typer.Option(False, "--json", help="With --list: print JSON."),
) -> None:
    """Reproduce a thesis experiment end to end (``--list`` shows them)."""
    if ctx.invoked_subcommand is not None:
        return
    if not list_:
        typer.echo(ctx.get_help())
        raise typer.Exit()
    entries = [e.listing() for e in experiments().values()]
    if json_out:
        echo_json({"experiments": entries})
        raise typer.Exit()
    for e in entries:
        t = e["trials"]
        typer.echo(
            f"{e['name']:<16} chapter {e['chapter']}  {t['quick']:>5} trials quick, "
            f"{t['full']:>6} full  {e['description']}"
        )
    raise typer.Exit()


_RENAME = option_renamer({"seed": "--seed", "workers": "--workers", "scheduler": "--scheduler"})


def _run(
    exp: Experiment,
    quick: bool,
    json_out: bool,
    out: Path,
    seed: int,
    workers: int | None,
    scheduler: str | None,
    figures: bool,
    baseline: Path | None,
    **options: Any,
) -> None:
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from vibrissa.evaluate.baseline import load_baseline
    from vibrissa.experiments.contract import SelfGenerating, chunk_size_of
    from vibrissa.experiments.generate import kept_trials, parts_dir
    from vibrissa.reproduce import check_job_arguments, dataset_path, run_experiment
    from vibrissa.reproduce.pipeline import check_scheduler

    seed_option("--seed", seed)
    count_option("--workers", workers)
    try:
        check_job_arguments(out, seed, workers, scheduler=scheduler)
    except ValueError as exc:
        text = _RENAME(str(exc))
        raise ValueError(
            f"--out: {text}" if text.startswith("output directory") else text
        ) from None
    try:
        check_writable(out, directory=True)
    except ValueError as exc:
        raise ValueError(f"--out: {exc}") from None
    opts = {o.name: o.check(options[o.name]) for o in exp.options}
    before = load_baseline(baseline) if baseline is not None else None
    console = Console(stderr=True)
    protocol = exp.protocol_for(quick, seed, opts)
    try:
        check_scheduler(protocol, scheduler)
    except ValueError as exc:
        raise ValueError(_RENAME(str(exc))) from None
    data = dataset_path(protocol, out)
    if not data.exists() and not isinstance(protocol, SelfGenerating):
        need = generation_disk_bytes(protocol, data)
        free_space("--out", data, need, "the simulated dataset and its shards")
    stages: dict[str, int] = {}

    def interrupted() -> str:
        if "evaluate" in stages or data.exists():
            return (
                f"the simulated dataset is kept in {data}; rerun the same command to "
                "evaluate it without simulating again"
            )
        if "generate" in stages:
            return (
                f"{kept_trials(data)} of {protocol.n_trials} trials kept in "
                f"{parts_dir(data)}/; rerun the same command to resume"
            )
        return "before any trial was simulated; rerun the same command to start again"

    with interruptible(interrupted):
        grid = "quick" if quick else "full"
        if data.exists():
            work = f"simulated dataset reused from {data}"
        elif scheduler is not None:
            work = f"simulating on the Dask cluster at {scheduler}"
        elif isinstance(protocol, SelfGenerating):  # simulates itself, no XY estimate
            work = "simulating"
        else:
            chunk = chunk_size_of(protocol)
            work = f"simulating {work_statement(protocol, workers, chunk_size=chunk)}"
        console.print(
            f"{exp.name}: {protocol.n_trials} trials ({grid} grid), seed {seed}, "
            f"{work}; then the evaluation -> {out}",
            highlight=False,
            soft_wrap=True,
        )
        labels = {"generate": "simulating trials", "evaluate": "evaluating classifiers"}
        with Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total}"),
            TimeElapsedColumn(),
            console=console,
            disable=os.environ.get("CI") is not None,
        ) as bar:
            tasks: dict[str, Any] = {}

            def progress(stage: str, done: int, total: int) -> None:
                stages[stage] = done
                if stage not in tasks:
                    tasks[stage] = bar.add_task(labels.get(stage, stage), total=total)
                bar.update(tasks[stage], completed=done, total=total)

            res = run_experiment(
                exp.name,
                out,
                quick=quick,
                seed=seed,
                workers=workers,
                scheduler=scheduler,
                progress=progress,
                figures=figures,
                baseline=before,
                command=shlex.join(["vibrissa", *sys.argv[1:]]),
                **opts,
            )
        said_reused = work.startswith("simulated dataset reused")
        if said_reused and not (res.get("meta", {}).get("dataset") or {}).get("reused", True):
            # the cached file could not be trusted: the pipeline simulated it again
            console.print(
                f"{exp.name}: the cached dataset {data} could not be trusted (unreadable, "
                "changed since written, or without vibrissa's checksum); it was simulated "
                "again",
                highlight=False,
                soft_wrap=True,
            )
    summary = {
        "experiment": exp.name,
        "chapter": exp.chapter,
        "protocol": exp.name,
        "quick": quick,
        "out": str(out),
        "report": str(out / "report.md"),
        "report_html": str(out / "report.html"),
        "meta": res["meta"],
        **exp.summary(res),
    }
    if json_out:
        echo_json(summary)
        return
    table = exp.console_table(summary)
    if table is not None:
        print_table(table)
    typer.echo(f"report: {out / 'report.md'} and {out / 'report.html'}")


def _command(exp: Experiment) -> Any:
    """A typer command for ``exp``: the common options plus the experiment's own."""

    def command(**kwargs: Any) -> None:
        _run(exp, **kwargs)

    Opt = inspect.Parameter.KEYWORD_ONLY
    quick_n, full_n = exp.n_trials(True), exp.n_trials(False)
    params = [
        inspect.Parameter(
            "quick",
            Opt,
            annotation=bool,
            default=typer.Option(
                False, "--quick", help=f"Small grid: {quick_n} trials instead of {full_n}."
            ),
        ),
        inspect.Parameter(
            "json_out",
            Opt,
            annotation=bool,
            default=typer.Option(
                False, "--json", help="Print the results summary as one JSON object."
            ),
        ),
        inspect.Parameter(
            "out",
            Opt,
            annotation=Path,
            default=typer.Option(
                Path(f"vibrissa-out/{exp.name}"),
                "--out",
                help="Output directory (report, results, figures, data).",
            ),
        ),
        inspect.Parameter(
            "seed",
            Opt,
            annotation=int,
            default=typer.Option(
                0, "--seed", help="Seed of the simulated session and of the evaluation."
            ),
        ),
        inspect.Parameter(
            "workers",
            Opt,
            annotation=int,
            default=typer.Option(
                None,
                "--workers",
                help="Processes for simulating and for evaluating (default: all cores).",
            ),
        ),
        inspect.Parameter(
            "scheduler",
            Opt,
            annotation=str,
            default=typer.Option(
                None,
                "--scheduler",
                help="Simulate the dataset on an existing Dask cluster at this address "
                "(tcp://host:port); the evaluation runs here.",
            ),
        ),
        inspect.Parameter(
            "figures",
            Opt,
            annotation=bool,
            default=typer.Option(True, "--figures/--no-figures", help="Draw the figures."),
        ),
        inspect.Parameter(
            "baseline",
            Opt,
            annotation=Path,
            default=typer.Option(
                None,
                "--baseline",
                help="An earlier run's results.json (or a compact one, e.g. docs/runs/...): the "
                "report shows its numbers as 'before' beside the thesis' and this run's.",
            ),
        ),
    ]
    for o in exp.options:
        params.append(
            inspect.Parameter(
                o.name,
                Opt,
                annotation=str if o.choices or o.numbers else int,
                default=typer.Option(o.default, o.flag, help=o.help),
            )
        )
    command.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]
    command.__name__ = exp.name.replace("-", "_")
    command.__doc__ = (
        f"Chapter {exp.chapter}: {exp.description}.\n\n"
        f"Generates (or reuses) the simulated dataset ({full_n} trials; --quick: {quick_n}), "
        "runs the classifiers and the evaluation, and writes results.json, report.md, "
        "report.html and figures/ into --out."
    )
    return user_errors(command)


for _exp in experiments().values():
    reproduce_app.command(_exp.name)(_command(_exp))
