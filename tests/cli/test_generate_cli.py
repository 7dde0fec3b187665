"""`vibrissa generate` refuses bad options before any work (issue 13, findings 1-4 and 8).

Each command comes from the issue's list; on the old main each ran (or hung) instead.
"""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()


@pytest.mark.parametrize(("args", "message"), [
    (["radial-distance", "--textures", "p80"], "--textures does not apply"),
    (["radial-distance", "--angles", "10,20"], "--angles does not apply"),
    (["angle-texture", "--radial-distances", "5000"], "--radial-distances does not apply"),
    (["radial-distance", "--radial-distances", ""], "empty grid"),
    (["angle-texture", "--textures", ""], "--textures: empty list"),
    (["radial-distance", "--speeds", "1:2:#100000000"], "more than 10000 values"),
    (["radial-distance", "--speeds", "50:100:0.0000001"], "more than 10000 values"),
    (["radial-distance", "--runs", "1000000000"], "assembled in memory"),
    (["radial-distance", "--speeds", "100,100,100"], "repeats the value"),
    (["radial-distance", "--quick", "--workers", "0"], "workers must be a positive integer"),
    (["radial-distance", "--quick", "--seed", "-1"], "seed must be a non-negative integer"),
])
def test_bad_options_refused_in_one_line_and_nothing_created(tmp_path, args, message):
    out = tmp_path / "x.nc"
    res = runner.invoke(app, ["generate", *args, "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert "Traceback" not in res.output
    assert list(tmp_path.iterdir()) == []
