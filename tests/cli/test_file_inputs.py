"""Every file input is a regular file before it is opened (issue 33, item 2).

A FIFO blocked ``import``, ``plot`` and ``run crunchbot --arena`` forever; a directory
or a device failed from deep inside a reader. Each is now one line naming the input,
exit 2, before any work. Run as subprocesses with a timeout, so a regression fails
instead of hanging the suite.
"""

from __future__ import annotations

import os
import subprocess

import pytest
from console import console_script


@pytest.fixture
def specials(tmp_path):
    fifo = tmp_path / "pipe.mat"
    os.mkfifo(fifo)
    folder = tmp_path / "folder.nc"
    folder.mkdir()
    return {"fifo": fifo, "folder": folder, "device": "/dev/zero"}


CASES = [
    (["import", "{fifo}", "--out", "o.nc"], "SOURCE: {fifo} is not a regular file"),
    (["import", "{folder}", "--out", "o.nc"], "SOURCE: {folder} is not a regular file"),
    (["import", "{device}", "--out", "o.nc"], "SOURCE: {device} is not a regular file"),
    (["plot", "{fifo}", "--out", "figs"], "DATASET: {fifo} is not a regular file"),
    (["plot", "{folder}", "--out", "figs"], "DATASET: {folder} is not a regular file"),
    (
        ["run", "crunchbot", "--out", "w", "--seconds", "5", "--arena", "{fifo}.json"],
        "--arena: {fifo}.json is not a regular file",
    ),
]


@pytest.mark.parametrize(("args", "line"), CASES)
def test_a_special_file_input_is_refused_in_one_line(tmp_path, specials, args, line):
    if "{fifo}.json" in " ".join(args):
        os.mkfifo(f"{specials['fifo']}.json")
    argv = [a.format(**specials) for a in args]
    res = subprocess.run(
        [console_script(), *argv], capture_output=True, text=True, cwd=tmp_path, timeout=60
    )
    assert res.returncode == 2, res.stderr
    assert res.stderr.strip() == "error: " + line.format(**specials)
    assert not (tmp_path / "o.nc").exists() and not (tmp_path / "figs").exists()
    assert not (tmp_path / "w").exists()


def test_a_fifo_mapping_is_refused_before_it_is_read(tmp_path, specials):
    src = tmp_path / "rec.csv"
    src.write_text("x,y\n2.5,2.5\n2.6,2.5\n")
    res = subprocess.run(
        [console_script(), "import", str(src), "--out", "o.nc", "--mapping", str(specials["fifo"])],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=60,
    )
    assert res.returncode == 2
    assert res.stderr.strip() == f"error: --mapping: {specials['fifo']} is not a regular file"
