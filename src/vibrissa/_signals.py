"""SIGINT and SIGTERM as exceptions, and the line an interrupted command prints.

Shared by the console entry point (:mod:`vibrissa.__main__`, before the command line is
imported), the command group (:mod:`vibrissa.cli._usage`) and long commands
(:mod:`vibrissa.cli._interrupt`). Imports nothing but the standard library's
``signal``: the entry point loads it before it installs its handlers.
"""

from __future__ import annotations

import signal
from types import FrameType

__all__ = ["INTERRUPTED", "Terminated", "interrupt_in", "raise_terminated"]

#: What an interrupted command says when it has nothing more precise to say.
INTERRUPTED = "interrupted: the command stopped before it finished"


class Terminated(BaseException):
    """SIGTERM as an exception.

    A ``BaseException``, like ``KeyboardInterrupt``, so that no ``except Exception`` on the
    way swallows it.
    """


def raise_terminated(signum: int, frame: FrameType | None) -> None:
    """A SIGTERM handler: raise :class:`Terminated`."""
    raise Terminated


def interrupt_in(exc: BaseException) -> int | None:
    """The signal (SIGINT, SIGTERM) whose exception ``exc`` is or was raised from.

    A signal's exception raised while a C extension module initialises comes back as
    ``ImportError: initialization failed`` with the interrupt as its cause (pybind11's
    module init, e.g. SciPy's HiGHS wrapper): that ImportError is an interruption too,
    not a broken installation.

    Returns
    -------
    int or None
        ``signal.SIGINT``, ``signal.SIGTERM`` or ``None`` when no interrupt is in the
        chain of causes and contexts.
    """
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        seen.add(id(e))
        if isinstance(e, KeyboardInterrupt):
            return int(signal.SIGINT)
        if isinstance(e, Terminated):
            return int(signal.SIGTERM)
        if not isinstance(e, ImportError):
            return None
        e = e.__cause__ or e.__context__
    return None
