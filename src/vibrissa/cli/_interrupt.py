"""Interrupted commands say what they kept and how to go on.

A long command (``vibrissa generate``, ``vibrissa reproduce ...``) runs inside
:func:`interruptible`: Ctrl-C (SIGINT) or ``kill`` (SIGTERM) stops it with one line
on standard error, ``interrupted: <what was kept>``, and the conventional exit
status 128 + signal number (130, 143) instead of a traceback or silence.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType

import typer

from vibrissa._signals import Terminated, interrupt_in, raise_terminated

__all__ = ["interruptible", "uninterrupted"]


@contextlib.contextmanager
def interruptible(kept: Callable[[], str]) -> Iterator[None]:
    """Report SIGINT and SIGTERM during the block in one line and exit 130 / 143.

    Parameters
    ----------
    kept
        Called after the interruption (once the block has unwound, so workers are
        stopped and temporary files removed): what was kept and how to resume, e.g.
        ``"12 of 24 trials kept in x.nc.parts/; rerun the same command to resume"``.
    """
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, raise_terminated) if main else None
    try:
        yield
        return
    except KeyboardInterrupt:
        code = 128 + signal.SIGINT
    except Terminated:
        code = 128 + signal.SIGTERM
    except ImportError as exc:  # an interrupt inside a C extension's initialisation
        sig = interrupt_in(exc)
        if sig is None:
            raise
        code = 128 + sig
    finally:
        if main:
            signal.signal(signal.SIGTERM, previous)
    print(f"interrupted: {kept()}", file=sys.stderr)
    raise typer.Exit(code=code)


@contextlib.contextmanager
def uninterrupted() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back until the block is done, then deliver them.

    For a short step that must happen whole or not at all (a batch pushed through the
    live pipeline and its events written): an interruption arriving inside it would
    leave the records counted but never processed. Off the main thread the block runs
    as is (signals only reach the main thread).
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum: int, frame: FrameType | None) -> None:
        held.append(signum)

    before_int = signal.signal(signal.SIGINT, hold)
    before_term = signal.signal(signal.SIGTERM, hold)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before_int)
        signal.signal(signal.SIGTERM, before_term)
    if held:
        signal.raise_signal(held[0])
