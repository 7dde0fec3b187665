"""The hostile-input corpus: every case refused before any work, in one line (issue 13).

Each case of :mod:`hostile_corpus` runs in an empty directory and must exit with
status 2, print exactly one line on standard error (``error: ...``) naming the
option or path at fault, print no traceback and create no file. On the old main,
type errors printed usage boxes, ``--seed -1`` did not name the option, a corrupt
HDF5 header added destructor tracebacks, several bad outputs were found only after
the work was stated, and out-of-range whisker parameters gave tracebacks.
``scripts/hostile_inputs.py`` runs the same corpus through the console script.
"""

from __future__ import annotations

import importlib

import pytest
from console import console_script
from hostile_corpus import CASES, run_console, run_in_process

from vibrissa.cli import app

#: The commands of ``vibrissa --help`` (each must be in the corpus).
COMMANDS = (
    "whisker",
    "bench",
    "generate",
    "import",
    "plot",
    "reproduce",
    "identify",
    "run",
    "live",
    "fit-pipeline",
)

#: The issue's own command lines (findings 1-3, 7 and 8), each a case of the corpus.
ISSUE_COMMANDS = [
    ("generate", "radial-distance", "--out", "x.nc", "--textures", "p80"),
    ("generate", "angle-texture", "--out", "x.nc", "--radial-distances", "5000"),
    ("generate", "radial-distance", "--out", "x.nc", "--radial-distances", ""),
    ("generate", "angle-texture", "--out", "x.nc", "--textures", ""),
    ("generate", "radial-distance", "--out", "x.nc", "--speeds", "1:2:#100000000"),
    ("generate", "radial-distance", "--out", "x.nc", "--speeds", "50:100:0.0000001"),
    ("generate", "radial-distance", "--out", "x.nc", "--runs", "1000000000"),
    ("generate", "radial-distance", "--out", "x.nc", "--quick", "--workers", "0"),
    ("generate", "radial-distance", "--out", "x.nc", "--quick", "--workers", "-1"),
    ("generate", "radial-distance", "--out", "x.nc", "--quick", "--seed", "-1"),
    ("generate", "radial-distance", "--out", "x.nc", "--speeds", "100,100,100"),
    ("whisker", "ring", "--duration-s", "1e9"),
    ("whisker", "info", "--length-mm", "1e300"),
    ("whisker", "info", "--length-mm", "1e20"),
    ("whisker", "push", "--at-mm", "150", "--displacement-mm", "60", "--pole-radius-mm", "1e6"),
    ("whisker", "info", "--damping-ratio", "0.7"),
    ("whisker", "info", "--damping-ratio", "1.5"),
    ("plot", "ds.nc", "--out", "file.txt"),
    ("plot", "bad-attributes.nc", "--out", "o"),
]


def test_the_corpus_is_large_and_covers_every_command_and_the_issue():
    assert len(CASES) >= 100
    assert {c.args[0] for c in CASES} >= set(COMMANDS)
    args = {c.args for c in CASES}
    assert [cmd for cmd in ISSUE_COMMANDS if cmd not in args] == []
    # the commands of the corpus are the commands of the app
    assert set(COMMANDS) == {c.name for c in app.registered_commands} | {
        g.name for g in app.registered_groups
    }


class SimulationStarted(BaseException):
    """Raised by every entry point of the simulator while the corpus runs (a
    ``BaseException``, so that no command's error handling can swallow it)."""


@pytest.fixture
def no_simulation(monkeypatch):
    """Make starting any simulation an error: the corpus must be refused before."""

    def refuse(*args, **kwargs):
        raise SimulationStarted("a hostile input started a simulation")

    # the solvers every simulation goes through: dynamics, and the static solves of
    # pushes, static loads and the Hall sensor's calibration
    monkeypatch.setattr(
        importlib.import_module("vibrissa.whisker.simulate"), "run_dynamics", refuse
    )
    monkeypatch.setattr(importlib.import_module("vibrissa.whisker.rod"), "solve_static", refuse)
    # CrunchBot: the simulated robot's run and training, the synthetic robot's run and
    # the particle filter's steps (issue 16)
    monkeypatch.setattr(
        importlib.import_module("vibrissa.robots.crunchbot.robot"), "run_crunchbot", refuse
    )
    monkeypatch.setattr(
        importlib.import_module("vibrissa.robots.crunchbot.training"), "train_classifiers", refuse
    )
    monkeypatch.setattr(
        importlib.import_module("vibrissa.robots.crunchbot.synthetic"), "synthetic_log", refuse
    )
    monkeypatch.setattr(
        importlib.import_module("vibrissa.slam.filter").ParticleFilter, "step", refuse
    )


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_hostile_input_is_refused_in_one_line_before_any_work(case, tmp_path, no_simulation):
    outcome = run_in_process(case, tmp_path)
    assert outcome.refused_cleanly, outcome.problem()


@pytest.mark.parametrize(
    "args",
    [
        ("generate", "radial-distance", "--out", "x.nc", "--quick", "--workers", "abc"),
        ("generate", "radial-distance", "--out", "x.nc", "--quick", "--seed", "-1"),
        ("plot", "bad-attributes.nc", "--out", "o"),
        ("plot", "ds.nc", "--out", "file.txt"),
        ("whisker", "static", "--force-n", "1"),
    ],
    ids=lambda a: " ".join(a),
)
def test_the_console_script_prints_the_same_one_line(args, tmp_path):
    (case,) = [c for c in CASES if c.args == args]
    outcome = run_console(case, tmp_path, console_script())
    assert outcome.refused_cleanly, outcome.problem()
