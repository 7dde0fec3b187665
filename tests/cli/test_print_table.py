"""Tables printed by the commands never cut a name short, in a pipe or in a terminal."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
import textwrap

import pytest

NAMES = (
    "naive_bayes_raw",
    "naive_bayes_velocity",
    "naive_bayes_velocity_robust",
    "static_beam_measured",
)

#: Prints the radial-distance experiment's own console table (what ``vibrissa reproduce
#: radial-distance`` prints) for a summary of the classifiers above.
PROGRAM = textwrap.dedent(
    f"""
    from vibrissa.cli._common import print_table
    from vibrissa.reproduce import experiments

    exp = experiments()["radial-distance"]
    e = {{"radius_mm": {{"mean": 0.5, "std": 12.25}}, "speed_mm_s": {{"mean": -3.0, "std": 40.0}},
         "classify_seconds": 0.01}}
    print_table(exp.console_table({{"classifiers": {{n: e for n in {NAMES!r}}}}}))
    """
)


def _whole_names(out: str) -> None:
    assert "…" not in out
    for name in NAMES:
        assert name in out, f"{name} cut short in:\n{out}"


def test_a_table_piped_to_a_file_keeps_every_name_whole() -> None:
    env = dict(os.environ, COLUMNS="")
    env.pop("COLUMNS")
    out = subprocess.run(
        [sys.executable, "-c", PROGRAM], capture_output=True, text=True, env=env, timeout=120
    )
    assert out.returncode == 0, out.stderr
    _whole_names(out.stdout)
    # the whole table, not just the names: the last column's header is there too
    assert "thesis speed std" in out.stdout


@pytest.mark.parametrize("columns", ["80", "40"])
def test_a_table_in_a_narrow_terminal_keeps_every_name_whole(columns: str) -> None:
    main, sub = pty.openpty()
    env = dict(os.environ, COLUMNS=columns, LINES="40", TERM="xterm")
    proc = subprocess.Popen([sys.executable, "-c", PROGRAM], stdout=sub, stderr=sub, env=env)
    os.close(sub)
    chunks = []
    while True:
        try:
            chunk = os.read(main, 65536)
        except OSError:  # the child closed the terminal
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(main)
    assert proc.wait(timeout=120) == 0
    _whole_names(b"".join(chunks).decode())


def test_a_group_prints_its_table_whole_and_its_line(capsys) -> None:
    """The full chapter-5 run's console summary is a table and a line under it (a rich
    Group); print_table took only tables and raised AttributeError at the end of the run."""
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text

    from vibrissa.cli._common import print_table

    table = Table("classifier", "kappa")
    table.add_row("naive_bayes_velocity_robust", "0.91")
    print_table(Group(table, Text("sequential texture kappa: 0.95")))
    out = capsys.readouterr().out
    assert "naive_bayes_velocity_robust" in out and "sequential texture kappa: 0.95" in out
