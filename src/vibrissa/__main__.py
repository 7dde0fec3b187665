"""The ``vibrissa`` console script (and ``python -m vibrissa``): signals at any moment.

A long command reports Ctrl-C (SIGINT) and ``kill`` (SIGTERM) itself, saying what it
kept (:func:`vibrissa.cli._interrupt.interruptible`). A signal can also come before
such a command starts or after it ends: while the command line is still being imported,
while options are checked, while a short command runs. This entry point catches those
too, so every moment gives one ``interrupted:`` line on standard error and exit status
130 (SIGINT) or 143 (SIGTERM), never a traceback. It installs its SIGTERM handler
before it imports anything heavy.
"""

from __future__ import annotations

import signal
import sys
from types import FrameType

from vibrissa._signals import INTERRUPTED

__all__ = ["main"]


class _Terminated(BaseException):
    """SIGTERM outside a command's own handler."""


def _raise_terminated(signum: int, frame: FrameType | None) -> None:
    raise _Terminated


def main() -> None:
    """Run the command line; a stray SIGINT or SIGTERM is one line and exit 130 / 143."""
    signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        from vibrissa.cli import main as cli_main

        cli_main()
    except KeyboardInterrupt:
        code = 128 + signal.SIGINT
    except _Terminated:
        code = 128 + signal.SIGTERM
    else:
        return
    print(INTERRUPTED, file=sys.stderr)
    sys.exit(code)


if __name__ == "__main__":
    main()
