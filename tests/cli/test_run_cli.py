"""`vibrissa run crunchbot`: one run watched as a GIF and a page; bad options refused."""

from __future__ import annotations

import json

from PIL import Image
from typer.testing import CliRunner

from vibrissa.cli import app

runner = CliRunner()


def test_run_crunchbot_writes_the_animation_and_the_page(tmp_path):
    out = tmp_path / "watch"
    res = runner.invoke(
        app,
        [
            "run",
            "crunchbot",
            "--seconds",
            "8",
            "--particles",
            "10",
            "--mode",
            "geometric",
            "--seed",
            "2",
            "--out",
            str(out),
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout)
    assert s["mode"] == "geometric" and s["particles"] == 10 and s["seed"] == 2
    assert "FSM steps" in res.stderr and "8 s of robot time" in res.stderr
    with Image.open(out / "crunchbot.gif") as im:
        assert im.n_frames > 1
    assert "slider" in (out / "crunchbot.html").read_text()
    assert sorted(p.name for p in out.iterdir()) == ["crunchbot.gif", "crunchbot.html"]


def test_run_crunchbot_refuses_a_bad_arena_file_before_any_work(tmp_path):
    bad = tmp_path / "a.toml"
    bad.write_text(
        'size_m = 1.0\ntiles = [["vinyl", "shag"], ["vinyl", "vinyl"]]\n'
        "start = {x_m = 0.3, y_m = 0.3}\n"
    )
    res = runner.invoke(
        app, ["run", "crunchbot", "--arena", str(bad), "--out", str(tmp_path / "o")]
    )
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: --arena") and "'shag'" in lines[0]
    assert not (tmp_path / "o").exists()
