"""The thread pool that runs CrunchBot's whiskers side by side."""

from __future__ import annotations

import os
import threading

import pytest

from vibrissa.robots.crunchbot import _threads


def test_map_threads_keeps_the_order_and_uses_threads() -> None:
    names = set()

    def work(i: int) -> int:
        names.add(threading.current_thread().name)
        return i * i

    assert _threads.map_threads(work, range(7), 2) == [i * i for i in range(7)]
    assert any(n.startswith("crunchbot-whisker") for n in names)


def test_one_worker_or_one_item_runs_in_the_calling_thread() -> None:
    me = threading.current_thread().name
    seen = []
    _threads.map_threads(lambda i: seen.append(threading.current_thread().name), [1, 2], 1)
    _threads.map_threads(lambda i: seen.append(threading.current_thread().name), [1], 2)
    assert seen == [me, me, me]


def test_an_exception_in_a_thread_reaches_the_caller() -> None:
    def work(i: int) -> int:
        if i == 3:
            raise RuntimeError("whisker 3 failed")
        return i

    with pytest.raises(RuntimeError, match="whisker 3"):
        _threads.map_threads(work, range(5), 2)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_a_forked_child_gets_its_own_pool() -> None:
    _threads.map_threads(abs, [-1, -2], 2)  # the parent's pool exists
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # child: the inherited pool has no threads; a new one must be made
        try:
            ok = _threads.map_threads(abs, [-1, -2, -3], 2) == [1, 2, 3]
            os.write(w, b"1" if ok else b"0")
        finally:
            os._exit(0)
    os.close(w)
    with os.fdopen(r, "rb") as fh:
        got = fh.read()
    os.waitpid(pid, 0)
    assert got == b"1"


def test_default_workers_is_the_cores_this_process_may_use() -> None:
    assert _threads.default_workers() == len(os.sched_getaffinity(0))


def test_the_pool_is_kept_for_calls_of_any_length() -> None:
    _threads.map_threads(abs, [-1, -2], 2)
    pool = _threads._POOL
    _threads.map_threads(abs, [-1, -2, -3, -4, -5], 2)
    assert _threads._POOL is pool
    _threads.map_threads(abs, [-1, -2, -3], 3)  # another size: the old pool is let go
    assert _threads._POOL is not pool and pool[2]._shutdown
