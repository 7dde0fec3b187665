"""Tests of the console entry point, vibrissa.__main__ (signals at the edges of a command).

Each runs ``main()`` in a fresh interpreter whose command line is replaced by a stand-in,
so the moment of the signal is exact rather than a race; the interpreter runs a module
(``python -m``), as ``python -m vibrissa`` does, since CPython ends such a run by SIGINT
when it believes a KeyboardInterrupt went unhandled.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

PRELUDE = r"""
import os, signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)
import vibrissa.cli
sys.argv = ["vibrissa"]
"""


def _run(body: str, where: Path) -> subprocess.CompletedProcess[str]:
    (where / "stand_in.py").write_text(PRELUDE + body)
    return subprocess.run(
        [sys.executable, "-m", "stand_in"], cwd=where, capture_output=True, text=True, timeout=120
    )


def test_an_interrupt_that_left_an_exec_still_exits_130(tmp_path) -> None:
    """``exec`` of a string marks a KeyboardInterrupt leaving it as unhandled for good;
    ``python -m vibrissa`` then ended by SIGINT (-2) after printing its line (found by
    ``scripts/fuzz_cli_slow.py --signals``: Ctrl-C while NumPy was being imported)."""
    res = _run(
        'vibrissa.cli.main = lambda: exec("raise KeyboardInterrupt")\n'
        "from vibrissa.__main__ import main\nmain()\n",
        tmp_path,
    )
    assert res.returncode == 130, (res.returncode, res.stderr)
    assert res.stderr.strip().splitlines() == [
        "interrupted: the command stopped before it finished"
    ]


@pytest.mark.parametrize(("cause", "code"), [("KeyboardInterrupt", 130), ("Terminated", 143)])
def test_an_interrupt_inside_an_extensions_import_is_an_interruption(tmp_path, cause, code) -> None:
    """Issue 33: a signal while a C extension initialised was an ImportError traceback."""
    res = _run(
        "from vibrissa._signals import Terminated\n"
        "def cli():\n"
        "    try:\n"
        f"        raise {cause}\n"
        "    except BaseException as exc:\n"
        "        raise ImportError('initialization failed') from exc\n"
        "vibrissa.cli.main = cli\n"
        "from vibrissa.__main__ import main\nmain()\n",
        tmp_path,
    )
    assert res.returncode == code, (res.returncode, res.stderr)
    assert "Traceback" not in res.stderr
    assert res.stderr.strip().splitlines()[-1].startswith("interrupted:")


def test_an_import_error_that_is_not_an_interrupt_stays_a_bug(tmp_path) -> None:
    res = _run(
        "def cli():\n    raise ImportError('no module named x')\n"
        "vibrissa.cli.main = cli\nfrom vibrissa.__main__ import main\nmain()\n",
        tmp_path,
    )
    assert res.returncode == 1 and "ImportError: no module named x" in res.stderr


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_signal_after_the_command_finished_leaves_its_result(tmp_path, sig) -> None:
    """A signal during the interpreter's teardown ended a finished command by that signal
    (status -15 to its parent: SIGTERMs 2.82 and 2.87 s into ``whisker presets``)."""
    res = _run(
        "vibrissa.cli.main = lambda: print('done')\n"
        "from vibrissa.__main__ import main\nmain()\n"
        f"os.kill(os.getpid(), signal.{sig})\n"
        "print('still here')\n",
        tmp_path,
    )
    assert res.returncode == 0, (res.returncode, res.stderr)
    assert res.stdout.split() == ["done", "still", "here"] and res.stderr == ""
