"""The ``vibrissa`` console script (and ``python -m vibrissa``): signals at any moment.

A long command reports Ctrl-C (SIGINT) and ``kill`` (SIGTERM) itself, saying what it
kept (:func:`vibrissa.cli._interrupt.interruptible`). A signal can also come before
such a command starts or after it ends: while the command line is still being imported,
while options are checked, while a short command runs. This entry point catches those
too, so every moment gives one ``interrupted:`` line on standard error and exit status
130 (SIGINT) or 143 (SIGTERM), never a traceback. It installs its SIGTERM handler
before it imports anything heavy, and importing the package does no work, so the only
moment left uncovered is the interpreter's own start (a few milliseconds, before any
of vibrissa runs).

Before that import it also checks the process' memory limit
(:mod:`vibrissa._address_space`): below what the libraries need to load, it says so in
one line (exit 2) instead of an ``ImportError`` traceback or OpenBLAS retrying its
allocation forever; close to it, it starts OpenBLAS with as many threads as fit.
"""

from __future__ import annotations

import sys

try:  # Ctrl-C in the first milliseconds: ``signal`` builds its enums in Python
    import os
    import signal

    from vibrissa._signals import INTERRUPTED, Terminated, interrupt_in, raise_terminated
except KeyboardInterrupt:  # pragma: no cover - tested by timing (fuzz_cli_slow --signals)
    sys.stderr.write("interrupted: the command stopped before it finished\n")  # INTERRUPTED
    raise SystemExit(130) from None

__all__ = ["main"]


def main() -> None:
    """Run the command line; a stray SIGINT or SIGTERM is one line and exit 130 / 143."""
    signal.signal(signal.SIGTERM, raise_terminated)  # first: before any import
    try:
        from vibrissa._address_space import THREADS_VAR, limit_mib, plan

        memory = plan(limit_mib(), os.environ)
        if memory.error is not None:
            print(memory.error, file=sys.stderr)
            sys.exit(2)
        if memory.threads is not None:
            os.environ[THREADS_VAR] = str(memory.threads)
        from vibrissa.cli import main as cli_main

        cli_main()
    except KeyboardInterrupt:
        code = 128 + signal.SIGINT
    except Terminated:
        code = 128 + signal.SIGTERM
    except ImportError as exc:  # an interrupt inside a C extension's initialisation
        sig = interrupt_in(exc)
        if sig is None:
            raise
        code = 128 + sig
    else:
        return
    finally:
        _forget_handled_interrupts()
        _ignore_interrupts()
    print(INTERRUPTED, file=sys.stderr)
    sys.exit(code)


def _ignore_interrupts() -> None:
    """Ignore SIGINT and SIGTERM once the command is over, output written or refused.

    What is left is the interpreter's teardown, during which Python puts the default
    handlers back: a signal then ended the process by that signal, after the command
    had finished (status -15 to its parent: SIGTERMs 2.82 and 2.87 s into ``whisker
    presets``, once its table was printed). The command's result stands instead.
    """
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_IGN)


def _forget_handled_interrupts() -> None:
    """Clear CPython's record of a KeyboardInterrupt that left an ``exec`` of a string.

    ``exec(text)`` runs through ``PyRun_StringFlags``, which marks the interpreter as
    ended by an unhandled KeyboardInterrupt whenever one leaves the executed code
    (``_Py_UnhandledKeyboardInterrupt`` in CPython 3.11's ``pythonrun.c``), even when a
    caller catches it. NumPy, dataclasses and namedtuple ``exec`` generated code while
    they are imported, so a Ctrl-C during the command line's import, reported here with
    exit 130, ended ``python -m vibrissa`` by SIGINT instead (status -2 to its parent,
    measured: 17 of 30 interrupts 0.2-0.4 s after the start of ``whisker presets``).
    Each such run starts by clearing the mark, so a harmless one clears it.
    """
    exec("None")  # a constant: see the docstring


if __name__ == "__main__":
    main()
