"""`vibrissa identify`: the simulated robot against the thesis' own observations."""

from __future__ import annotations

import sys

import typer

from vibrissa.cli._common import echo_json, print_table, user_errors


def _fmt(x: float | None, unit: str) -> str:
    if x is None:
        return "-"
    if unit == "fraction" or unit.startswith("fraction"):
        return f"{x:.2f}"
    return f"{x:.1f} {unit}"


def register(app: typer.Typer) -> None:
    """Register ``vibrissa identify`` on the top-level ``app``."""

    @app.command("identify")
    @user_errors
    def identify_cmd(
        quick: bool = typer.Option(
            False, "--quick", help="Coarser grids (about a tenth of the trials)."
        ),
        json_out: bool = typer.Option(
            False, "--json", help="Print the observables as one JSON object."
        ),
    ) -> None:
        """Measure the thesis' physical observables on the simulated whisker and XY robot.

        Simulates single trials with the chapter-4 and chapter-5 protocols' settings
        (about 160 trials, ~20 s; --quick: about 35) and prints, for each statement the
        thesis makes about its hardware (resonance 5.3.1, loop latency 3.3.2,
        closest usable contact, tip zone and speed limit 4.2, ringing 3.3 / 5.4,
        durations 4.3.4 / 5.5), the thesis' value, ours, the tolerance and whether
        ours is within it. Parameters and their sources: docs/physics.md.
        """
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn
        from rich.table import Table

        from vibrissa.experiments.identify import identify, plan

        n = plan(quick).n_trials
        err = Console(stderr=True)
        if not json_out:
            err.print(f"identify: simulating {n} trials on the current parameters")
        with Progress(
            TextColumn("trials"),
            BarColumn(),
            MofNCompleteColumn(),
            console=err,
            disable=not sys.stderr.isatty(),
            transient=True,
        ) as bar:
            task = bar.add_task("trials", total=n)
            obs = identify(quick=quick, progress=lambda k: bar.advance(task, k))
        if json_out:
            echo_json(
                {
                    "n_trials": n,
                    "quick": quick,
                    "n_within": sum(o.within for o in obs),
                    "observables": {o.key: o.to_dict() for o in obs},
                }
            )
            return
        table = Table(title="The simulated XY robot against the thesis", show_lines=True)
        for col in ("observable", "thesis", "ours", "tolerance", "within"):
            table.add_column(col)
        for o in obs:
            table.add_row(
                f"{o.key}\n[dim]{o.description}[/dim]",
                f"{_fmt(o.thesis_value, o.unit)}\n[dim]{o.thesis}[/dim]",
                _fmt(o.value, o.unit),
                o.tolerance,
                "[green]yes[/green]" if o.within else "[red]no[/red]",
            )
        print_table(table)
        Console().print(f"{sum(o.within for o in obs)} of {len(obs)} observables within tolerance")
