"""Quick runs of every registered experiment, made once per test session and shared by the
orchestration and experiment tests (`quick_runs`).

The runs are made once per test session: under pytest-xdist they are made in a
directory all workers share, each run by the worker that takes its lock first; a worker
makes the runs no other worker has taken, then waits for the others' locks and reads
what they made.
"""

from __future__ import annotations

import fcntl
import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from vibrissa.reproduce import experiments, run_experiment

#: Options of the quick runs (chapter 4: one repeat of each reduced set, as pinned;
#: CrunchBot: 2 runs of 60 s instead of the quick preset's 3 of 6 minutes, 52 s instead
#: of 157-167 s on one core: the tests of these runs check the envelope, the report and
#: its page, which short runs exercise alike, and tests/thesis/crunchbot_slam runs the
#: robot's own checks).
QUICK_OPTIONS = {
    "radial-distance": {"n_seeds": 1},
    "crunchbot-slam": {"runs": (2,), "seconds": (60,)},
}


@contextmanager
def locked(path: Path, wait: bool = True) -> Iterator[bool]:
    """Hold an exclusive lock on the file ``path`` (created if missing) while inside.

    Yields whether the lock is held: always with ``wait``, else ``False`` when
    another process holds it.
    """
    with open(path, "a") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX if wait else fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            yield False
            return
        try:
            yield True
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


@pytest.fixture(scope="session")
def quick_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, dict]]:
    """name -> (output directory, results) of a quick run with figures, seed 0.

    The results are those saved in the run's ``results.json`` (what
    :func:`~vibrissa.reproduce.run_experiment` returns, as JSON), read back by every
    worker alike.
    """
    if os.environ.get("PYTEST_XDIST_WORKER"):
        # the parent of a worker's base directory is this session's, shared by its workers
        root = tmp_path_factory.getbasetemp().parent / "quick-runs"
        root.mkdir(exist_ok=True)
    else:
        root = tmp_path_factory.mktemp("quick-runs")

    def run(name: str, wait: bool) -> bool:
        """Make the run ``name`` unless made already; False if another worker is at it."""
        with locked(root / f"{name}.lock", wait) as held:
            done = root / f"{name}.done"  # written once the run has finished
            if held and not done.exists():
                run_experiment(
                    name,
                    root / name / "out",
                    quick=True,
                    seed=0,
                    workers=1,
                    command=f"pytest quick {name}",
                    **QUICK_OPTIONS.get(name, {}),
                )
                done.touch()
            return held

    names = list(experiments())
    taken = [name for name in names if not run(name, wait=False)]
    for name in taken:  # another worker's runs: wait for them (or redo one it failed)
        run(name, wait=True)
    out = {}
    for name in names:
        d = root / name / "out"
        out[name] = (d, json.loads((d / "results.json").read_text()))
    return out
