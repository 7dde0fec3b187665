"""Sources: CSV and JSON lines alike, bad lines reported once, files followed, UDP, replay."""

from __future__ import annotations

import io
import json
import socket
import sys
import threading
import time
import types

import numpy as np
import pytest

from vibrissa.data.dataset import make_dataset
from vibrissa.data.netcdf import save_dataset
from vibrissa.framework import ContactReport, TactilePipeline
from vibrissa.framework.sources import TextSource, open_source, replay_dataset
from vibrissa.framework.stream import IssueLog, StreamGuard

from .test_stream import FS, make_stream, offline


def as_csv(t, x, header=True):
    cols = [f"w{w}c{c}" for w in range(x.shape[1]) for c in range(x.shape[2])]
    rows = [",".join(["t", *cols])] if header else []
    flat = x.reshape(t.size, -1)
    rows += [
        ",".join([repr(float(ti)), *map(repr, map(float, r))])
        for ti, r in zip(t, flat, strict=True)
    ]
    return "\n".join(rows) + "\n"


def as_jsonl(t, x):
    return "".join(
        json.dumps({"t": float(ti), "x": xi.tolist()}) + "\n" for ti, xi in zip(t, x, strict=True)
    )


def run(source):
    g = StreamGuard(TactilePipeline(FS, 2, 2), log=source.log)
    out = []
    for t, v in source:
        out += g.push(t, v)
    out += g.flush()
    return [o.to_dict() for o in out], g


def test_csv_with_and_without_header_and_jsonl_give_the_offline_reports():
    t, x = make_stream(3.0)
    ref = offline(t, x)
    for text in (as_csv(t, x), as_csv(t, x, header=False), as_jsonl(t, x)):
        got, g = run(TextSource(io.BytesIO(text.encode()), 2, 2))
        assert got == ref and g.issue_counts == {}
    assert len(ref) == 2


def test_a_named_header_places_the_columns_and_missing_values_are_nan():
    text = "t,w1c0,w0c1,w1c1,w0c0\n0,3,2,4,1\n0.001,3,,4,1\n"
    (t, v), *_ = list(TextSource(io.StringIO(text), 2, 2))
    assert t.tolist() == [0.0, 0.001]
    assert v[0].tolist() == [[1, 2], [3, 4]] and np.isnan(v[1, 0, 1])
    with pytest.raises(ValueError, match="header"):
        list(TextSource(io.StringIO("t,a,b\n0,1,2\n"), 2, 2))


@pytest.mark.parametrize("fmt", ["csv", "jsonl"])
def test_malformed_lines_are_one_issue_and_later_contacts_survive(fmt):
    t, x = make_stream(3.0)
    lines = (as_csv(t, x) if fmt == "csv" else as_jsonl(t, x)).splitlines()
    bad = ["1.0,oops", "{not json", '{"t": 1, "x": [1, 2]}', "nan,1,2,3,4", "\x00\xff"]
    for k, b in enumerate(bad):
        lines.insert(900 + 3 * k, b)  # before the first contact (1.0 s)
    text = "\n".join(lines) + "\n"
    got, g = run(TextSource(io.BytesIO(text.encode()), 2, 2))
    assert g.issue_counts == {"bad_line": len(bad)}
    issues = [d for d in got if d.get("type") == "stream_issue"]
    assert len(issues) == 1 and issues[0]["message"].startswith("line ")
    assert [d for d in got if "type" not in d] == offline(t, x)


def test_a_growing_file_is_followed_until_it_is_idle(tmp_path):
    t, x = make_stream(3.0)
    lines = as_csv(t, x).splitlines(keepends=True)
    path = tmp_path / "live.csv"
    path.write_text("".join(lines[:500]))

    def grow():
        with open(path, "a") as fh:
            for a in range(500, len(lines), 700):
                time.sleep(0.05)
                fh.write("".join(lines[a : a + 700]))
                fh.flush()

    writer = threading.Thread(target=grow)
    writer.start()
    source = open_source(str(path), 2, 2, follow=True, idle_timeout_s=0.4)
    start = time.monotonic()
    got, g = run(source)
    writer.join()
    assert got == offline(t, x) and g.records == t.size
    assert 0.4 <= time.monotonic() - start < 5


def test_udp_datagrams_of_several_lines_on_an_ephemeral_port():
    t, x = make_stream(3.0)
    lines = as_csv(t, x, header=False).splitlines()
    source = open_source("udp://127.0.0.1:0", 2, 2, idle_timeout_s=0.5)
    addr = source.address
    assert addr[1] > 0

    def send():
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            for a in range(0, len(lines), 20):
                s.sendto("\n".join(lines[a : a + 20]).encode(), addr)
                time.sleep(0.002)  # 10 kHz of records: a fast sensor, not a flood

    sender = threading.Thread(target=send)
    sender.start()
    got, g = run(source)
    sender.join()
    assert g.records == t.size  # nothing lost on the loopback
    assert got == offline(t, x)


def test_serial_without_pyserial_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "serial", None)
    with pytest.raises(ValueError, match=r"vibrissa\[serial\]"):
        open_source("serial:///dev/ttyUSB0?baud=9600", 1, 2)


def test_serial_reads_lines_through_pyserial(monkeypatch):
    chunks = [b"0,1,2\n0.00", b"1,3,4\n", b"0.002,5,6"]
    opened = {}

    class FakeSerial:
        in_waiting = 0

        def __init__(self, device, baud, timeout):
            opened.update(device=device, baud=baud)

        def read(self, n):
            return chunks.pop(0) if chunks else b""

        def close(self):
            opened["closed"] = True

    fake = types.ModuleType("serial")
    fake.Serial = FakeSerial
    fake.SerialException = OSError
    monkeypatch.setitem(sys.modules, "serial", fake)
    source = open_source("serial:///dev/ttyUSB0?baud=9600", 1, 2, idle_timeout_s=0.1)
    ts = np.concatenate([t for t, _ in source])
    assert ts.tolist() == [0.0, 0.001, 0.002]
    assert opened == {"device": "/dev/ttyUSB0", "baud": 9600, "closed": True}


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        ("udp://127.0.0.1:99999", "port"),
        ("udp://:5000", "HOST:PORT"),
        ("tcp://x:1", "scheme"),
        ("serial://", "DEVICE"),
        ("serial:///dev/x?speed=3", "baud"),
        ("no/such/file.csv", "does not exist"),
    ],
)
def test_bad_inputs_are_refused_naming_them(spec, match, tmp_path):
    with pytest.raises(ValueError, match=match):
        open_source(spec, 1, 2)


def test_a_port_in_use_is_refused():
    first = open_source("udp://127.0.0.1:0", 1, 1)
    try:
        with pytest.raises(ValueError, match="cannot listen"):
            open_source(f"udp://127.0.0.1:{first.address[1]}", 1, 1)
    finally:
        first.close()


def small_dataset(path, n_trials=3, n_time=800, seed=1):
    """Trials (n_trials, 2 channels, n_time) at FS, each with one contact."""
    rng = np.random.default_rng(seed)
    sig = 0.005 * rng.standard_normal((n_trials, 2, n_time))
    tt = np.arange(n_time) / FS
    for k in range(n_trials):
        m = (tt >= 0.3) & (tt < 0.42)
        sig[k, 0, m] += (0.3 + 0.1 * k) * np.sin(np.pi * (tt[m] - 0.3) / 0.12)
    save_dataset(make_dataset(sig, sample_rate_hz=FS, channels=["x", "y"]), path)
    return sig


def test_replay_at_full_speed_is_the_offline_run_on_the_concatenated_trials(tmp_path):
    sig = small_dataset(tmp_path / "d.nc")
    source = replay_dataset(tmp_path / "d.nc", speed=0, trials=slice(1, 3))
    assert source.n_channels == 2 and source.sample_rate_hz == FS
    p = TactilePipeline(FS, 1, 2)
    g = StreamGuard(p)
    got = []
    for t, v in source:
        got += g.push(t, v)
    got += g.flush()
    flat = sig[1:3].transpose(0, 2, 1).reshape(-1, 1, 2)
    q = TactilePipeline(FS, 1, 2)
    ref = [r.to_dict() for r in q.feed(flat) + q.flush()]
    assert [r.to_dict() for r in got if isinstance(r, ContactReport)] == ref and len(ref) == 2


def test_replay_at_speed_one_takes_real_time(tmp_path):
    small_dataset(tmp_path / "d.nc", n_trials=1, n_time=500)
    start = time.monotonic()
    batches = list(replay_dataset(tmp_path / "d.nc", speed=1.0))
    took = time.monotonic() - start
    assert sum(t.size for t, _ in batches) == 500 and len(batches) > 5
    # never faster than the data's own 0.5 s; the upper bound only catches a stall (a
    # loaded CI worker also reads and verifies the file inside the timed call)
    assert 0.45 <= took < 3.0


def test_replay_refuses_bad_trials_and_speed(tmp_path):
    small_dataset(tmp_path / "d.nc")
    with pytest.raises(ValueError, match="selects none"):
        replay_dataset(tmp_path / "d.nc", trials=slice(5, 9))
    with pytest.raises(ValueError, match="speed"):
        replay_dataset(tmp_path / "d.nc", speed=-1)
    with pytest.raises(ValueError, match="trials"):
        replay_dataset(tmp_path / "d.nc", trials=[0, 7])


def test_bad_lines_share_the_log_given():
    log = IssueLog()
    src = TextSource(io.StringIO("0,1\nx\n0.001,2\n"), 1, 1, "csv", log=log)
    assert sum(t.size for t, _ in src) == 2 and log.counts == {"bad_line": 1}
