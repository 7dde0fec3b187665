"""One-line usage errors for the whole ``vibrissa`` command line.

typer reports a value of the wrong type, a missing value or argument, an unknown
option or command as a usage box: the usage line, a hint and a framed message.
:class:`OneLineUsageErrors`, the class of the top-level command group, reports each
of them instead as one line on standard error that names the option,
``error: --seed: expected an integer, got 'x'``, with exit status 2 -- the same as
every other bad input (:func:`vibrissa.cli._common.user_errors`). ``--help``, the
help shown for a bare command group and every command's own output are unchanged.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator
from typing import Any

import typer
from typer._click import exceptions as click_errors
from typer.core import TyperGroup

from vibrissa._signals import INTERRUPTED

__all__ = ["OneLineUsageErrors", "flags_show_no_type", "usage_message"]

#: pydantic error types (typer converts values with pydantic) -> what was expected.
_EXPECTED = {
    "int_parsing": "an integer",
    "int_from_float": "an integer",
    "int_type": "an integer",
    "float_parsing": "a number",
    "float_type": "a number",
    "bool_parsing": "true or false",
    "bool_type": "true or false",
    "finite_number": "a finite number",
}
_BOUNDS = {
    "greater_than_equal": ("ge", "at least"),
    "greater_than": ("gt", "greater than"),
    "less_than_equal": ("le", "at most"),
    "less_than": ("lt", "less than"),
}


def _label(param: Any) -> str | None:
    """``--long-name`` of an option, ``NAME`` of an argument."""
    if param is None:
        return None
    opts = [o for o in getattr(param, "opts", []) if o.startswith("--")]
    if getattr(param, "param_type_name", "") == "option" and opts:
        return max(opts, key=len)
    name = getattr(param, "name", None)
    return name.upper() if name else None


def _sentence(text: str) -> str:
    """A message as a clause: first letter lower-case, no final full stop, one line."""
    text = " ".join(str(text).split()).rstrip(".")
    return text[:1].lower() + text[1:] if text[1:2].islower() or len(text) == 1 else text


def _reason(exc: click_errors.BadParameter) -> str:
    """What was wrong with the value, with the value itself where it is known."""
    cause = exc.__cause__
    errors = getattr(cause, "errors", None)
    if callable(errors):
        try:
            err = errors()[0]
        except (IndexError, TypeError, ValueError):
            err = None
        if err is not None:
            kind, ctx = err.get("type", ""), err.get("ctx") or {}
            got = f", got {err['input']!r}" if "input" in err else ""
            if kind in _EXPECTED:
                return f"expected {_EXPECTED[kind]}{got}"
            if kind in _BOUNDS:
                key, words = _BOUNDS[kind]
                bound = ctx.get(key)
                got = f", got {err['input']}" if "input" in err else ""
                if kind == "greater_than_equal" and bound in (0, 1):
                    sign = "non-negative" if bound == 0 else "positive"
                    return f"expected a {sign} integer{got}"
                return f"must be {words} {bound}{got}"
            return f"{_sentence(err.get('msg', exc.message))}{got}"
    return _sentence(exc.message)


def usage_message(exc: click_errors.UsageError) -> str:
    """The one line (without ``error:``) that reports a typer/click usage error.

    Parameters
    ----------
    exc
        Any usage error raised while parsing a command line.

    Returns
    -------
    str
        ``OPTION: what is wrong`` when the error concerns one option or argument,
        else the error's own message as one clause.
    """
    param = getattr(exc, "param", None)
    label = _label(param)
    if isinstance(exc, click_errors.MissingParameter):
        kind = getattr(param, "param_type_name", "option")
        return (
            f"{label}: missing; this {kind} is required"
            if label
            else _sentence(exc.format_message())
        )
    if isinstance(exc, click_errors.BadParameter):
        return f"{label}: {_reason(exc)}" if label else _sentence(exc.format_message())
    if isinstance(exc, click_errors.NoSuchOption):
        text = f"no such option: {exc.option_name}"
        if exc.possibilities:
            text += f" (did you mean {' or '.join(sorted(exc.possibilities))}?)"
        return text
    if isinstance(exc, click_errors.BadOptionUsage):
        message = exc.format_message()
        for phrase in ("requires an argument", "does not take a value"):
            if phrase in message:
                verb = "needs a value" if phrase == "requires an argument" else phrase
                return f"{exc.option_name}: {verb}"
        return _sentence(message)
    message = _sentence(exc.format_message())
    ctx = getattr(exc, "ctx", None)
    if message.startswith("no such command") and ctx is not None:
        names = ", ".join(ctx.command.list_commands(ctx))  # type: ignore[attr-defined]
        return f"{message} (commands: {names})"
    return message


@contextlib.contextmanager
def _one_line() -> Iterator[None]:
    try:
        yield
    except click_errors.NoArgsIsHelpError:
        raise  # a bare command group shows its help
    except click_errors.UsageError as exc:
        print(f"error: {usage_message(exc)}", file=sys.stderr)
        raise typer.Exit(code=2) from exc


class OneLineUsageErrors(TyperGroup):
    """Top-level command group that reports every usage error in one line (exit 2).

    Parsing errors of the group's own options surface in :meth:`make_context`, those
    of every subcommand (and nested group) in :meth:`invoke`. A Ctrl-C that no command
    reported itself (:func:`vibrissa.cli._interrupt.interruptible`) is one line too:
    typer would turn it into a silent exit 130.
    """

    def make_context(self, *args: Any, **kwargs: Any) -> Any:
        with _one_line():
            return super().make_context(*args, **kwargs)

    def invoke(self, ctx: Any) -> Any:
        try:
            with _one_line():
                return super().invoke(ctx)
        except KeyboardInterrupt:
            print(INTERRUPTED, file=sys.stderr)
            raise typer.Exit(code=130) from None

    def main(self, *args: Any, **kwargs: Any) -> Any:
        """Run the command line; a Ctrl-C outside :meth:`invoke` is one line too.

        typer turns a KeyboardInterrupt anywhere in its main (while the options are
        parsed, or as the context closes after the command) into a silent exit 130:
        ``fuzz_cli_slow --signals`` found 2 of 210 runs that stopped so, without their
        ``interrupted:`` line. That exit is recognised by its cause (typer raises it
        ``from`` the KeyboardInterrupt; the handlers here and in
        :func:`~vibrissa.cli._interrupt.interruptible` print first and raise without one).
        """
        try:
            return super().main(*args, **kwargs)
        except SystemExit as exc:
            stopped = exc.__context__
            if exc.code == 130 and isinstance(
                getattr(stopped, "__cause__", None), KeyboardInterrupt
            ):
                print(INTERRUPTED, file=sys.stderr)
            raise


def flags_show_no_type() -> None:
    """Show a flag in ``--help`` as a flag, without a value type.

    Recent typer (0.2x) labels every option's type in the help, flags included
    (``--version <bool>``), which reads as if the flag took a value. A flag's type label
    is dropped here; every other option keeps its own. Safe to call more than once, and
    a no-op on a typer without that hook.
    """
    from typer.core import TyperOption

    shown = getattr(TyperOption, "display_type_rich", None)
    if shown is None or getattr(shown, "flags_untyped", False):
        return

    def display_type_rich(self: Any, ctx: Any) -> str | None:
        return None if getattr(self, "is_flag", False) else shown(self, ctx)

    display_type_rich.flags_untyped = True  # type: ignore[attr-defined]
    TyperOption.display_type_rich = display_type_rich  # type: ignore[method-assign]
