"""cli._contract: one row per option of every command, and what a row checks."""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import pytest
import typer.main
from hypothesis import given
from hypothesis import strategies as st
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.cli._contract import CONTRACT, MAX_TEXT, Spec, read_structured

runner = CliRunner()


def _leaves(cmd, path=()):
    if getattr(cmd, "commands", None):
        for name, sub in cmd.commands.items():
            yield from _leaves(sub, (*path, name))
    else:
        yield " ".join(path), cmd


def test_every_option_of_every_command_has_exactly_one_row() -> None:
    seen = {}
    for path, cmd in _leaves(typer.main.get_command(app)):
        seen[path] = {p.name for p in cmd.params if p.name != "help"}
    assert set(seen) == set(CONTRACT)
    for path, names in seen.items():
        assert names == set(CONTRACT[path]), path


def test_help_shows_the_bounds() -> None:
    res = runner.invoke(app, ["run", "crunchbot", "--help"], env={"COLUMNS": "200"})
    assert "[> 0 and <= 3600 s]" in res.output and "[1 to 10000]" in res.output


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_a_number_is_accepted_exactly_within_its_bounds(x: float) -> None:
    spec = Spec("number", 0.5, 3600.0, unit="s")
    inside = math.isfinite(x) and 0.5 <= x <= 3600.0
    if inside:
        spec.check("--seconds", x)
    else:
        with pytest.raises(ValueError, match="^--seconds"):
            spec.check("--seconds", x)


@given(st.integers(-(2**80), 2**80))
def test_a_seed_is_what_a_dataset_stores(n: int) -> None:
    spec = Spec("seed")
    if 0 <= n <= 2**63 - 1:
        spec.check("--seed", n)
    else:
        with pytest.raises(ValueError, match="^--seed: expected"):
            spec.check("--seed", n)


def test_an_open_bound_excludes_its_end() -> None:
    spec = Spec("number", 0.0, 10.0, open_low=True)
    spec.check("--x", 1e-300)
    with pytest.raises(ValueError, match="must be positive"):
        spec.check("--x", 0.0)


@given(st.text(max_size=30))
def test_text_with_control_or_surrogate_characters_is_refused(text: str) -> None:
    bad = any(ord(c) < 32 or ord(c) == 127 or 0xD800 <= ord(c) < 0xE000 for c in text)
    if bad:
        with pytest.raises(ValueError, match="^--signal: contains"):
            Spec("text").check("--signal", text)
    else:
        Spec("text").check("--signal", text)
    with pytest.raises(ValueError, match="longer than"):
        Spec("text").check("--signal", "x" * (MAX_TEXT + 1))


def test_file_inputs_must_be_regular_readable_files(tmp_path: Path) -> None:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, why in (
        (fifo, "not a regular file"),
        (tmp_path, "not a regular file"),
        (Path("/dev/zero"), "not a regular file"),
        (tmp_path / "nope", "does not exist"),
    ):
        with pytest.raises(ValueError, match=why):
            Spec("file").check("--mapping", str(path))
    Spec("file", stdin=True).check("--input", "-")


def test_outputs_do_not_collide(tmp_path: Path) -> None:
    f = tmp_path / "f"
    f.write_text("keep")
    with pytest.raises(ValueError, match="is a file, not a directory"):
        Spec("output", directory=True).check("--out", str(f))
    with pytest.raises(ValueError, match="is a directory, not a file"):
        Spec("output").check("--out", str(tmp_path))
    assert f.read_text() == "keep"


def test_structured_inputs_are_bounded(tmp_path: Path) -> None:
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match="--mapping: .* nested too deep"):
        read_structured("--mapping", deep)
    bad = tmp_path / "bad.toml"
    bad.write_text("= = =")
    with pytest.raises(ValueError, match="is not TOML"):
        read_structured("--mapping", bad)
    good = tmp_path / "ok.json"
    good.write_text('{"a": [1, 2]}')
    assert read_structured("--mapping", good) == {"a": [1, 2]}


def test_a_bad_value_is_refused_before_the_command_runs(tmp_path: Path) -> None:
    res = runner.invoke(app, ["run", "crunchbot", "--out", str(tmp_path / "w"), "--seconds", "inf"])
    assert res.exit_code == 2
    assert res.stderr == "error: --seconds must be finite, got inf\n"
    assert not (tmp_path / "w").exists()


@pytest.mark.parametrize(
    "name", ["scratchbot", "biotact-g1", "crunchbot-slam", "tactile-framework"]
)
def test_a_baseline_is_refused_where_the_report_cannot_show_it(tmp_path: Path, name: str) -> None:
    """Issue 33, item 5: these reports accepted --baseline and ignored it."""
    base = tmp_path / "results.json"
    base.write_text('{"classifiers": {}}')
    res = runner.invoke(
        app, ["reproduce", name, "--out", str(tmp_path / "o"), "--baseline", str(base)]
    )
    assert res.exit_code == 2
    assert res.stderr.startswith(f"error: --baseline: the {name} report has no 'before' column")
    assert not (tmp_path / "o").exists()
    shown = runner.invoke(app, ["reproduce", name, "--help"], env={"COLUMNS": "300"}).output
    assert "not for this command" in shown


def test_out_of_memory_is_one_line_naming_what_to_lower(tmp_path: Path, monkeypatch) -> None:
    def exhausted(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr("vibrissa.thesis.crunchbot_slam.viewer.watch_run", exhausted)
    res = runner.invoke(app, ["run", "crunchbot", "--out", str(tmp_path / "w"), "--seconds", "5"])
    assert res.exit_code == 2
    assert res.stderr.splitlines()[-1] == (
        "error: out of memory; ask for less work: lower --seconds or --particles"
    )
    assert "Traceback" not in res.output


def test_every_memory_hint_names_a_command_and_its_options() -> None:
    from vibrissa.cli._contract import MEMORY

    assert set(MEMORY) <= set(CONTRACT)
    for path, hint in MEMORY.items():
        for word in hint.replace(",", " ").replace(")", " ").replace("(", " ").split():
            if word.startswith("--"):
                flags = {f"--{n.replace('_', '-')}" for n in CONTRACT[path]}
                assert word in flags | {"--quick", "--crop"}, (path, word)


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["generate", "radial-distance", "--quick", "-o", "x.nc", "--drift", "5e-324"], "--drift"),
        (["whisker", "ring", "--tip-deflection-mm", "5e-324"], "--tip-deflection-mm"),
        (["whisker", "whisk", "--control-rate-hz", "5e-324"], "--control-rate-hz"),
        (["import", "x.mat", "-o", "x.nc", "--sample-rate-hz", "5e-324"], "--sample-rate-hz"),
    ],
)
def test_subnormal_values_the_slow_fuzzer_found_are_refused_first(
    tmp_path: Path, monkeypatch, args: list[str], option: str
) -> None:
    """scripts/fuzz_cli_slow.py: each of these divided by (nearly) zero inside the work
    (ZeroDivisionError tracebacks, or an overflow warning before the error line)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.mat").write_bytes(b"")
    res = runner.invoke(app, args)
    assert res.exit_code == 2
    assert res.stderr.startswith(f"error: {option}") and len(res.stderr.splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.mat"]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("5,5.0000000000001", "repeats 5"),
        ("1e-300", "must be 0 or at least 1e-06 mm from it"),
        ("5,nan", "must be finite"),
        ("5,x", "must be comma-separated numbers"),
        ("5,2000", "must be at most 1000 mm"),
    ],
)
def test_a_list_of_numbers_is_checked_item_by_item(text: str, message: str) -> None:
    """Issue 33: --distances 5,5.0000000000001 made two classes 1e-13 mm apart and 1e-300
    was accepted where 0 was refused."""
    spec = CONTRACT["reproduce biotact-g1"]["distances"]
    with pytest.raises(ValueError, match=f"^--distances.*{re.escape(message)}"):
        spec.check("--distances", text)
    spec.check("--distances", "")  # none given: the defaults
    spec.check("--distances", "5, 10,15")
    spec.check("--distances", "0,-5")  # the head refuses these, saying why


def test_whole_numbers_for_runs_and_particles() -> None:
    runs = CONTRACT["reproduce crunchbot-slam"]["runs"]
    runs.check("--runs", "20")
    for bad, message in (
        ("2.5", "whole numbers"),
        ("1e30", "must lie in [1, 1000]"),
        ("0", "positive"),
    ):
        with pytest.raises(ValueError, match=re.escape(message)):
            runs.check("--runs", bad)
