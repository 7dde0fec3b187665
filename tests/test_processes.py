"""Worker processes that finish every job once and never outlive the iterator."""

from __future__ import annotations

import multiprocessing
import os
import time

import pytest

from vibrissa._processes import WorkerDied, imap_unordered


def _square_after(job: tuple[int, float]) -> int:
    x, pause = job
    time.sleep(pause)
    return x * x


def _fail_on_three(x: int) -> int:
    if x == 3:
        raise KeyError(f"job {x}")
    return x


def _die_on_two(x: int) -> int:
    if x == 2:
        os._exit(3)
    return x


@pytest.fixture(autouse=True)
def _others() -> set:
    """Child processes other tests of this session may have left running."""
    return set(multiprocessing.active_children())


def _no_children_left(others: set) -> bool:
    return set(multiprocessing.active_children()) <= others


@pytest.mark.parametrize("workers", [1, 2, 3, 20])
def test_every_job_runs_once_whatever_order_the_workers_finish_in(workers, _others):
    # later jobs are quicker, so the workers finish them out of order
    jobs = [(x, 0.002 * (12 - x)) for x in range(12)]
    got = list(imap_unordered(_square_after, jobs, workers))
    assert sorted(i for i, _ in got) == list(range(12))
    assert all(res == i * i for i, res in got)
    assert _no_children_left(_others)


def test_no_jobs_start_no_workers():
    assert list(imap_unordered(_square_after, [], 2)) == []


@pytest.mark.parametrize("workers", [0, -1, 1.5, True, "2"])
def test_workers_must_be_a_positive_integer(workers):
    with pytest.raises(ValueError, match="workers must be a positive integer"):
        list(imap_unordered(_square_after, [(1, 0.0)], workers))


def test_a_failing_job_raises_its_own_exception_with_the_worker_traceback(_others):
    with pytest.raises(KeyError, match="job 3") as info:
        list(imap_unordered(_fail_on_three, list(range(8)), 2))
    notes = "\n".join(getattr(info.value, "__notes__", []))
    assert "raised in a worker process" in notes and "_fail_on_three" in notes
    assert _no_children_left(_others)


def test_a_worker_that_dies_is_reported_not_waited_for(_others):
    start = time.monotonic()
    with pytest.raises(WorkerDied, match="exit code 3 while it ran job 2"):
        list(imap_unordered(_die_on_two, list(range(6)), 2))
    assert time.monotonic() - start < 30
    assert _no_children_left(_others)


def test_leaving_early_kills_the_workers_without_waiting_for_their_jobs(_others):
    jobs = [(0, 0.0)] + [(x, 60.0) for x in range(1, 4)]
    it = imap_unordered(_square_after, jobs, 2)
    start = time.monotonic()
    assert next(it) == (0, 0)
    it.close()
    assert time.monotonic() - start < 10  # not the 60 s the running job would take
    assert _no_children_left(_others)


def test_an_exception_in_the_callers_loop_kills_the_workers(_others):
    jobs = [(0, 0.0)] + [(x, 60.0) for x in range(1, 4)]
    start = time.monotonic()
    with pytest.raises(RuntimeError, match="caller"):
        for _ in imap_unordered(_square_after, jobs, 2):
            raise RuntimeError("caller")
    assert time.monotonic() - start < 10
    assert _no_children_left(_others)


def _exit_at_once(conn) -> None:
    conn.close()
    os._exit(5)


@pytest.mark.skipif(os.name != "posix", reason="forks a process")
@pytest.mark.parametrize("job", [0, None])
def test_a_worker_gone_before_its_next_job_is_reported_and_one_gone_before_stop_is_not(job):
    from vibrissa._processes import _hand_out

    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=True)
    proc = ctx.Process(target=_exit_at_once, args=(child,))
    proc.start()
    child.close()
    proc.join()
    if job is None:
        _hand_out(parent, proc, None, None)  # nothing lost: it was to stop
    else:
        with pytest.raises(WorkerDied, match="exit code 5 before it could take job 0"):
            _hand_out(parent, proc, (0, "payload"), 0)
    parent.close()
