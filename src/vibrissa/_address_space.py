"""Whether the process' memory limit lets NumPy, SciPy and numba load at all.

A limit on the address space (``ulimit -v``, ``RLIMIT_AS``; batch schedulers such as
Grid Engine's ``h_vmem`` set it) or on the data segment (``RLIMIT_DATA``) below what the
libraries need to load does not give a ``MemoryError``: it gives an ``ImportError``
traceback ("failed to map segment from shared object"), or OpenBLAS, starting its
threads, retries its buffer allocation forever and no signal but SIGKILL stops the
process. OpenBLAS reserves a buffer and a malloc arena per thread, so fewer threads
need less; one thread does the work of every command here without measurable loss
(the physics is numba-compiled; BLAS only serves the classifiers' small matrices).

Measured on this project's reference machine (2 cores, Python 3.11, the pinned
libraries), the peak virtual size after importing every library a command uses:
590 MiB with one OpenBLAS thread, 670 MiB with two (``VmPeak`` in
``/proc/self/status``). :data:`BASE_MIB` and :data:`PER_THREAD_MIB` are those figures
with a margin; :func:`plan` is called by the console entry point before anything
heavy is imported.
"""

from __future__ import annotations

import os
import resource
from collections.abc import MutableMapping
from dataclasses import dataclass

__all__ = ["BASE_MIB", "PER_THREAD_MIB", "THREADS_VAR", "Plan", "limit_mib", "plan"]

#: Address space to load the libraries with one OpenBLAS thread, less that thread (MiB).
BASE_MIB = 560
#: Address space each further OpenBLAS thread reserves (MiB; measured 80).
PER_THREAD_MIB = 96
#: The environment variable OpenBLAS reads its thread count from.
THREADS_VAR = "OPENBLAS_NUM_THREADS"


@dataclass(frozen=True)
class Plan:
    """What the entry point does under the process' memory limit.

    Attributes
    ----------
    threads
        OpenBLAS threads to set in the environment (``None``: leave it as it is).
    error
        The one-line refusal when even one thread does not fit (``None``: go on).
    """

    threads: int | None = None
    error: str | None = None


def limit_mib() -> float | None:
    """The smaller of the soft ``RLIMIT_AS`` and ``RLIMIT_DATA`` (MiB), ``None`` if neither."""
    limits = []
    for which in (resource.RLIMIT_AS, resource.RLIMIT_DATA):
        soft, _ = resource.getrlimit(which)
        if soft != resource.RLIM_INFINITY:
            limits.append(soft / 2**20)
    return min(limits) if limits else None


def _need_mib(threads: int) -> int:
    return BASE_MIB + PER_THREAD_MIB * threads


def plan(limit: float | None, environ: MutableMapping[str, str], cpus: int | None = None) -> Plan:
    """Decide the OpenBLAS thread count, or refuse, for a memory limit of ``limit`` MiB.

    Parameters
    ----------
    limit
        The process' limit (:func:`limit_mib`); ``None``: no limit, nothing to do.
    environ
        The environment; an OpenBLAS thread count already in it is the user's and is
        kept (the refusal then names it).
    cpus
        Cores OpenBLAS would start a thread for (default :func:`os.cpu_count`).

    Returns
    -------
    Plan
        The thread count to set (the most that fit, when the default would not), or
        the refusal naming the limit and what is needed.
    """
    if limit is None:
        return Plan()
    given = environ.get(THREADS_VAR, "").strip()
    if given.isdigit() and int(given) > 0:
        if _need_mib(int(given)) <= limit:
            return Plan()
        return Plan(
            error=(
                f"error: the memory limit (ulimit -v / -d) is {limit:.0f} MiB; loading NumPy, "
                f"SciPy and numba with {THREADS_VAR}={given} needs about "
                f"{_need_mib(int(given))} MiB: raise the limit or lower {THREADS_VAR}"
            )
        )
    cores = cpus or os.cpu_count() or 1
    if _need_mib(cores) <= limit:
        return Plan()
    fits = int((limit - BASE_MIB) // PER_THREAD_MIB)
    if fits >= 1:
        return Plan(threads=min(fits, cores))
    return Plan(
        error=(
            f"error: the memory limit (ulimit -v / -d) is {limit:.0f} MiB; loading NumPy, "
            f"SciPy and numba needs about {_need_mib(1)} MiB: raise the limit"
        )
    )
