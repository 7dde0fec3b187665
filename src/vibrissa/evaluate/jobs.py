"""Independent evaluation steps in worker processes, reading arrays they share.

:func:`run_jobs` calls a module-level function once per job: in this process when
``workers`` is 1, else in a pool of ``workers`` processes (joblib's loky backend,
the one scikit-learn uses). The large arrays the jobs read (the trials, their
windows) are held by a :class:`SharedArrays`: with workers, each is written once
to a ``.npy`` file in a temporary directory (in ``/dev/shm`` where it exists) that
every worker maps read-only, instead of being pickled into every job; a job names
the array and the rows it needs. Results come back in job order, whichever job
finishes first, so an evaluation gives the same results with any number of
workers.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["SharedArrays", "resolve_workers", "run_jobs"]


def resolve_workers(workers: int | None) -> int:
    """Worker processes to use: ``workers``, or every core for ``None``.

    Raises
    ------
    ValueError
        When ``workers`` is not a positive integer (or ``None``).
    """
    if workers is None:
        return max(1, os.cpu_count() or 1)
    if isinstance(workers, bool) or not isinstance(workers, int | np.integer) or workers < 1:
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    return int(workers)


class _Mapped(Mapping[str, np.ndarray]):
    """The arrays of a :class:`SharedArrays` as a worker sees them (pickled by path).

    Each access maps the file anew and nothing keeps the map after the job: a worker
    whose resident memory stays grown is restarted by loky as leaking.
    """

    def __init__(self, paths: Mapping[str, str]) -> None:
        self.paths = dict(paths)

    def __getitem__(self, name: str) -> np.ndarray:
        return np.load(self.paths[name], mmap_mode="r")

    def __iter__(self) -> Iterator[str]:
        return iter(self.paths)

    def __len__(self) -> int:
        return len(self.paths)


_PREFIX = "vibrissa-eval-"


def _temporary_folder() -> str:
    """A new folder for shared arrays, in ``/dev/shm`` (memory) where it can be written.

    Its name carries this process's id; folders left by processes that no longer
    exist (killed before they could remove theirs) are removed first.
    """
    shm = Path("/dev/shm")
    base = Path(str(shm) if shm.is_dir() and os.access(shm, os.W_OK) else tempfile.gettempdir())
    for old in base.glob(f"{_PREFIX}*-*"):
        pid = old.name[len(_PREFIX) :].split("-", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(old, ignore_errors=True)
    return tempfile.mkdtemp(prefix=f"{_PREFIX}{os.getpid()}-", dir=base)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # e.g. another user's process
        return True
    return True


class SharedArrays(Mapping[str, np.ndarray]):
    """Named arrays that the jobs of :func:`run_jobs` read, in this process or in workers.

    Use as a context manager: with ``workers > 1`` every added array is written to a
    temporary ``.npy`` file, removed on exit (or, if this process is killed, by the
    next evaluation that starts).

    Parameters
    ----------
    workers : int
        Worker processes the arrays are for (1: none, nothing is written).
    """

    def __init__(self, workers: int = 1) -> None:
        self.workers = resolve_workers(workers)
        self._arrays: dict[str, np.ndarray] = {}
        self._paths: dict[str, str] = {}
        self._dir: str | None = None

    def __enter__(self) -> SharedArrays:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Remove the temporary files (workers keep what they have mapped)."""
        if self._dir is not None:
            shutil.rmtree(self._dir, ignore_errors=True)
            self._dir = None
            self._paths.clear()

    def add(self, name: str, array: np.ndarray) -> None:
        """Share ``array`` as ``name``.

        With workers it is written to a file and this process keeps only a read-only
        map of it (so a caller that drops its own reference frees the memory).
        """
        if self.workers <= 1:
            self._arrays[name] = array
            return
        if self._dir is None:
            self._dir = _temporary_folder()
        path = os.path.join(self._dir, f"{len(self._paths)}.npy")
        np.save(path, np.ascontiguousarray(array))
        self._paths[name] = path
        self._arrays[name] = np.load(path, mmap_mode="r")

    def __getitem__(self, name: str) -> np.ndarray:
        return self._arrays[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._arrays)

    def __len__(self) -> int:
        return len(self._arrays)

    def for_workers(self) -> Mapping[str, np.ndarray]:
        """The picklable view a worker opens (memory-mapped, read-only)."""
        return _Mapped(self._paths)


def _call(
    func: Callable[..., Any], arrays: Mapping[str, np.ndarray], i: int, job: Mapping[str, Any]
) -> tuple[int, Any]:
    return i, func(arrays, **job)


def run_jobs(
    func: Callable[..., Any],
    jobs: Sequence[Mapping[str, Any]],
    arrays: SharedArrays,
    *,
    order: Sequence[int] | None = None,
    on_done: Callable[[int], Any] | None = None,
) -> list[Any]:
    """``[func(arrays, **job) for job in jobs]``, in ``arrays.workers`` processes.

    Parameters
    ----------
    func : callable
        A module-level function (workers import it by name), called as
        ``func(arrays, **job)``; ``arrays`` maps names to the shared arrays.
    jobs : sequence of dict
        Keyword arguments of each call (picklable; small: index arrays, estimators).
    arrays : SharedArrays
        The arrays the jobs read; its ``workers`` sets the number of processes.
    order : sequence of int, optional
        The order in which jobs are started (e.g. the longest first, so that the
        workers finish together); default: as given.
    on_done : callable, optional
        Called with the job's index as each job finishes.

    Returns
    -------
    list
        The results, in the order of ``jobs``.
    """
    seq = list(range(len(jobs)) if order is None else order)
    if sorted(seq) != list(range(len(jobs))):
        raise ValueError("order must be a permutation of the job indices")
    results: list[Any] = [None] * len(jobs)
    workers = min(arrays.workers, len(jobs))
    if workers <= 1:
        for i in seq:
            results[i] = func(arrays, **jobs[i])
            if on_done is not None:
                on_done(i)
        return results
    from joblib import Parallel, delayed

    view = arrays.for_workers()
    parallel = Parallel(
        n_jobs=workers, backend="loky", return_as="generator_unordered", max_nbytes=None
    )
    for i, res in parallel(delayed(_call)(func, view, i, jobs[i]) for i in seq):
        results[i] = res
        if on_done is not None:
            on_done(i)
    return results
