"""benchmarks/profile_plane_contact.py counts every case and writes its JSON (no timing is
asserted)."""

from __future__ import annotations

import json
import sys


def test_every_case_is_counted_or_says_where_it_failed(tmp_path, monkeypatch, bench_script) -> None:
    bench = bench_script("profile_plane_contact")
    out = tmp_path / "plane.json"
    monkeypatch.setattr(sys, "argv", ["profile_plane_contact.py", "--out", str(out)])
    bench.main()
    cases = json.loads(out.read_text())["cases"]
    assert len(cases) == 8 and "pole" in cases and "wall 60 deg, still, from outside" in cases
    for c in cases.values():
        if "failed" in c:
            assert "converge" in c["failed"]
            continue
        assert c["steps"] > 0 and c["contact_rows"] > 0
        # below 1 where free flight (exact, no Newton) or long steps cover part of it
        assert c["newton_iterations_per_step"] > 0
