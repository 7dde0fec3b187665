"""`vibrissa identify`: table and JSON of the thesis' observables."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()


def test_identify_json_has_every_observable_with_thesis_value_and_tolerance():
    res = runner.invoke(app, ["identify", "--quick", "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["quick"] is True and d["n_trials"] > 0
    obs = d["observables"]
    assert "resonance_hz" in obs and "mi_latency_ms" in obs and "tip_zone_mm" in obs
    for key, o in obs.items():
        assert o["key"] == key
        for field in (
            "description",
            "thesis",
            "thesis_value",
            "value",
            "unit",
            "tolerance",
            "within",
            "detail",
        ):
            assert field in o
    assert d["n_within"] == sum(o["within"] for o in obs.values())


def test_identify_table_names_each_observable():
    res = runner.invoke(app, ["identify", "--quick"], terminal_width=200)
    assert res.exit_code == 0, res.output
    assert "resonance_hz" in res.stdout and "observables within tolerance" in res.stdout
