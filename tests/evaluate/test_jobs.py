"""Tests of vibrissa.evaluate.jobs: jobs in worker processes on shared arrays, results in order."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from vibrissa.evaluate.jobs import SharedArrays, resolve_workers, run_jobs


def row_sum(arrays, *, name, rows, scale):
    """A job: a sum of some rows of a shared array, and the process that computed it."""
    a = arrays[name]
    return float(np.asarray(a[rows]).sum() * scale), os.getpid(), a.flags.writeable


@pytest.mark.parametrize("workers", [1, 2])
def test_run_jobs_returns_results_in_job_order(workers) -> None:
    data = np.arange(60.0).reshape(20, 3)
    jobs = [{"name": "data", "rows": np.array([i, 19 - i]), "scale": i + 1} for i in range(10)]
    done = []
    with SharedArrays(workers) as arrays:
        arrays.add("data", data)
        out = run_jobs(row_sum, jobs, arrays, order=list(range(9, -1, -1)), on_done=done.append)
    assert [r[0] for r in out] == [data[[i, 19 - i]].sum() * (i + 1) for i in range(10)]
    assert sorted(done) == list(range(10))
    pids = {r[1] for r in out}
    if workers == 1:
        assert pids == {os.getpid()}
    else:  # in workers, on a read-only map of the array
        assert os.getpid() not in pids and not any(r[2] for r in out)


def test_shared_arrays_files_are_removed_on_exit() -> None:
    with SharedArrays(2) as arrays:
        arrays.add("a", np.ones((4, 5)))
        view = arrays.for_workers()
        assert np.array_equal(view["a"], np.ones((4, 5))) and list(view) == ["a"]
        folder = Path(view.paths["a"]).parent
        assert folder.is_dir()
    assert not folder.exists()
    with SharedArrays(1) as local:  # one process: nothing is written
        local.add("a", np.ones(3))
        assert local.for_workers().paths == {} and local["a"].sum() == 3


def test_resolve_workers_and_bad_arguments() -> None:
    assert resolve_workers(None) == (os.cpu_count() or 1)
    assert resolve_workers(3) == 3
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(ValueError, match="workers must be a positive integer"):
            resolve_workers(bad)
    with SharedArrays(1) as arrays, pytest.raises(ValueError, match="permutation"):
        run_jobs(row_sum, [{}, {}], arrays, order=[0, 0])


def test_folders_of_dead_processes_are_removed(tmp_path, monkeypatch) -> None:
    import subprocess
    import sys

    from vibrissa.evaluate import jobs

    monkeypatch.setattr(jobs, "Path", lambda p: tmp_path if p == "/dev/shm" else Path(p))
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    stale = tmp_path / f"vibrissa-eval-{dead}-abc"
    stale.mkdir()
    (stale / "0.npy").write_bytes(b"x")
    alive = tmp_path / f"vibrissa-eval-{os.getpid()}-def"
    alive.mkdir()
    with SharedArrays(2) as arrays:
        arrays.add("a", np.zeros(3))
        assert Path(arrays.for_workers().paths["a"]).parent.parent == tmp_path
        assert isinstance(arrays["a"], np.memmap) and not arrays["a"].flags.writeable
    assert not stale.exists() and alive.exists()
