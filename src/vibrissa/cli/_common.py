"""Helpers shared by the command-line modules: JSON output and error reporting."""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
from collections.abc import Callable
from functools import wraps
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import typer

F = TypeVar("F", bound=Callable[..., Any])


def _default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def dumps(obj: Any) -> str:
    """Serialise ``obj`` (numpy scalars and arrays allowed) as indented JSON."""
    return json.dumps(obj, indent=2, default=_default, allow_nan=False)


def echo_json(obj: Any) -> None:
    """Print ``obj`` as JSON on standard output."""
    typer.echo(dumps(obj))


def error_message(exc: BaseException) -> str:
    """The one line (without ``error:``) that reports a user's bad input ``exc``.

    An ``OSError`` names its path (``OUT.nc: No space left on device``), a
    ``KeyError`` shows its message without quotes, anything else its text.
    """
    if isinstance(exc, KeyError) and exc.args:
        return str(exc.args[0])
    if isinstance(exc, OSError) and exc.filename is not None:
        where = os.fsdecode(exc.filename)
        if exc.filename2 is not None:
            where += f" -> {os.fsdecode(exc.filename2)}"
        reason = exc.strerror or (str(exc.args[0]) if exc.args else type(exc).__name__)
        return f"{where}: {reason}"
    return " ".join(str(exc).split()) or type(exc).__name__


def user_errors(func: F) -> F:
    """Turn a user's bad input into one clear line on standard error and exit status 2.

    Bad input is a ``ValueError``, ``TypeError``, ``OSError`` or ``KeyError``; it is
    reported so instead of a traceback.
    """

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (ValueError, TypeError, OSError, KeyError) as exc:
            print(f"error: {error_message(exc)}", file=sys.stderr)
            raise typer.Exit(code=2) from exc

    return wrapper  # type: ignore[return-value]


def physics_errors(func: F) -> F:
    """Report a solver failure as one line on standard error and exit status 1 (a bug).

    The failure (``SimulationError``) is on inputs the command fixes itself; it is
    reported so instead of a traceback.
    """

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        from vibrissa.whisker.rod import SimulationError

        try:
            return func(*args, **kwargs)
        except SimulationError as exc:
            print(f"error: simulation failed: {exc}", file=sys.stderr)
            raise typer.Exit(code=1) from exc

    return wrapper  # type: ignore[return-value]


def solver_limits(remedy: str, rename: Callable[[str], str] | None = None) -> Callable[[F], F]:
    """Report a solver that does not converge on the user's own parameters as bad input.

    The command's options set everything the solver is given, so a
    ``SimulationError`` means they lie outside the range where it converges: it
    becomes a ``ValueError`` (one line and exit status 2 under :func:`user_errors`,
    which must wrap this decorator) that names what to change.

    Parameters
    ----------
    remedy
        What to change, naming the options, e.g. ``"use a smaller --force-n"``.
    rename
        Applied to every ``ValueError`` message on the way out, e.g. to write the
        library's parameter names as the command's option names.
    """
    named = rename if rename is not None else str

    def decorate(func: F) -> F:
        @wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            from vibrissa.whisker.rod import SimulationError

            try:
                return func(*args, **kwargs)
            except SimulationError as exc:
                raise ValueError(
                    named(f"the solver did not converge on these parameters ({exc}); {remedy}")
                ) from exc
            except ValueError as exc:
                raise ValueError(named(str(exc))) from exc

        return wrapper  # type: ignore[return-value]

    return decorate


def option_renamer(names: dict[str, str]) -> Callable[[str], str]:
    """A function that writes a library's parameter names in a message as option names.

    Parameters
    ----------
    names
        Parameter name -> option, e.g. ``{"noise_v": "--noise-v"}``; only whole
        words are replaced.
    """
    pattern = re.compile(r"\b(" + "|".join(map(re.escape, names)) + r")\b")

    def rename(message: str) -> str:
        return pattern.sub(lambda m: names[m.group(1)], message)

    return rename


def count_option(option: str, value: int | None, minimum: int = 1) -> int | None:
    """Check an integer option that counts something (``None``: not given).

    ``minimum`` is 1 (a positive count) or 0 (a non-negative one, e.g. a seed).

    Raises
    ------
    ValueError
        ``OPTION: expected a positive integer, got VALUE`` (``non-negative`` for
        ``minimum=0``).
    """
    if value is not None and value < minimum:
        kind = "non-negative" if minimum == 0 else "positive"
        raise ValueError(f"{option}: expected a {kind} integer, got {value}")
    return value


def regular_file(option: str, path: Path) -> Path:
    """Check a file input before it is opened: it exists, is a regular file, is readable.

    A FIFO would block the command forever, a device (``/dev/zero``) would never end,
    and a directory gives an error from deep inside a reader.

    Raises
    ------
    ValueError
        ``OPTION: PATH does not exist`` / ``is not a regular file`` / ``is not readable``.
    """
    if not path.exists():
        raise ValueError(f"{option}: {path} does not exist")
    if not path.is_file():
        raise ValueError(f"{option}: {path} is not a regular file")
    if not os.access(path, os.R_OK):
        raise ValueError(f"{option}: {path} is not readable")
    return path


def generation_disk_bytes(protocol: Any, out: Path) -> int:
    """Disk that generating ``protocol`` into ``out`` needs at its peak.

    Its shards and the finished file exist at once (2 x the signal's bytes), less what
    the shards an interrupted run kept already hold.
    """
    from vibrissa.experiments.generate import dataset_bytes, parts_dir

    parts = parts_dir(out)
    kept = sum(f.stat().st_size for f in parts.iterdir() if f.is_file()) if parts.is_dir() else 0
    return max(2 * dataset_bytes(protocol) - kept, 0)


def free_space(option: str, path: Path, needed_bytes: int, what: str) -> None:
    """Refuse to start work whose output will not fit on its filesystem.

    A full disk is reported cleanly wherever it happens (the writes are atomic), but
    only after the simulation it was meant to keep; this says so before it starts.

    Parameters
    ----------
    option
        The option naming the output, e.g. ``"-o"``.
    path
        The output (it and its parents need not exist yet).
    needed_bytes
        What the work writes at its peak (e.g. a dataset's shards and the file).
    what
        What is written, for the message: ``"the dataset and its shards"``.

    Raises
    ------
    ValueError
        ``OPTION: PATH needs about X MB for WHAT; DIR has Y MB free``.
    """
    where = Path(path).absolute().parent
    while not where.exists() and where != where.parent:
        where = where.parent
    try:
        free = shutil.disk_usage(where).free
    except OSError:  # cannot tell: the writes report it if it happens
        return
    if needed_bytes > free:
        raise ValueError(
            f"{option}: {path} needs about {needed_bytes / 1e6:,.0f} MB for {what}; "
            f"{where} has {free / 1e6:,.0f} MB free"
        )


#: Largest seed a command accepts: datasets store it as a signed 64-bit integer.
MAX_SEED = 2**63 - 1


def seed_option(option: str, value: int) -> int:
    """Check a seed: a non-negative integer the dataset format can store.

    Raises
    ------
    ValueError
        ``OPTION: expected a non-negative integer ...`` or ``... at most 2**63 - 1`` (a
        larger seed simulated everything and then failed writing the dataset).
    """
    count_option(option, value, minimum=0)
    if value > MAX_SEED:
        raise ValueError(
            f"{option}: expected an integer at most 2**63 - 1 (what a dataset stores), got {value}"
        )
    return value


def print_table(table: Any, stderr: bool = False) -> None:
    """Print a rich table so that no cell is ever cut short.

    Outside a terminal (a pipe, a file, a CI log) rich would lay the table out at 80
    columns and end long cells such as classifier names with an ellipsis; there the
    console is as wide as the table needs. In a terminal, a cell folds onto further lines
    but never inside a word, and a table that cannot fit even then is printed at its
    least width and left to the terminal to wrap. A rich ``Group`` (a table with a line
    under it, as the full chapter-5 run prints) has each of its tables printed so and
    anything else as it is.
    """
    from rich.console import Console, Group

    if isinstance(table, Group):
        for part in table.renderables:
            if hasattr(part, "columns"):
                print_table(part, stderr=stderr)
            else:
                Console(stderr=stderr, highlight=False, soft_wrap=True).print(part)
        return

    for column in table.columns:
        # a name is never split inside a word, nor ended with an ellipsis
        words = [w for cell in column.cells if isinstance(cell, str) for w in cell.split()]
        longest = max((len(w) for w in words), default=0)
        column.min_width = max(column.min_width or 0, longest)
        column.overflow = "fold"
    console = Console(stderr=stderr, highlight=False)
    need = Console(width=100_000).measure(table)
    if not console.is_terminal:
        console = Console(stderr=stderr, highlight=False, width=max(need.maximum, 20))
    elif need.minimum > console.width:
        # narrower than the table's least width: rich would cut columns off; the lines
        # are printed whole and the terminal wraps them
        console = Console(stderr=stderr, highlight=False, width=need.minimum)
    console.print(table)
