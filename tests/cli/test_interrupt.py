"""Interrupted commands (cli._interrupt): reported in one line, or held back over a step."""

from __future__ import annotations

import os
import signal

import pytest
import typer

from vibrissa._signals import Terminated
from vibrissa.cli._interrupt import interruptible, uninterrupted


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_inside_the_step_is_delivered_after_it(signum: int) -> None:
    seen: list[str] = []
    caught: list[int] = []

    def record(s: int, frame: object) -> None:
        caught.append(s)

    before = signal.signal(signum, record)
    try:
        with uninterrupted():
            os.kill(os.getpid(), signum)
            seen.append("the rest of the step ran")
            assert caught == []
        assert seen == ["the rest of the step ran"]
        assert caught == [signum]
        assert signal.getsignal(signum) is record
    finally:
        signal.signal(signum, before)


@pytest.fixture
def ctrl_c():
    """Python's own SIGINT handler for the test (a CI runner may start it with SIGINT
    ignored, and a child inherits that)."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


def test_ctrl_c_inside_the_step_raises_keyboard_interrupt_after_it(ctrl_c) -> None:
    done = []
    with pytest.raises(KeyboardInterrupt):
        with uninterrupted():
            os.kill(os.getpid(), signal.SIGINT)
            done.append(1)
    assert done == [1]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_no_signal_no_effect(ctrl_c) -> None:
    term = signal.getsignal(signal.SIGTERM)
    with uninterrupted():
        pass
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert signal.getsignal(signal.SIGTERM) is term


@pytest.mark.parametrize(("cause", "code"), [(KeyboardInterrupt, 130), (Terminated, 143)])
def test_an_interrupt_wrapped_by_an_extensions_import_is_reported(capsys, cause, code) -> None:
    """pybind11 turns an exception inside a module's init into ``ImportError:
    initialization failed`` (SciPy's HiGHS wrapper, imported inside long commands)."""
    with pytest.raises(typer.Exit) as stop:
        with interruptible(lambda: "nothing kept"):
            try:
                raise cause
            except BaseException as exc:
                raise ImportError("initialization failed") from exc
    assert stop.value.exit_code == code
    assert capsys.readouterr().err == "interrupted: nothing kept\n"


def test_an_import_error_of_its_own_passes_through() -> None:
    with pytest.raises(ImportError, match="no module"):
        with interruptible(lambda: "nothing kept"):
            raise ImportError("no module named x")
