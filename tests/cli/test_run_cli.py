"""`vibrissa run crunchbot`: one run watched as a GIF and a page; bad options refused."""

from __future__ import annotations

import json
import signal

import pytest
from console import interrupt_after
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


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--seconds", "0.001"], "--seconds must be between 0.5 (one FSM step)"),
        (["--seconds", "1e300"], "--seconds must lie in (0, 3600] s"),
        (["--seconds", "nan"], "--seconds must be finite"),
        (["--particles", "1000000000000"], "--particles must lie in [1, 10000]"),
        (["--particles", "0"], "--particles: expected a positive integer"),
        (["--seed", "18446744073709551616"], "--seed: expected an integer at most 2**63 - 1"),
    ],
)
def test_run_crunchbot_refuses_unbounded_work_before_any(tmp_path, args, message):
    out = tmp_path / "w"
    r = runner.invoke(app, ["run", "crunchbot", "--out", str(out), *args])
    assert r.exit_code == 2, r.output
    assert message in r.output and len(r.output.strip().splitlines()) == 1
    assert not out.exists()


@pytest.mark.parametrize(
    ("sig", "after_s"),
    # while the command line is imported, then while the robot is trained or runs
    [(signal.SIGINT, 0.3), (signal.SIGINT, 8.0), (signal.SIGTERM, 8.0)],
)
def test_run_crunchbot_says_it_was_interrupted_at_any_moment(tmp_path, sig, after_s):
    code, err = interrupt_after(
        ["run", "crunchbot", "--out", str(tmp_path / "w"), "--seconds", "60"], after_s, sig
    )
    assert code == 128 + sig, err
    assert err.strip().splitlines()[-1].startswith("interrupted:"), err
    assert "Traceback" not in err
