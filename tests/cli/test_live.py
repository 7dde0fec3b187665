"""`vibrissa live`: a stream through a saved pipeline as JSON lines; bad options refused."""

from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.data.dataset import make_dataset
from vibrissa.data.netcdf import save_dataset
from vibrissa.framework import TactilePipeline

runner = CliRunner()
FS = 1000.0


def make_stream(n_s=3.0, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(n_s * FS)) / FS
    x = 0.005 * rng.standard_normal((t.size, 2, 2))
    for i, onset in enumerate((0.8, 2.0)):
        m = (t >= onset) & (t < onset + 0.15)
        x[m, i % 2, 0] += 0.5 * np.sin(np.pi * (t[m] - onset) / 0.15)
    return t, x


def csv_text(t, x):
    flat = x.reshape(t.size, -1)
    head = "t,w0c0,w0c1,w1c0,w1c1\n"
    return head + "".join(
        f"{float(ti)!r}," + ",".join(map(repr, r.tolist())) + "\n"
        for ti, r in zip(t, flat, strict=True)
    )


def offline(x, n_whiskers=2):
    p = TactilePipeline(FS, n_whiskers, x.shape[2])
    return [r.to_dict() for r in p.feed(x) + p.flush()]


@pytest.fixture
def files(tmp_path):
    TactilePipeline(FS, 2, 2).save(tmp_path / "p.vtp")
    t, x = make_stream()
    text = csv_text(t, x).splitlines(keepends=True)
    text.insert(300, "garbage\n")
    (tmp_path / "in.csv").write_text("".join(text))
    return tmp_path, x


def lines_of(text):
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def test_live_writes_contacts_issues_and_a_summary(files):
    d, x = files
    args = ["live", "--pipeline", str(d / "p.vtp"), "--input", str(d / "in.csv")]
    res = runner.invoke(app, [*args, "--out", str(d / "o.jsonl")])
    assert res.exit_code == 0, res.output
    assert (
        res.stderr.startswith("live: reading") and "1000 Hz, 2 whiskers x 2 channels" in res.stderr
    )
    out = lines_of((d / "o.jsonl").read_text())
    contacts = [{k: v for k, v in o.items() if k != "type"} for o in out if o["type"] == "contact"]
    assert contacts == offline(x) and len(contacts) == 2
    issues = [o for o in out if o["type"] == "stream_issue"]
    assert [i["kind"] for i in issues] == ["bad_line"] and "line 301" in issues[0]["message"]
    assert out[-1] == {
        "type": "summary",
        "samples": x.shape[0],
        "seconds": x.shape[0] / FS,
        "contacts": 2,
        "decisions": 0,
        "issues": {"bad_line": 1},
    }
    # a second run appends to the log
    assert runner.invoke(app, [*args, "--out", str(d / "o.jsonl")]).exit_code == 0
    assert len(lines_of((d / "o.jsonl").read_text())) == 2 * len(out)


def test_live_reads_standard_input_and_stops_at_max_seconds(files):
    d, x = files
    res = runner.invoke(
        app,
        ["live", "--pipeline", str(d / "p.vtp"), "--max-seconds", "1.5"],
        input=(d / "in.csv").read_text(),
    )
    assert res.exit_code == 0, res.output
    out = lines_of(res.stdout)
    assert [o["whisker"] for o in out if o["type"] == "contact"] == [0]
    assert out[-1]["samples"] == 1500


def test_live_replay_is_the_offline_run_on_the_concatenated_trials(tmp_path):
    TactilePipeline(FS, 1, 2).save(tmp_path / "p1.vtp")
    rng = np.random.default_rng(3)
    sig = 0.005 * rng.standard_normal((4, 2, 700))
    sig[:, 0, 300:420] += 0.4 * np.sin(np.pi * np.arange(120) / 120)
    save_dataset(make_dataset(sig, sample_rate_hz=FS), tmp_path / "d.nc")
    res = runner.invoke(
        app,
        ["live", "--pipeline", str(tmp_path / "p1.vtp"), "--replay", str(tmp_path / "d.nc")]
        + ["--speed", "0", "--trials", "1:4"],
    )
    assert res.exit_code == 0, res.output
    out = lines_of(res.stdout)
    contacts = [{k: v for k, v in o.items() if k != "type"} for o in out if o["type"] == "contact"]
    ref = offline(sig[1:4].transpose(0, 2, 1).reshape(-1, 1, 2), n_whiskers=1)
    assert contacts == ref and len(ref) == 3
    assert out[-1]["issues"] == {}


BAD = [
    (["--input", "in.csv"], "--pipeline: missing"),
    (["--pipeline", "nope.vtp", "--input", "in.csv"], "--pipeline"),
    (["--pipeline", "in.csv", "--input", "in.csv"], "--pipeline"),
    (["--pipeline", "p.vtp", "--input", "nope.csv"], "--input"),
    (["--pipeline", "p.vtp", "--input", "."], "--input"),
    (["--pipeline", "p.vtp", "--input", "udp://127.0.0.1:70000"], "--input"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--rate-hz", "500"], "--rate-hz"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--rate-hz", "nan"], "--rate-hz"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--format", "xml"], "--format"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--max-seconds", "-1"], "--max-seconds"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--idle-timeout-s", "0"], "--idle-timeout-s"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--speed", "2"], "--speed"),
    (["--pipeline", "p.vtp", "--input", "-", "--follow"], "--input"),
    (["--pipeline", "p.vtp", "--replay", "in.csv", "--input", "in.csv"], "--input"),
    (["--pipeline", "p.vtp", "--replay", "in.csv"], "--replay"),
    (["--pipeline", "p.vtp", "--replay", "in.csv", "--trials", "a-b"], "--trials"),
    (["--pipeline", "p.vtp", "--input", "in.csv", "--out", "in.csv/x.jsonl"], "--out"),
]


@pytest.mark.parametrize(("args", "names"), BAD, ids=[" ".join(a)[-60:] for a, _ in BAD])
def test_bad_options_exit_2_with_one_line_and_create_nothing(files, args, names, monkeypatch):
    d, _ = files
    monkeypatch.chdir(d)
    before = sorted(p.name for p in d.iterdir())
    res = runner.invoke(
        app, ["live", *args, "--out", "o.jsonl"] if "--out" not in args else ["live", *args]
    )
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and names in lines[0], lines
    assert sorted(p.name for p in d.iterdir()) == before


def test_sigint_flushes_what_was_read_and_exits_130(files):
    d, _ = files
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]  # free a moment ago; the command binds it
    cmd = [sys.executable, "-c", "from vibrissa.cli import main; main()", "live"]
    cmd += ["--pipeline", str(d / "p.vtp"), "--input", f"udp://127.0.0.1:{port}"]
    cmd += ["--out", str(d / "o.jsonl")]
    # a child inherits an ignored SIGINT (a job started in the background of a shell) and
    # Python then installs no KeyboardInterrupt: give it the default disposition
    proc = subprocess.Popen(
        cmd,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "CI": "1"},
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert proc.stderr is not None
    first = proc.stderr.readline()
    assert first.startswith("live: reading udp://")
    t, x = make_stream(1.5)
    text = csv_text(t, x).splitlines()[1:]
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for a in range(0, len(text), 50):
            s.sendto("\n".join(text[a : a + 50]).encode(), ("127.0.0.1", port))
            time.sleep(0.002)
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:  # until the first contact is in the log
        if (d / "o.jsonl").exists() and '"contact"' in (d / "o.jsonl").read_text():
            break
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    try:
        _, rest = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.wait(10) == 130
    # The signal may arrive before the last datagrams are read (a loaded machine): what
    # matters is that everything read is flushed and counted, and the contact is kept.
    said = re.match(r"interrupted: (\d+) records read, (\d+) contacts", rest)
    assert said is not None, rest
    n_read, n_contacts = int(said.group(1)), int(said.group(2))
    assert 0 < n_read <= 1500 and n_contacts >= 1
    out = lines_of((d / "o.jsonl").read_text())
    assert out[-1]["type"] == "summary" and out[-1]["samples"] == n_read
    assert sum(r["type"] == "contact" for r in out) == n_contacts
