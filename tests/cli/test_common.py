"""One-line errors of the command line: paths named, solver limits as bad input (issue 13, 7).

On the old main a full disk and an existing ``plot --out`` file printed a bare
``[Errno ...]`` without the path, and a solver that did not converge on the user's
own whisker parameters exited with status 1 ("simulation failed"), as for a bug.
"""

from __future__ import annotations

import errno
import os
import shutil

import pytest
import typer
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.cli._common import count_option, error_message, solver_limits, user_errors
from vibrissa.examples import example_path
from vibrissa.whisker.rod import SimulationError

runner = CliRunner()


@pytest.mark.parametrize(
    ("exc", "line"),
    [
        (
            OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), "out.nc"),
            "out.nc: No space left on device",
        ),
        (
            PermissionError(errno.EACCES, os.strerror(errno.EACCES), "/root/x"),
            "/root/x: Permission denied",
        ),
        (
            OSError(errno.EXDEV, os.strerror(errno.EXDEV), "a", None, "b"),
            "a -> b: Invalid cross-device link",
        ),
        (FileNotFoundError("dataset file not found: x.nc"), "dataset file not found: x.nc"),
        (KeyError("no variable 'data'"), "no variable 'data'"),
        (ValueError("bad\nvalue"), "bad value"),
    ],
)
def test_error_message_is_one_line_and_names_the_path(exc, line):
    assert error_message(exc) == line


def _mapped_import(tmp_path):
    src = tmp_path / "data.mat"
    shutil.copyfile(example_path("data_XY_small.mat"), src)
    mapping = example_path("data_XY_small.mapping.json")
    return ["import", str(src), "--mapping", str(mapping), "--out", str(tmp_path / "x.nc")]


def test_a_full_disk_during_a_command_names_the_output(tmp_path, monkeypatch):
    def no_space(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr("vibrissa._atomic.os.fsync", no_space)
    res = runner.invoke(app, _mapped_import(tmp_path))
    assert res.exit_code == 2
    assert res.stderr == f"error: {tmp_path / 'x.nc'}: No space left on device\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data.mat"]


def test_an_output_directory_named_by_an_existing_file_is_refused_by_name(tmp_path):
    blocker = tmp_path / "figures"
    blocker.write_text("keep")
    (tmp_path / "data.nc").write_text("not read: the output is refused first")
    res = runner.invoke(app, ["plot", str(tmp_path / "data.nc"), "--out", str(blocker)])
    assert res.exit_code == 2
    assert res.stderr == f"error: --out: {blocker} is a file, not a directory\n"
    assert blocker.read_text() == "keep"


def test_a_directory_where_a_file_is_wanted_is_refused_by_name(tmp_path):
    (tmp_path / "x.nc").mkdir()
    res = runner.invoke(app, _mapped_import(tmp_path))
    assert res.exit_code == 2
    assert res.stderr == f"error: --out: {tmp_path / 'x.nc'} is a directory, not a file\n"


def _command(exc: BaseException):
    @user_errors
    @solver_limits("use a smaller --force-n", lambda m: m.replace("force_n", "--force-n"))
    def command() -> None:
        raise exc

    return command


def test_a_solver_failure_on_the_users_parameters_is_bad_input(capsys):
    with pytest.raises(typer.Exit) as info:
        _command(SimulationError("static solve did not converge for force_n=1000"))()
    assert info.value.exit_code == 2
    assert capsys.readouterr().err == (
        "error: the solver did not converge on these parameters (static solve did not "
        "converge for --force-n=1000); use a smaller --force-n\n"
    )


def test_solver_limits_names_options_in_other_errors_and_passes_bugs_through(capsys):
    with pytest.raises(typer.Exit):
        _command(ValueError("force_n must be finite"))()
    assert capsys.readouterr().err == "error: --force-n must be finite\n"
    with pytest.raises(ZeroDivisionError):  # a bug stays a traceback (exit 1)
        _command(ZeroDivisionError("bug"))()


@pytest.mark.parametrize(
    ("value", "minimum", "message"),
    [
        (0, 1, "--workers: expected a positive integer, got 0"),
        (-1, 0, "--workers: expected a non-negative integer, got -1"),
    ],
)
def test_count_option(value, minimum, message):
    assert count_option("--workers", None) is None
    assert count_option("--workers", 3, minimum) == 3
    with pytest.raises(ValueError, match=message):
        count_option("--workers", value, minimum)
