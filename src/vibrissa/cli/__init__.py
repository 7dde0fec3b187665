"""The ``vibrissa`` command line.

Each command group lives in its own module and registers itself on the
top-level :data:`app` through a ``register(app)`` function, so that command
families can grow independently.
"""

from __future__ import annotations

import typer

from vibrissa import __version__
from vibrissa.cli import (
    bench,
    data,
    generate,
    identify,
    live,
    pipeline,
    plot,
    reproduce,
    run,
    whisker,
)
from vibrissa.cli._contract import enforce
from vibrissa.cli._usage import OneLineUsageErrors, flags_show_no_type

flags_show_no_type()

app = typer.Typer(
    name="vibrissa",
    cls=OneLineUsageErrors,
    help="Whisker-based tactile sensing after Evans (2011): simulate, generate, import, "
    "classify and reproduce the thesis' experiments.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"vibrissa {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
) -> None:
    """Whisker-based tactile sensing toolkit."""


for _module in (whisker, bench, generate, data, plot, reproduce, identify, run, live, pipeline):
    _module.register(app)
enforce(app)  # every option checked against its row of cli._contract.CONTRACT


def main() -> None:
    """Entry point of the ``vibrissa`` console script."""
    app()
