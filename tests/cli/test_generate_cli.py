"""`vibrissa generate` refuses bad options before any work (issue 13, findings 1-4, 7, 8).

Each command comes from the issue's list; on the old main each ran (or hung) instead.
Finding 7: nothing is printed before a bad ``--out`` is refused; the work is stated
with its time; an interrupted run says what it kept and resumes to the same bytes.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys

import pytest
from console import console_script, interrupt_once_a_shard_exists
from typer.testing import CliRunner

from vibrissa.cli import app
from vibrissa.data import load_dataset
from vibrissa.experiments.generate import generate
from vibrissa.experiments.protocols import get_protocol

runner = CliRunner()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["radial-distance", "--textures", "p80"], "--textures does not apply"),
        (["radial-distance", "--angles", "10,20"], "--angles does not apply"),
        (["angle-texture", "--radial-distances", "5000"], "--radial-distances does not apply"),
        (["radial-distance", "--radial-distances", ""], "empty grid"),
        (["angle-texture", "--textures", ""], "--textures: empty list"),
        (["radial-distance", "--speeds", "1:2:#100000000"], "more than 10000 values"),
        (["radial-distance", "--speeds", "50:100:0.0000001"], "more than 10000 values"),
        (["radial-distance", "--runs", "100000"], "assembled in memory"),
        (["radial-distance", "--runs", "1000000000"], "--runs must lie in [1, 1000000]"),
        (["radial-distance", "--speeds", "100,100,100"], "repeats the value"),
        (
            ["radial-distance", "--quick", "--workers", "0"],
            "error: --workers: expected a positive integer, got 0",
        ),
        (
            ["radial-distance", "--quick", "--seed", "-1"],
            "error: --seed: expected a non-negative integer, got -1",
        ),
    ],
)
def test_bad_options_refused_in_one_line_and_nothing_created(tmp_path, args, message):
    out = tmp_path / "x.nc"
    res = runner.invoke(app, ["generate", *args, "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert "Traceback" not in res.output
    assert list(tmp_path.iterdir()) == []


# ----------------------------------------------------------------- issue 13, finding 7
SMALL = [
    "generate",
    "radial-distance",
    "--radial-distances",
    "100,150",
    "--speeds",
    "60,180",
    "--runs",
    "1",
]


@pytest.mark.parametrize("where", ["existing-dir", "a-file/x.nc", "a-fifo", "/proc/x.nc"])
def test_a_bad_out_prints_nothing_before_its_one_line(tmp_path, where):
    """The old main stated the work and printed a "0/24 trials" line, then failed (or,
    for a pipe or device, simulated everything and replaced it by a plain file)."""
    (tmp_path / "existing-dir").mkdir()
    (tmp_path / "a-file").write_text("keep")
    os.mkfifo(tmp_path / "a-fifo")
    before = sorted(tmp_path.rglob("*"))
    out = where if where.startswith("/") else str(tmp_path / where)
    res = runner.invoke(app, [*SMALL, "--out", out])
    assert res.exit_code == 2
    lines = res.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:"), res.stderr
    assert res.stdout == ""
    assert sorted(tmp_path.rglob("*")) == before


def test_the_work_is_stated_with_its_time_and_size_before_it_starts(tmp_path):
    out = tmp_path / "x.nc"
    res = runner.invoke(app, [*SMALL, "--workers", "1", "--json", "--out", str(out)])
    assert res.exit_code == 0, res.output
    first = res.stderr.splitlines()[0]
    assert re.fullmatch(
        rf"radial-distance: 8 trials, about \d+ (s|min|h) on 1 core, "
        rf"about [\d.]+ MB -> {re.escape(str(out))}",
        first,
    ), first


GRID = ["--radial-distances", "100,120,140,160", "--speeds", "60,100,140,180", "--runs", "1"]


@pytest.mark.parametrize(("sig", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_an_interrupted_generation_says_what_it_kept_and_resumes_to_the_same_bytes(
    tmp_path, sig, status
):
    """The old main stopped silently (SIGTERM killed it, status -15)."""
    out, parts = tmp_path / "x.nc", tmp_path / "x.nc.parts"
    args = [
        "generate",
        "radial-distance",
        *GRID,
        "--chunk-size",
        "1",
        "--workers",
        "2",
        "--out",
        str(out),
    ]
    code, err = interrupt_once_a_shard_exists(args, parts, sig)
    assert code == status, err
    assert "Traceback" not in err
    last = err.splitlines()[-1]
    m = re.fullmatch(
        rf"interrupted: (\d+) of 32 trials kept in {re.escape(str(parts))}/; "
        "rerun the same command to resume",
        last,
    )
    assert m, err
    assert 1 <= int(m.group(1)) == len(list(parts.glob("chunk-*.npz")))  # chunks of 1 trial
    assert not out.exists()
    again = subprocess.run(
        [console_script(), *args],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "CI": "1"},
    )
    assert again.returncode == 0, again.stderr
    protocol = get_protocol(
        "radial-distance",
        radial_distances_mm=(100.0, 120.0, 140.0, 160.0),
        speeds_mm_s=(60.0, 100.0, 140.0, 180.0),
        runs=1,
    )
    ref = generate(protocol, tmp_path / "ref.nc", workers=1)
    assert load_dataset(out)["signal"].values.tobytes() == ref["signal"].values.tobytes()


# ----------------------------------------------------- dask is the optional extra
def without_dask(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make ``dask`` and ``distributed`` unimportable, as in a plain ``pip install``."""
    for name in ("dask", "distributed", "dask.distributed"):
        monkeypatch.setitem(sys.modules, name, None)


def test_a_scheduler_without_dask_is_refused_in_one_line_before_any_work(tmp_path, monkeypatch):
    without_dask(monkeypatch)
    out = tmp_path / "x.nc"
    res = runner.invoke(app, [*SMALL, "--scheduler", "tcp://127.0.0.1:1", "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert res.output.strip() == (
        "error: --scheduler: needs the 'distributed' extra (pip install 'vibrissa[distributed]')"
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "argv",
    [
        ["generate", "radial-distance", "--quick", "-o", "{tmp}/sub/d.nc"],
        ["reproduce", "radial-distance", "--quick", "--out", "{tmp}/rep"],
    ],
)
def test_an_output_that_will_not_fit_is_refused_before_work(tmp_path, monkeypatch, argv) -> None:
    """Issue 33: a full disk was reported only after the simulation it was meant to keep."""
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 1000, 1000))
    res = runner.invoke(app, [a.format(tmp=tmp_path) for a in argv])
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert re.match(
        r"error: (-o|--out): .* needs about [\d,]+ MB for the .*dataset and its shards; "
        r".* has 0 MB free$",
        lines[0],
    ), lines[0]
    assert list(tmp_path.iterdir()) == []
