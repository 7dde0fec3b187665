"""Run jobs in worker processes and stop them at once, without ever hanging.

:class:`multiprocessing.pool.Pool` can hang in ``terminate()`` when it is torn down
while a worker or one of its handler threads holds a queue lock (CPython issues
#73945, #78178, #96995, all open). ``vibrissa generate`` tears its workers down on
Ctrl-C or ``kill``, so it met that hang once in CI (the process sat for 120 s after
SIGTERM). :func:`imap_unordered` does the same job with no shared locks at all: each
worker has its own pipe, the parent hands out one job at a time and waits on the
pipes and the workers' exit sentinels together, and leaving the iterator for any
reason (finished, failed, interrupted, closed) kills every worker that is still
running. A worker that dies without answering is reported, never waited for.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import traceback
from collections.abc import Callable, Iterator, Sequence
from multiprocessing.connection import Connection, wait
from typing import Any, TypeVar

__all__ = ["WorkerDied", "imap_unordered"]

J = TypeVar("J")
R = TypeVar("R")


class WorkerDied(RuntimeError):
    """A worker process ended without returning the job it was running."""


def _serve(conn: Connection, fn: Callable[[Any], Any]) -> None:
    """A worker: run the jobs the parent sends until it sends ``None`` or goes away.

    An interrupt is the parent's to handle (Ctrl-C reaches the whole process group),
    and termination by the parent is immediate.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        if msg is None:
            return
        i, job = msg
        try:
            reply = (i, True, fn(job))
        except Exception as exc:  # every failure goes back to the parent
            exc.add_note("raised in a worker process:\n" + traceback.format_exc().rstrip())
            reply = (i, False, exc)
        try:
            conn.send(reply)
        except Exception as exc:  # e.g. a result or exception that does not pickle
            conn.send((i, False, RuntimeError(f"a worker could not send its result back: {exc!r}")))


def imap_unordered(
    fn: Callable[[J], R], jobs: Sequence[J], workers: int
) -> Iterator[tuple[int, R]]:
    """Yield ``(i, fn(jobs[i]))`` for every job, in the order the workers finish them.

    Parameters
    ----------
    fn
        Run in the workers; with the ``spawn`` start method (not POSIX) it must pickle.
    jobs
        Sent to the workers one at a time as they become free.
    workers
        Number of worker processes (at most ``len(jobs)`` are started).

    Raises
    ------
    ValueError
        ``workers`` is not a positive integer.
    WorkerDied
        A worker process ended (e.g. killed) while it ran a job.
    Exception
        Whatever ``fn`` raised in a worker, with the worker's traceback as a note.

    Notes
    -----
    Leaving the iterator early (an exception in the caller's loop, ``close()``, an
    interrupt) kills the workers still running: their jobs are lost, nothing waits.
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be a positive integer, got {workers!r}")
    if not jobs:
        return
    ctx = (
        multiprocessing.get_context("fork")
        if os.name == "posix"
        else multiprocessing.get_context("spawn")
    )
    procs: list[multiprocessing.process.BaseProcess] = []
    conns: list[Connection] = []
    try:
        for _ in range(min(workers, len(jobs))):
            parent, child = ctx.Pipe(duplex=True)
            proc: multiprocessing.process.BaseProcess = ctx.Process(
                target=_serve, args=(child, fn), daemon=True
            )
            proc.start()
            child.close()
            procs.append(proc)
            conns.append(parent)
        running: dict[int, int] = {}  # worker -> job it runs
        following = 0
        for w in range(len(conns)):
            _hand_out(conns[w], procs[w], (following, jobs[following]), following)
            running[w] = following
            following += 1
        while running:
            watched = [conns[w] for w in running] + [procs[w].sentinel for w in running]
            ready = wait(watched)
            for w in list(running):
                conn, proc = conns[w], procs[w]
                if conn in ready or conn.poll():
                    try:
                        i, ok, payload = conn.recv()
                    except (EOFError, OSError):
                        raise WorkerDied(_died(proc, running[w])) from None
                    del running[w]
                    if following < len(jobs):
                        _hand_out(conn, proc, (following, jobs[following]), following)
                        running[w] = following
                        following += 1
                    else:
                        _hand_out(conn, proc, None, None)
                    if not ok:
                        raise payload
                    yield i, payload
                elif proc.sentinel in ready:
                    raise WorkerDied(_died(proc, running[w]))
    finally:
        for proc in procs:
            if proc.is_alive():
                proc.kill()
        for proc in procs:
            proc.join()
        for conn in conns:
            conn.close()


def _hand_out(
    conn: Connection, proc: multiprocessing.process.BaseProcess, msg: Any, job: int | None
) -> None:
    """Send ``msg`` (job ``job``, or None: stop) to a worker.

    One that has died meanwhile is reported as such if it was to take a job.
    """
    try:
        conn.send(msg)
    except (BrokenPipeError, ConnectionResetError):
        if job is None:  # it was to stop anyway, and all it ran has come back
            return
        proc.join(timeout=1.0)
        raise WorkerDied(
            f"worker process {proc.pid} ended with exit code {proc.exitcode} "
            f"before it could take job {job}"
        ) from None


def _died(proc: multiprocessing.process.BaseProcess, job: int) -> str:
    proc.join(timeout=1.0)
    return f"worker process {proc.pid} ended with exit code {proc.exitcode} while it ran job {job}"
