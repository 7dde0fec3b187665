"""Helpers shared by the command-line modules: JSON output and error reporting."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from functools import wraps
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


def user_errors(func: F) -> F:
    """Turn a user's bad input (``ValueError``, ``TypeError``, ``OSError``, ``KeyError``)
    into one clear line on standard error and exit status 2, instead of a traceback."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except (ValueError, TypeError, OSError, KeyError) as exc:
            msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            print(f"error: {msg}", file=sys.stderr)
            raise typer.Exit(code=2) from exc

    return wrapper  # type: ignore[return-value]


def physics_errors(func: F) -> F:
    """Report a solver failure (``SimulationError``) as one line on standard error and
    exit status 1, instead of a traceback."""

    @wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        from vibrissa.whisker.rod import SimulationError

        try:
            return func(*args, **kwargs)
        except SimulationError as exc:
            print(f"error: simulation failed: {exc}", file=sys.stderr)
            raise typer.Exit(code=1) from exc

    return wrapper  # type: ignore[return-value]
