"""A fuzzer over the command-line contract (issue 33, item 7).

Every option of every registered command, from the tables of :mod:`vibrissa.cli._contract`,
is given extreme and odd values (0, negative, subnormal, 1e300, NaN, infinities, 2**64,
empty and control-character strings, special files, deeply nested JSON) with the
simulation patched out: each command's work entry point raises :class:`WorkStarted`. The
contract: the command either reaches its work (the value is accepted) or exits 2 with one
``error:`` line and no traceback, creating nothing; it never exits 1, never raises, never
hangs. A deterministic sweep covers every option with every hostile value of its kind;
hypothesis then draws further values.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import signal
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner as ClickRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.cli._contract import CONTRACT, Spec
from vibrissa.examples import example_path

runner = CliRunner()
click_runner = ClickRunner()


class WorkStarted(BaseException):
    """Raised where a command's work begins: the options were accepted."""


class Hung(BaseException):
    """Raised by the alarm: the command neither refused nor reached its work in time."""


#: Where each command's work begins (patched to raise :class:`WorkStarted`).
WORK = (
    "vibrissa.experiments.generate.generate",
    "vibrissa.data.importers.import_file",
    "vibrissa.evaluate.figures.typical_traces_figure",
    "vibrissa.evaluate.figures.angle_texture_traces",
    "vibrissa.evaluate.figures.feature_contours",
    "vibrissa.experiments.identify.identify",
    "vibrissa.framework.stream.StreamGuard",
    "vibrissa.framework.calibrate.fit_pipeline_from_datasets",
    "vibrissa.whisker.rod.RodModel.static_force",
    "vibrissa.whisker.rod.RodModel.push",
    "vibrissa.experiments.ringdown.ring_down_test",
    "vibrissa.robots.whisking.run_whisking",
    "vibrissa.cli.bench.physics_benchmark",
    "vibrissa.reproduce.run_experiment",
    "vibrissa.thesis.crunchbot_slam.viewer.watch_run",
)
#: Work reached through a property: ``whisker info`` sets the follicle damper by root
#: finding on dense eigenvalues (seconds at 150 elements, more under load; a drawn
#: ``--n-elements 189`` counted as a hang on a loaded machine).
WORK_PROPERTIES = ("vibrissa.whisker.rod.RodModel.damping",)
#: Seconds a case may take before it counts as a hang.
TIMEOUT_S = 30

NUMBERS = ("0", "-1", "5e-324", "1e-320", "1e300", "-1e300", "nan", "inf", "-inf", "1e999")
INTEGERS = ("0", "-1", "18446744073709551616", "-18446744073709551616", "1.5", "x")
TEXTS = ("", ",", ",,", " ", "\x07", "\x00", "x" * 5000, "nan", "-", "1e300")


def _work(*args: Any, **kwargs: Any) -> Any:
    raise WorkStarted


@pytest.fixture(scope="module")
def assets() -> Iterator[dict[str, Path]]:
    """Valid inputs for the required options, and special files for the hostile ones."""
    from vibrissa.framework import TactilePipeline

    root = Path(tempfile.mkdtemp(prefix="fuzz-assets-"))
    mat = root / "data.mat"
    shutil.copyfile(example_path("data_XY_small.mat"), mat)
    mapping = root / "mapping.json"
    shutil.copyfile(example_path("data_XY_small.mapping.json"), mapping)
    words = ["import", str(mat), "--mapping", str(mapping), "-o", str(root / "d.nc")]
    res = runner.invoke(app, words)
    assert res.exit_code == 0, res.output
    TactilePipeline(1000.0, 1, 2).save(root / "p.vtp")
    (root / "dir").mkdir()
    os.mkfifo(root / "fifo")
    (root / "empty").write_text("")
    (root / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    yield {
        "mat": mat,
        "mapping": mapping,
        "dataset": root / "d.nc",
        "pipeline": root / "p.vtp",
        "dir": root / "dir",
        "fifo": root / "fifo",
        "empty": root / "empty",
        "deep": root / "deep.json",
    }
    shutil.rmtree(root, ignore_errors=True)


def _slow_profile() -> Any:
    """``scripts/fuzz_cli_slow.py`` (the slow profile) as a module: its required options."""
    import importlib.util

    path = Path(__file__).resolve().parents[2] / "scripts" / "fuzz_cli_slow.py"
    spec = importlib.util.spec_from_file_location("fuzz_cli_slow", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: The slow profile's valid values for each command's required options.
required = _slow_profile().required


@functools.cache
def _flag(path: str, name: str) -> tuple[str, bool]:
    """The option's flag (or "" for an argument) from the click command itself."""
    import typer.main

    cmd: Any = typer.main.get_command(app)
    for word in path.split():
        cmd = cmd.commands[word]
    (param,) = [p for p in cmd.params if p.name == name]
    if param.param_type_name == "argument":
        return "", False
    return max(param.opts, key=len), bool(getattr(param, "is_flag", False))


def argv(path: str, name: str, value: str, a: dict[str, Path]) -> list[str]:
    """The command line: the required options, with ``name`` given ``value``."""
    words = path.split()
    reqs = required(path, a)
    flag, _ = _flag(path, name)
    for opt, words_of_opt in reqs.items():
        if opt != name:
            words += words_of_opt
    if flag:
        words += [flag, value]
    else:  # an argument goes first after the command
        words.insert(len(path.split()), value)
    return words


def hostile(spec: Spec, a: dict[str, Path]) -> tuple[str, ...]:
    """The hostile values of an option of this kind."""
    files = (str(a["fifo"]), str(a["dir"]), "/dev/zero", "missing.file", str(a["empty"]))
    files += (str(a["deep"]),)
    if spec.kind == "number":
        return NUMBERS + ("x",)
    if spec.kind in ("integer", "seed"):
        return INTEGERS + NUMBERS[:4]
    if spec.kind == "file":
        return files
    if spec.kind == "refused":
        return (str(a["empty"]),)
    if spec.kind == "output":
        return (str(a["dir"]) if not spec.directory else str(a["empty"]), f"{a['empty']}/x", "")
    return TEXTS + files[:3] + (str(a["deep"]),)


def cases(a: dict[str, Path]) -> list[tuple[str, str, str]]:
    """Every (command, option, hostile value) of the sweep."""
    out = []
    for path, table in CONTRACT.items():
        for name, spec in table.items():
            if spec.kind == "flag":
                continue
            out += [(path, name, v) for v in hostile(spec, a)]
    return out


@contextmanager
def _alarm(seconds: int) -> Iterator[None]:
    def ring(signum: int, frame: Any) -> None:
        raise Hung

    previous = signal.signal(signal.SIGALRM, ring)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _listing(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> Any:
    """The command line as one click command, with every command's work patched out."""
    import typer.main

    for target in WORK:
        monkeypatch.setattr(target, _work)
    for target in WORK_PROPERTIES:
        monkeypatch.setattr(target, property(_work))
    return typer.main.get_command(app)


def run_case(words: list[str], command: Any) -> str:
    """Run one command line in a fresh directory; check the contract; say what happened."""
    with tempfile.TemporaryDirectory(prefix="fuzz-") as tmp:
        here = os.getcwd()
        os.chdir(tmp)
        before = _listing(Path(tmp))
        try:
            with _alarm(TIMEOUT_S):
                res = click_runner.invoke(command, words, catch_exceptions=True)
        except WorkStarted:
            return "accepted"
        except Hung:
            raise AssertionError(f"hang: vibrissa {words!r}") from None
        finally:
            os.chdir(here)
        out = res.stdout + res.stderr
        assert "Traceback" not in out, f"traceback: vibrissa {words!r}\n{out}"
        if res.exit_code == 0:
            return "finished"  # a quick command that did its (unpatched, cheap) work
        assert res.exit_code == 2, f"exit {res.exit_code}: vibrissa {words!r} {res.exception!r}"
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: "), f"vibrissa {words!r}: {out!r}"
        assert _listing(Path(tmp)) == before, f"created on refusal: vibrissa {words!r}"
        return "refused"


def test_every_option_of_every_command_has_hostile_values(assets) -> None:
    covered = {(p, n) for p, n, _ in cases(assets)}
    wanted = {(p, n) for p, t in CONTRACT.items() for n, s in t.items() if s.kind != "flag"}
    assert covered == wanted and len(wanted) > 100


def test_the_sweep_every_option_every_hostile_value(assets, no_work) -> None:
    counts: dict[str, int] = {}
    seconds: dict[str, float] = {}
    broken: list[str] = []
    for path, name, value in cases(assets):
        t0 = time.perf_counter()
        try:
            what = run_case(argv(path, name, value, assets), no_work)
        except AssertionError as exc:
            broken.append(str(exc).splitlines()[0][:300])
            what = "broken"
        counts[what] = counts.get(what, 0) + 1
        seconds[path] = seconds.get(path, 0.0) + time.perf_counter() - t0
    print(json.dumps({"counts": counts, "seconds": {k: round(v, 1) for k, v in seconds.items()}}))
    assert not broken, "\n".join(broken)
    assert counts.get("refused", 0) > 500


@settings(
    max_examples=1000,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data())
def test_drawn_values_keep_the_contract(assets, no_work, data) -> None:
    options = sorted(
        (p, n, s) for p, t in CONTRACT.items() for n, s in t.items() if s.kind != "flag"
    )
    path, name, spec = data.draw(st.sampled_from(options), label="option")
    if spec.kind == "number":
        value = repr(data.draw(st.floats(allow_nan=True, allow_infinity=True), label="value"))
    elif spec.kind in ("integer", "seed"):
        value = str(data.draw(st.integers(-(2**70), 2**70), label="value"))
    else:
        value = data.draw(
            st.text(st.characters(blacklist_categories=("Cs",)), max_size=40), label="value"
        )
    run_case(argv(path, name, value, assets), no_work)
