"""Usage errors of the whole command line are one line naming the option (issue 13, 7).

On the old main a wrong type, a missing value or an unknown option printed a
5-6-line usage box, and ``--seed -1`` did not name the option.
"""

from __future__ import annotations

import sys

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()
GEN = ["generate", "radial-distance", "--out", "x.nc"]


@pytest.mark.parametrize(
    ("args", "line"),
    [
        ([*GEN, "--workers", "abc"], "error: --workers: expected an integer, got 'abc'"),
        ([*GEN, "--seed", "-1"], "error: --seed: expected a non-negative integer, got -1"),
        ([*GEN, "--seed", "1.5"], "error: --seed: expected an integer, got '1.5'"),
        ([*GEN, "--unknown-flag"], "error: no such option: --unknown-flag"),
        (["generate"], "error: PROTOCOL: missing; this argument is required"),
        (["generate", "radial-distance"], "error: --out: missing; this option is required"),
        (["generate", "radial-distance", "--out"], "error: --out: needs a value"),
        (["plot", "x.nc", "--out", "o", "--dpi", "5"], "error: --dpi: must be at least 20, got 5"),
        (
            ["whisker", "info", "--length-mm", "abc"],
            "error: --length-mm: expected a number, got 'abc'",
        ),
        (
            ["whisker", "info", "--lenght-mm", "3"],
            "error: no such option: --lenght-mm (did you mean --length-mm?)",
        ),
        (
            ["whisker", "info", "--rigid-follicle=3"],
            "error: --rigid-follicle: does not take a value",
        ),
        (
            ["reproduce", "radial-distance", "--seed", "x"],
            "error: --seed: expected an integer, got 'x'",
        ),
        (["--bogus"], "error: no such option: --bogus"),
    ],
)
def test_usage_errors_are_one_line_naming_the_option(args, line, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res = runner.invoke(app, args)
    assert res.exit_code == 2
    assert res.stderr == line + "\n"
    assert res.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_an_unknown_command_lists_the_commands():
    res = runner.invoke(app, ["whisker", "bogus"])
    assert res.exit_code == 2
    assert res.stderr == (
        "error: no such command 'bogus' (commands: presets, info, static, push, ring, whisk)\n"
    )


@pytest.mark.parametrize(
    "args",
    [
        ["--help"],
        ["generate", "--help"],
        ["whisker", "--help"],
        ["reproduce", "radial-distance", "--help"],
    ],
)
def test_help_is_still_the_help(args):
    res = runner.invoke(app, args)
    assert res.exit_code == 0
    assert "Usage: vibrissa" in res.stdout and "--help" in res.stdout
    assert res.stderr == ""


def test_a_bare_command_group_still_shows_its_help():
    res = runner.invoke(app, ["whisker"])
    assert "Usage: vibrissa whisker" in res.output and "presets" in res.output
    assert "error:" not in res.output


def _every_command(group, path=()):
    """Paths of every command of the click group, sub-groups included."""
    import click

    for name, cmd in group.commands.items():
        if isinstance(cmd, click.Group):
            yield from _every_command(cmd, (*path, name))
        else:
            yield (*path, name)


def test_help_shows_a_flag_as_a_flag_on_every_command():
    # typer 0.2x labelled each flag with a type, "--version <bool>", as if it took a value
    import typer.main

    root = typer.main.get_command(app)
    paths = [(), *_every_command(root)]
    assert len(paths) > 10
    for path in paths:
        out = runner.invoke(app, [*path, "--help"], env={"COLUMNS": "200"})
        assert out.exit_code == 0, (path, out.output)
        assert "<bool>" not in out.output, path
        assert "--help" in out.output


@pytest.mark.parametrize("where", ["make_context", "invoke"])
def test_ctrl_c_anywhere_in_the_command_line_is_one_line(monkeypatch, capsys, where) -> None:
    """typer turned a Ctrl-C while options were parsed into a silent exit 130 (found by
    ``scripts/fuzz_cli_slow.py --signals``: 2 of 210 runs)."""
    import typer.core

    from vibrissa.cli import app

    def interrupted(self, *args, **kwargs):
        raise KeyboardInterrupt

    target = typer.core.TyperGroup if where == "make_context" else typer.core.TyperCommand
    monkeypatch.setattr(target, where, interrupted)
    monkeypatch.setattr(sys, "argv", ["vibrissa", "whisker", "presets"])
    with pytest.raises(SystemExit) as stop:
        app()
    assert stop.value.code == 130
    assert capsys.readouterr().err == "interrupted: the command stopped before it finished\n"
