"""benchmarks/profile_floor_contact.py: checks its options first, writes what it measured."""

from __future__ import annotations

import json

import pytest


def test_bad_seconds_are_refused_before_any_work(bench_script, tmp_path, monkeypatch) -> None:
    bench = bench_script("profile_floor_contact")
    monkeypatch.setattr(bench, "profile", lambda s: pytest.fail("ran before checking"))
    for bad in ("0", "-1", "nan", "17"):
        with pytest.raises(SystemExit) as exc:
            bench.main(["--seconds", bad, "--out", str(tmp_path / "f.json")])
        assert exc.value.code == 2
    assert not (tmp_path / "f.json").exists()


def test_writes_the_cases_and_the_load(bench_script, tmp_path, monkeypatch) -> None:
    bench = bench_script("profile_floor_contact")
    monkeypatch.setattr(bench, "profile", lambda s: {"as_run": {"vinyl, spot": {"x": s}}})
    out = tmp_path / "f.json"
    assert bench.main(["--seconds", "0.5", "--out", str(out)]) == 0
    res = json.loads(out.read_text())
    assert res["cases"]["as_run"]["vinyl, spot"]["x"] == 0.5
    assert res["recorded_seconds"] == 0.5 and "load_average_at_start" in res
