"""benchmarks/bench_thesis.py: times each reproduction, writes after each and resumes."""

from __future__ import annotations

import json

import pytest


def test_times_each_reproduction_and_resumes(bench_script, tmp_path, monkeypatch) -> None:
    bench = bench_script("bench_thesis")
    calls: list[str] = []

    def fake_run(name, out, quick, workers, command=None):
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


def test_keep_records_the_reproduce_command_and_refuses_an_existing_output(
    bench_script, tmp_path, monkeypatch
) -> None:
    bench = bench_script("bench_thesis")
    seen: dict[str, object] = {}

    def fake_run(name, out, quick, workers, command=None):
        seen.update(name=name, out=out, command=command)
        return {"meta": {"wall_seconds": {"generate": 1.0}, "dataset": {"n_trials": 3}}}

    monkeypatch.setattr(bench, "run_experiment", fake_run)
    keep = tmp_path / "kept"
    args = ["--out", str(tmp_path / "t.json"), "--only", "scratchbot", "--keep", str(keep)]
    assert bench.main([*args, "--workers", "2"]) == 0
    assert seen["out"] == keep / "scratchbot"
    assert seen["command"] == (
        f"vibrissa reproduce scratchbot --out {keep / 'scratchbot'} --workers 2 --json"
    )
    (keep / "scratchbot").mkdir(parents=True)
    with pytest.raises(SystemExit):  # refused before any work: a cache would be reused
        bench.main([*args, "--workers", "2", "--restart"])


def test_out_and_keep_of_the_wrong_kind_are_refused_before_any_work(
    bench_script, tmp_path, monkeypatch
) -> None:
    bench = bench_script("bench_thesis")
    monkeypatch.setattr(bench, "run_experiment", lambda *a, **k: pytest.fail("ran"))
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    for args in (
        ["--out", str(tmp_path)],
        ["--out", str(tmp_path / "t.json"), "--keep", str(a_file)],
    ):
        with pytest.raises(SystemExit) as exc:
            bench.main([*args, "--only", "scratchbot"])
        assert exc.value.code == 2
