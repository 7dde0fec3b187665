"""`vibrissa reproduce biotact-g1` (thesis 6.4): the JSON contract and refused input."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.reproduce import get_experiment

runner = CliRunner()
STRATEGIES = ["unmodulated", "rcp7", "rcp9"]


def test_json_contract_of_a_quick_run(quick_runs):
    out, res = quick_runs["biotact-g1"]
    s = get_experiment("biotact-g1").summary(res)
    assert list(s["hit_rate"]) == STRATEGIES
    for strategy in STRATEGIES:
        assert set(s["hit_rate"][strategy]) == {"naive_bayes", "template"}
        for tasks in s["hit_rate"][strategy].values():
            assert set(tasks) == {"joint", "texture", "distance"}
            for rates in tasks.values():
                # training whisks 1-8; the quick grid's 2 whisks: 1 to train, 1 to validate
                assert len(rates) == 8
                assert 0.0 <= rates[0] <= 1.0
                assert rates[1:] == [None] * 7
    # RCP gates protraction (z > 0) and presses less than unmodulated whisking
    w = s["whisks"]
    assert w["unmodulated"]["max_z"] == 0.0 and w["rcp7"]["max_z"] > 0.0
    assert w["rcp7"]["peak_deflection_v"] < w["unmodulated"]["peak_deflection_v"]
    assert set(s["naive_bayes_robust_range"]) == set(STRATEGIES)
    saved = json.loads((out / "results.json").read_text())
    assert saved["hit_rate"] == s["hit_rate"]
    md = (out / "report.md").read_text()
    assert "RCP7 reaches 100 % after seven training whisks" in md
    for fig in ("hit_rate_naive_bayes", "hit_rate_template", "trajectories", "distances"):
        assert (out / "figures" / f"{fig}.png").stat().st_size > 1000
        assert f"figures/{fig}.png" in md


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--distances", "0,10"], "error: --distances (0 mm) places the head inside the surface"),
        (["--distances", "-5,10"], "error: --distances (-5 mm) places the head inside the surface"),
        (["--distances", "5,90"], "error: --distances (90 mm) is beyond the 80 mm whisker's reach"),
        (["--distances", "5"], "error: --distances needs at least 2 numbers"),
        (["--distances", "5,ten"], "error: --distances must be comma-separated numbers"),
        (["--whisk-frequency", "0"], "error: --whisk-frequency must be > 0 Hz, got 0"),
        (["--whisk-frequency", "-2"], "error: --whisk-frequency must be > 0 Hz, got -2"),
        (["--whisk-frequency", "3"], "error: --whisk-frequency (3) must give a whole number"),
        (["--whisk-frequency", "2,4"], "error: --whisk-frequency takes one number"),
    ],
)
def test_bad_input_fails_with_one_line_before_any_simulation(tmp_path, args, message):
    out = tmp_path / "out"
    res = runner.invoke(app, ["reproduce", "biotact-g1", "--quick", "--out", str(out), *args])
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert len(res.output.strip().splitlines()) == 1
    assert not out.exists()  # nothing created, nothing simulated


def test_listed_with_its_trials_and_options():
    res = runner.invoke(app, ["reproduce", "--list", "--json"])
    entry = {e["name"]: e for e in json.loads(res.stdout)["experiments"]}["biotact-g1"]
    assert entry["trials"] == {"quick": 24, "full": 5 * 324}  # 5 sessions (quick: 1)
    assert {"--distances", "--whisk-frequency", "--n-seeds"} <= set(entry["options"])
