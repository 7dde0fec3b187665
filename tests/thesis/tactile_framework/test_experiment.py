"""`vibrissa reproduce tactile-framework --quick`: the results, the report and its figures."""

from __future__ import annotations

import json


def test_quick_run_results_and_report(quick_runs):
    out, res = quick_runs["tactile-framework"]
    assert set(res["curves"]) == {"passive", "active", "oracle"}
    for rows in res["curves"].values():
        assert [r["threshold"] for r in rows] == sorted(r["threshold"] for r in rows)
        for r in rows:
            assert r["decided_fraction"] is None or 0.0 <= r["decided_fraction"] <= 1.0
    pol = res["policies"]
    assert pol["passive"]["repositions"] == 0
    for name in ("passive", "active", "oracle"):
        m = res["maps"][name]
        assert m["empty_map_error"] > 0 and m["occupancy_error"] > 0
    assert res["calibration"]["contacts"] > 0
    report = (out / "report.md").read_text()
    for fig in ("curves.png", "episode.png", "radial.png", "touch_map.png"):
        assert (out / "figures" / fig).stat().st_size > 10_000
        assert f"figures/{fig}" in report
    # every number of the policy table comes from the results
    assert f"| passive | {pol['passive']['contacts']} |" in report
    saved = json.loads((out / "results.json").read_text())
    assert saved["comparison"] == res["comparison"]
