"""`vibrissa reproduce scratchbot` (thesis 6.3): the JSON contract and the thesis' relations."""

from __future__ import annotations

import json
import math

from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()
STAT = {"mean", "std"}


def test_json_contract_and_the_relations_of_6_3(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["reproduce", "scratchbot", "--quick", "--json", "--workers", "1",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    conds = s["conditions"]
    assert len(conds) == 9
    grid = {(c["radial_distance_mm"], c["whisk_frequency_hz"]) for c in conds}
    assert grid == {(r, f) for r in (70.0, 100.0, 130.0) for f in (2.0, 4.0, 6.0)}
    for c in conds:
        assert set(c) == {"radial_distance_mm", "whisk_frequency_hz", "peak_deflection_v",
                          "contact_duration_s"}
        for k in ("peak_deflection_v", "contact_duration_s"):
            assert set(c[k]) == STAT and all(math.isfinite(v) for v in c[k].values())
            assert c[k]["mean"] > 0
    assert set(s["classifiers"]) == {"feature", "template"}
    for e in s["classifiers"].values():
        assert set(e["radius_mm"]) == STAT and set(e["whisk_frequency_hz"]) == STAT
        assert 0.0 <= e["joint_correct"] <= 1.0
    # 6.3: peak deflection falls with radial distance at a given whisk speed, and the
    # contact duration falls as the whisk speed rises (the reverse of the XY robot)
    by = {(c["radial_distance_mm"], c["whisk_frequency_hz"]): c for c in conds}
    for f in (2.0, 4.0, 6.0):
        peaks = [by[(r, f)]["peak_deflection_v"]["mean"] for r in (70.0, 100.0, 130.0)]
        assert peaks[0] > peaks[1] > peaks[2], f
    for r in (70.0, 100.0, 130.0):
        durs = [by[(r, f)]["contact_duration_s"]["mean"] for f in (2.0, 4.0, 6.0)]
        assert durs[0] > durs[1] > durs[2], r
    assert s["relations"] == {"peak_falls_with_distance": True,
                              "duration_falls_with_frequency": True}
    md = (out / "report.md").read_text()
    assert "Figure 3.9" in md and "figures/figure_3_9.png" in md
    assert (out / "report.html").stat().st_size > 0
    for name in ("figure_3_9", "scratchbot_features", "whisk_trajectories"):
        assert (out / "figures" / f"{name}.png").stat().st_size > 0
