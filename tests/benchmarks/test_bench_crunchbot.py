"""benchmarks/bench_crunchbot.py runs end to end on a short run and writes its JSON (no
timing is asserted)."""

from __future__ import annotations

import json
import sys


def test_bench_crunchbot_times_the_robot_and_each_mode(tmp_path, monkeypatch, bench_script) -> None:
    bench = bench_script("bench_crunchbot")
    out = tmp_path / "crunchbot.json"
    monkeypatch.setattr(
        sys,
        "argv",
        [
            "bench_crunchbot.py",
            "--seconds",
            "6",
            "--particles",
            "4",
            "--quick-training",
            "--out",
            str(out),
        ],
    )
    bench.main()
    res = json.loads(out.read_text())
    assert res["n_particles"] == 4 and res["seconds"] >= 6
    assert res["robot"] == "simulated-physics" and res["quick_training"] is True
    assert res["robot_wall_seconds"] > 0
    assert set(res["modes"]) == {"blob", "geometric", "template"}
    for m in res["modes"].values():
        assert 0 <= m["map_error"] <= 1
        assert m["robot_plus_slam_seconds"] >= m["slam_wall_seconds"]
