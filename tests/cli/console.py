"""Running the installed ``vibrissa`` console script from tests (a helper, not tests)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def console_script() -> str:
    """The ``vibrissa`` console script of this environment (skip the test if missing)."""
    beside = Path(sys.executable).with_name("vibrissa")
    found = str(beside) if beside.exists() else shutil.which("vibrissa")
    if found is None:
        pytest.skip("the vibrissa console script is not installed")
    return found


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _spawn(args: list[str]) -> subprocess.Popen:
    """``vibrissa ARGS`` as a child whose output is read and who can be interrupted."""
    return subprocess.Popen(
        [console_script(), *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "CI": "1"},
        # a job started in a shell's background inherits an ignored SIGINT, and Python
        # then installs no KeyboardInterrupt: give the child the default disposition
        preexec_fn=_default_sigint,
    )


def interrupt_once_a_shard_exists(args: list[str], parts: Path, sig: int) -> tuple[int, str]:
    """Run ``vibrissa ARGS`` and send ``sig`` once a shard is in ``parts``.

    Returns
    -------
    (int, str)
        The exit status and standard error (standard output must be empty).
    """
    proc = _spawn(args)
    deadline = time.monotonic() + 300
    while not any(parts.glob("chunk-*.npz")):
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            _, err = proc.communicate()
            pytest.fail(f"no shard appeared in {parts} (status {proc.returncode}): {err}")
        time.sleep(0.02)
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    assert out == ""
    return proc.returncode, err


def interrupt_after(args: list[str], seconds: float, sig: int) -> tuple[int, str]:
    """Run ``vibrissa ARGS``, send ``sig`` after ``seconds``; exit status and stderr."""
    proc = _spawn(args)
    time.sleep(seconds)
    if proc.poll() is not None:
        _, err = proc.communicate()
        pytest.fail(f"finished before the signal (status {proc.returncode}): {err}")
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err
