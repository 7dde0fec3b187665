"""benchmarks/profile_closed_loops.py: its split of a profile into categories."""

from __future__ import annotations

import cProfile
import pstats

import numpy as np
import pytest

from vibrissa.whisker import RodModel, preset


def test_the_split_puts_kernel_time_under_solver_and_sums_to_the_total(bench_script) -> None:
    prof_mod = bench_script("profile_closed_loops")
    from vibrissa.whisker.simulate import free_vibration

    model = RodModel(preset("xy-robot"))
    free_vibration(model, tip_deflection_mm=5, duration_s=0.01)  # compiled beforehand
    prof = cProfile.Profile()
    prof.enable()
    free_vibration(model, tip_deflection_mm=5, duration_s=0.2)
    np.linalg.eigvals(np.random.default_rng(0).normal(size=(300, 300)))
    prof.disable()
    stats = pstats.Stats(prof)
    cats, top = prof_mod.split(stats)
    assert cats["solver"] > 0 and cats["step_setup"] > 0 and cats["linearisation"] > 0
    assert sum(cats.values()) == pytest.approx(stats.total_tt, abs=0.05)
    assert top[0]["own_seconds"] >= top[-1]["own_seconds"]


def test_an_unknown_loop_is_refused(bench_script) -> None:
    prof_mod = bench_script("profile_closed_loops")
    with pytest.raises(SystemExit):
        prof_mod.main(["--only", "roomba-x"])
