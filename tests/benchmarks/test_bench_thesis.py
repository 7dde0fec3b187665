"""benchmarks/bench_thesis.py: times each reproduction, writes after each and resumes."""

from __future__ import annotations

import json

import pytest


def test_times_each_reproduction_and_resumes(bench_script, tmp_path, monkeypatch) -> None:
    bench = bench_script("bench_thesis")
    calls: list[str] = []

    def fake_run(name, out, quick, workers):
        calls.append(name)
        return {"meta": {"wall_seconds": {"generate": 1.0}, "dataset": {"n_trials": 7}}}

    monkeypatch.setattr(bench, "run_experiment", fake_run)
    out = tmp_path / "thesis.json"
    assert bench.main(["--out", str(out), "--only", "scratchbot,biotact-g1", "--quick"]) == 0
    res = json.loads(out.read_text())
    assert calls == ["scratchbot", "biotact-g1"] and res["complete"] and res["quick"]
    assert res["runs"]["scratchbot"]["n_trials"] == 7 and res["machine"]["cores"] >= 1
    assert bench.main(["--out", str(out), "--only", "scratchbot,biotact-g1", "--quick"]) == 0
    assert calls == ["scratchbot", "biotact-g1"]  # nothing run again
    with pytest.raises(SystemExit):
        bench.main(["--out", str(out), "--only", "nope"])
