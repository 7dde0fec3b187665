"""The generation's time estimate, measured before it starts (issue 13, finding 7)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from vibrissa.experiments import estimate
from vibrissa.experiments.estimate import format_duration, generation_seconds, seconds_per_trial
from vibrissa.experiments.protocols import get_protocol


@pytest.mark.parametrize(
    ("n", "cores", "chunk", "expected"),
    [
        (0, 2, 32, 0.0),
        (32, 2, 32, 32.0),  # one chunk: one core busy
        (64, 2, 32, 32.0),  # two chunks side by side
        (96, 2, 32, 64.0),  # the third chunk runs alone
        (10, 1, 32, 10.0),
        (100, 8, 10, 20.0),  # 10 chunks on 8 cores: two rounds
    ],
)
def test_generation_seconds_counts_rounds_of_chunks(n, cores, chunk, expected):
    assert generation_seconds(n, 1.0, cores, chunk) == expected


@pytest.mark.parametrize(
    ("seconds", "text"),
    [
        (0.2, "1 s"),
        (40, "40 s"),
        (89, "89 s"),
        (600, "10 min"),
        (5400, "1.5 h"),
    ],
)
def test_format_duration(seconds, text):
    assert format_duration(seconds) == text


def test_seconds_per_trial_skips_the_warm_up_and_stops_at_the_budget(monkeypatch):
    calls: list[list[int]] = []
    clock = iter(range(1000))

    def fake_simulate(protocol, indices):
        calls.append(list(indices))

    # every timed trial takes 0.05 s on this fake clock
    monkeypatch.setattr(estimate, "simulate_trials", fake_simulate)
    monkeypatch.setattr(estimate, "time", SimpleNamespace(perf_counter=lambda: 0.05 * next(clock)))
    protocol = SimpleNamespace(n_trials=100)
    assert seconds_per_trial(protocol, budget_s=0.3) == pytest.approx(0.05)
    assert calls[0] == [50]  # the warm-up, at the middle of the grid, not timed
    # each timed trial is run once untimed first (its session's whisker is built then)
    assert len(calls) == 1 + 2 * 6  # 6 timed trials of 0.05 s reach the 0.3 s budget
    assert calls[1::2] == calls[2::2]
    assert calls[2::2] == [[0], [12], [25], [37], [50], [62]]  # spread over the grid
    calls.clear()
    seconds_per_trial(protocol, budget_s=100.0, max_trials=4)
    assert calls[2::2] == [[0], [25], [50], [74], [99]]  # at most max_trials + 1 points


def test_seconds_per_trial_measures_the_protocols_own_trials():
    p = get_protocol("radial-distance", radial_distances_mm=(120.0,), speeds_mm_s=(100.0,), runs=1)
    s = seconds_per_trial(p, budget_s=0.0)
    assert math.isfinite(s) and s > 0
