"""benchmarks/bench_slam.py runs end to end on a short log and writes its JSON (no timing
is asserted)."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_bench_slam_writes_every_mode(tmp_path, monkeypatch) -> None:
    spec = importlib.util.spec_from_file_location(
        "bench_slam", ROOT / "benchmarks" / "bench_slam.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    out = tmp_path / "slam.json"
    monkeypatch.setattr(
        sys, "argv", ["bench_slam.py", "--steps", "12", "--particles", "4", "--out", str(out)]
    )
    bench.main()
    res = json.loads(out.read_text())
    assert res["n_steps"] == 12 and res["n_particles"] == 4
    assert set(res["modes"]) == {"blob", "geometric", "template"}
    assert all(0 <= m["map_error"] <= 1 for m in res["modes"].values())
