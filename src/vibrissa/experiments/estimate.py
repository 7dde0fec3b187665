"""How long a generation will take on this machine, measured before it starts.

:func:`seconds_per_trial` times a few of the protocol's own trials on one core
(spread over the grid, after one that loads the compiled kernels), within a budget
of a fraction of a second; :func:`generation_seconds` turns that into the wall
time of the whole generation on the workers that will run it. The first trial also
leaves the kernels loaded, so forked workers start warm: the measurement is not
wasted work.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np

from vibrissa.experiments.contract import ChunkedTrials, SimulationProtocol
from vibrissa.experiments.runner import simulate_trials

__all__ = ["format_duration", "generation_seconds", "seconds_per_trial"]


def seconds_per_trial(
    protocol: SimulationProtocol, budget_s: float = 0.3, max_trials: int = 8
) -> float:
    """Mean wall-clock seconds of one trial of ``protocol`` on one core of this machine.

    The first trial (at the middle of the grid) loads the compiled kernels and is
    not counted; then trials spread evenly over the grid are timed until
    ``budget_s`` is spent (at least one, at most ``max_trials``), each run once
    untimed first so that building its session's whisker is not counted.

    Parameters
    ----------
    protocol
        The protocol whose trials are timed (its grid, whisker, sensor and time step).
    budget_s
        Seconds to spend on timed trials (after the first).
    max_trials
        Most trials timed.

    Returns
    -------
    float
        Seconds per trial.
    """
    if isinstance(protocol, ChunkedTrials):  # a protocol of another robot times itself
        return float(protocol.seconds_per_trial())
    n = protocol.n_trials
    order = np.unique(np.linspace(0, n - 1, max_trials + 1).round().astype(int))
    simulate_trials(protocol, [n // 2])  # loads the kernels (and the protocol's caches)
    spent, timed = 0.0, 0
    for i in order:
        # once untimed: a trial of another session builds that session's (drifted)
        # whisker and its free-flight modes, a cost each worker pays once per session
        # and that must not be counted per trial
        simulate_trials(protocol, [int(i)])
        t0 = time.perf_counter()
        simulate_trials(protocol, [int(i)])
        spent += time.perf_counter() - t0
        timed += 1
        if spent >= budget_s:
            break
    return spent / timed


def generation_seconds(
    n_trials: int, per_trial_s: float, workers: int | None = None, chunk_size: int = 32
) -> float:
    """Wall-clock seconds to simulate ``n_trials`` trials on ``workers`` processes.

    The trials run in chunks of ``chunk_size``, one chunk per process at a time, so at
    most ``ceil(n_trials / chunk_size)`` processes are busy.

    Parameters
    ----------
    n_trials
        Trials to simulate.
    per_trial_s
        Seconds per trial on one core (:func:`seconds_per_trial`).
    workers
        Processes (default: all cores).
    chunk_size
        Trials per chunk.
    """
    if n_trials <= 0:
        return 0.0
    cores = workers if workers is not None else (os.cpu_count() or 1)
    chunks = math.ceil(n_trials / chunk_size)
    busy = max(1, min(cores, chunks))
    # the last round of chunks may leave processes idle
    rounds = math.ceil(chunks / busy)
    return rounds * min(chunk_size, n_trials) * per_trial_s


def format_duration(seconds: float) -> str:
    """``"40 s"``, ``"12 min"`` or ``"3.5 h"``: a duration as a person would say it."""
    if seconds < 90:
        return f"{max(1, round(seconds))} s"
    if seconds < 90 * 60:
        return f"{round(seconds / 60)} min"
    return f"{seconds / 3600:.1f} h"
