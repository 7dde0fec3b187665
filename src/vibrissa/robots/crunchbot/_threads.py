"""The process' pool of threads that simulate CrunchBot's whiskers side by side.

The rod kernels (:func:`vibrissa.whisker._kernels.run_dynamics` and the linear free
flight) release the GIL, so whiskers that move independently within one control step
run on both cores of this machine from one process.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from typing import TypeVar

__all__ = ["default_workers", "map_threads"]

T = TypeVar("T")
R = TypeVar("R")

_POOL: tuple[int, int, ThreadPoolExecutor] | None = None
_LOCK = threading.Lock()


def default_workers() -> int:
    """Threads to use: the cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _pool(workers: int) -> ThreadPoolExecutor:
    # made again after a fork: the child inherits the pool object, not its threads
    global _POOL
    with _LOCK:
        if _POOL is None or _POOL[0] != os.getpid() or _POOL[1] != workers:
            if _POOL is not None and _POOL[0] == os.getpid():
                _POOL[2].shutdown(wait=False)  # another size asked for: no idle leftovers
            _POOL = (
                os.getpid(),
                workers,
                ThreadPoolExecutor(workers, thread_name_prefix="crunchbot-whisker"),
            )
        return _POOL[2]


def map_threads(fn: Callable[[T], R], items: Iterable[T], workers: int) -> list[R]:
    """``[fn(i) for i in items]``, on up to ``workers`` threads.

    The results are in order; the first exception is raised.
    """
    items = list(items)
    if workers <= 1 or len(items) < 2:
        return [fn(i) for i in items]
    return list(_pool(workers).map(fn, items))
