"""Tests of vibrissa._signals (interrupts as exceptions, and found inside ImportErrors)."""

from __future__ import annotations

import signal

import pytest

from vibrissa._signals import Terminated, interrupt_in, raise_terminated


def _import_error_from(cause: BaseException) -> ImportError:
    try:
        try:
            raise cause
        except BaseException as exc:
            raise ImportError("initialization failed") from exc  # as pybind11 does
    except ImportError as wrapped:
        return wrapped


def test_interrupts_are_found_directly_and_inside_import_errors() -> None:
    assert interrupt_in(KeyboardInterrupt()) == signal.SIGINT
    assert interrupt_in(Terminated()) == signal.SIGTERM
    assert interrupt_in(_import_error_from(KeyboardInterrupt())) == signal.SIGINT
    assert interrupt_in(_import_error_from(Terminated())) == signal.SIGTERM
    assert interrupt_in(_import_error_from(_import_error_from(Terminated()))) == signal.SIGTERM


def test_other_failures_are_not_interrupts() -> None:
    assert interrupt_in(ImportError("no module named x")) is None
    assert interrupt_in(_import_error_from(ValueError())) is None
    assert interrupt_in(ValueError()) is None
    a, b = ImportError("a"), ImportError("b")
    a.__cause__, b.__cause__ = b, a  # a cycle ends
    assert interrupt_in(a) is None


def test_the_handler_raises_terminated() -> None:
    with pytest.raises(Terminated):
        raise_terminated(signal.SIGTERM, None)
