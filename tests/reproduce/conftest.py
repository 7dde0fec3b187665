"""Quick runs of every registered experiment, shared by the orchestration tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from vibrissa.reproduce import experiments, run_experiment

#: Options of the pinned quick runs (chapter 4: one repeat of each reduced set).
QUICK_OPTIONS = {"radial-distance": {"n_seeds": 1}}


@pytest.fixture(scope="session")
def quick_runs(tmp_path_factory) -> dict[str, tuple[Path, dict]]:
    """name -> (output directory, results) of a quick run with figures, seed 0."""
    out = {}
    for name in experiments():
        d = tmp_path_factory.mktemp(name) / "out"
        res = run_experiment(name, d, quick=True, seed=0, workers=1,
                             command=f"pytest quick {name}", **QUICK_OPTIONS.get(name, {}))
        out[name] = (d, res)
    return out
