"""`vibrissa reproduce scratchbot` (thesis 6.3): the JSON contract and the thesis' relations."""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()
STAT = {"mean", "std"}


def test_json_contract_and_the_relations_of_6_3(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(
        app, ["reproduce", "scratchbot", "--quick", "--json", "--workers", "1", "--out", str(out)]
    )
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    conds = s["conditions"]
    assert len(conds) == 9
    grid = {(c["radial_distance_mm"], c["whisk_frequency_hz"]) for c in conds}
    assert grid == {(r, f) for r in (70.0, 100.0, 130.0) for f in (2.0, 4.0, 6.0)}
    for c in conds:
        assert set(c) == {
            "radial_distance_mm",
            "whisk_frequency_hz",
            "peak_deflection_v",
            "contact_duration_s",
        }
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
    # over the 5 sessions (seeds 0-4): true only if it held in every one, and the fraction
    assert s["relations"] == {
        "peak_falls_with_distance": True,
        "duration_falls_with_frequency": True,
        "peak_falls_with_distance_fraction": 1.0,
        "duration_falls_with_frequency_fraction": 1.0,
    }
    saved = json.loads((out / "results.json").read_text())
    assert saved["meta"]["n_seeds"] == 5 and saved["meta"]["seeds"] == [0, 1, 2, 3, 4]
    assert saved["meta"]["options"] == {"n_seeds": 5}
    leaf = saved["spread"]["conditions"][0]["peak_deflection_v"]["mean"]
    assert leaf["n"] == 5 and len(leaf["values"]) == 5
    assert leaf["mean"] == pytest.approx(saved["conditions"][0]["peak_deflection_v"]["mean"])
    assert leaf["min"] <= leaf["mean"] <= leaf["max"] and leaf["std"] > 0  # the noise differs
    assert saved["spread"]["relations"]["peak_falls_with_distance"]["values"] == [1.0] * 5
    # the closed loop on the physical whisker: RCP presses less on the pole (3.2.4) and
    # shortens the contact (6.4: "RCP tends to reduce ... the duration of contact")
    cl = s["closed_loop"]["settings"]
    assert [(c["sigma_z"], c["tau_z_periods"]) for c in cl] == [
        (0.0, 0.25),
        (0.7, 0.25),
        (2.0, 0.1),
    ]
    assert cl[0]["max_z"] == 0.0 and all(0 < c["max_z"] <= 1 for c in cl[1:])
    # figure 3.9's outcomes on the physical whisker: one contact per whisk, then biphasic
    assert cl[1]["figure_3_9_contacts"] == [1] * 4 and cl[1]["biphasic_whisks"] == 0
    assert cl[2]["biphasic_whisks"] == 4
    assert cl[0]["peak_deflection_v"] > cl[1]["peak_deflection_v"] > cl[2]["peak_deflection_v"]
    assert cl[0]["contact_time_per_whisk_s"] > cl[2]["contact_time_per_whisk_s"] > 0
    md = (out / "report.md").read_text()
    assert "Figure 3.9" in md and "figures/figure_3_9.png" in md
    assert (out / "report.html").stat().st_size > 0
    for name in ("figure_3_9", "scratchbot_features", "whisk_trajectories", "closed_loop"):
        assert (out / "figures" / f"{name}.png").stat().st_size > 0
