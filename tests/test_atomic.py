"""Atomic writes name the file asked for when they fail; outputs are checked before work.

Issue 13, finding 7: a full disk printed a bare ``[Errno 28] No space left on
device`` without the path.
"""

from __future__ import annotations

import errno
import os

import pytest

from vibrissa._atomic import atomic_path, atomic_write_text, check_writable


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_full_disk_names_the_file_and_leaves_nothing(tmp_path, monkeypatch):
    monkeypatch.setattr("vibrissa._atomic.os.fsync", _no_space)
    target = tmp_path / "out.nc"
    with pytest.raises(OSError) as info:
        atomic_write_text(target, "data")
    assert info.value.errno == errno.ENOSPC
    assert info.value.filename == str(target) and info.value.filename2 is None
    assert list(tmp_path.iterdir()) == []  # no temporary left behind


def test_a_failed_write_inside_the_block_names_the_target_not_the_temporary(tmp_path):
    target = tmp_path / "out.bin"
    with pytest.raises(OSError) as info, atomic_path(target) as tmp:
        raise OSError(errno.EIO, os.strerror(errno.EIO), str(tmp))
    assert info.value.filename == str(target)


def test_a_file_where_a_directory_is_needed_is_named(tmp_path):
    (tmp_path / "a-file").write_text("keep")
    with pytest.raises(NotADirectoryError) as info:
        atomic_write_text(tmp_path / "a-file" / "sub" / "x.txt", "data")
    assert info.value.filename == str(tmp_path / "a-file")
    assert (tmp_path / "a-file").read_text() == "keep"


def test_replacing_a_directory_names_it_once(tmp_path):
    (tmp_path / "d").mkdir()
    with pytest.raises(OSError) as info:
        atomic_write_text(tmp_path / "d", "data")
    assert info.value.filename == str(tmp_path / "d") and info.value.filename2 is None


@pytest.mark.parametrize(
    ("make", "path", "directory", "message"),
    [
        (lambda p: (p / "d").mkdir(), "d", False, "d is a directory, not a file"),
        (lambda p: (p / "f").write_text("x"), "f", True, "f is a file, not a directory"),
        (lambda p: (p / "f").write_text("x"), "f/sub/x.nc", False, "f is a file, not a directory"),
        (lambda p: None, "/proc/x.nc", False, "no file can be created in /proc"),
        (lambda p: os.mkfifo(p / "pipe"), "pipe", False, "pipe is not a regular file"),
    ],
)
def test_check_writable_refuses_and_creates_nothing(tmp_path, make, path, directory, message):
    make(tmp_path)
    before = sorted(tmp_path.rglob("*"))
    target = path if path.startswith("/") else tmp_path / path
    with pytest.raises(ValueError, match=message):
        check_writable(target, directory=directory)
    assert sorted(tmp_path.rglob("*")) == before


def test_check_writable_accepts_missing_directories_without_creating_them(tmp_path):
    assert check_writable(tmp_path / "a" / "b" / "x.nc") == tmp_path / "a" / "b" / "x.nc"
    assert check_writable(tmp_path / "new-dir", directory=True) == tmp_path / "new-dir"
    (tmp_path / "old.nc").write_text("x")
    check_writable(tmp_path / "old.nc")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.nc"]
