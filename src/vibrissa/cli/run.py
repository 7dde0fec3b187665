"""`vibrissa run crunchbot`: watch one robot run as an animation and an interactive page."""

from __future__ import annotations

import os
from pathlib import Path

import typer

from vibrissa._atomic import check_writable
from vibrissa.cli._common import echo_json, user_errors
from vibrissa.cli._contract import read_structured
from vibrissa.cli._interrupt import interruptible

run_app = typer.Typer(
    help="Run one robot and watch it: an animation and an interactive HTML page.",
    no_args_is_help=True,
)


def register(app: typer.Typer) -> None:
    """Register ``vibrissa run`` on the top-level ``app``."""
    app.add_typer(run_app, name="run")


@run_app.command("crunchbot")
@user_errors
def crunchbot_cmd(
    out: Path = typer.Option(..., "--out", help="Directory for crunchbot.gif and crunchbot.html."),
    arena: str = typer.Option(
        "slam", "--arena", help="A preset (slam, tiles) or a .toml/.json arena file."
    ),
    seconds: float = typer.Option(360.0, "--seconds", help="Robot seconds to run."),
    seed: int = typer.Option(0, "--seed", help="Seed of the run and of the filter."),
    particles: int = typer.Option(100, "--particles", help="Particles of the filter."),
    mode: str = typer.Option("blob", "--mode", help="Mapping mode: blob, geometric or template."),
    json_out: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
) -> None:
    """One CrunchBot run (thesis 6.5), then tactile SLAM over it, then its animation and page.

    The animation is DIR/crunchbot.gif; the page, DIR/crunchbot.html, is one self-contained
    page: time slider, play button, arena, robot, whiskers, particles, map and whisker
    traces.
    """
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from vibrissa.thesis.crunchbot_slam.protocol import default_robot, robot_kind
    from vibrissa.thesis.crunchbot_slam.viewer import check_watch, watch_run

    if Path(arena).suffix.lower() in (".toml", ".json"):
        # a FIFO would block, /dev/zero never end, 100,000 brackets overflow the parser
        read_structured("--arena", Path(arena))
    a = check_watch(arena, seconds, seed, particles, mode)
    try:
        check_writable(out, directory=True)
    except ValueError as exc:
        raise ValueError(f"--out: {exc}") from None
    console = Console(stderr=True)
    kind = robot_kind(default_robot()[0])
    console.print(
        f"crunchbot: {seconds:g} s of robot time in arena {a.name!r} "
        f"({kind}), then SLAM with {particles} particles in {mode} mode over about "
        f"{int(seconds * 2)} FSM steps, then an animation and a page -> {out}",
        highlight=False,
        soft_wrap=True,
    )
    with (
        interruptible(lambda: f"nothing kept in {out}; the run starts again from its beginning"),
        Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            TextColumn("{task.percentage:>3.0f}%"),
            TimeElapsedColumn(),
            console=console,
            disable=os.environ.get("CI") is not None,
        ) as bar,
    ):
        tasks: dict[str, int] = {}
        labels = {"robot": "running the robot", "slam": "tactile SLAM", "draw": "drawing"}

        def progress(stage: str, fraction: float) -> None:
            if stage not in tasks:
                tasks[stage] = bar.add_task(labels[stage], total=1.0)
            bar.update(tasks[stage], completed=fraction)

        res = watch_run(out, a, seconds, seed, particles, mode, progress=progress)
    if json_out:
        echo_json(res)
        return
    typer.echo(
        f"map error {res['map_error']:.3f}, trajectory error "
        f"{res['trajectory_error_mm']:.1f} mm; animation: {res['animation']}; "
        f"page: {res['html']}"
    )
