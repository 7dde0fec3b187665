"""Atomic file writes: write to a temporary file beside the target, then rename.

A reader never sees a half-written file in place of a good one: either the old
file or the complete new one is at ``path``.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path


def check_writable(path: str | os.PathLike[str], *, directory: bool = False) -> Path:
    """Check, creating nothing, that a file (or a directory) can be written at ``path``.

    Missing directories above ``path`` count as creatable; the nearest existing one
    must be a directory in which a file can be created.

    Parameters
    ----------
    path
        The file (``directory=False``) or directory to be written.
    directory
        Whether ``path`` is to be a directory.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        Naming the path: a directory where a file is wanted or the reverse, a device
        or pipe where a file is wanted (writing atomically would replace it), a file
        where a directory is needed above it, or a place where nothing can be created
        (read-only file system, permissions).
    """
    p = Path(path)
    if p.exists() and p.is_dir() != directory:
        kind = ("a file, not a directory", "a directory, not a file")[p.is_dir()]
        raise ValueError(f"{p} is {kind}")
    if p.exists() and not directory and not p.is_file():
        # a device, pipe or socket: the atomic rename would replace it by a plain file
        raise ValueError(f"{p} is not a regular file (a device, pipe or socket)")
    parent = next(
        (a for a in ((p,) if directory else ()) + tuple(p.parents) if a.exists()), Path.cwd()
    )
    if not parent.is_dir():
        raise ValueError(f"cannot write {p}: {parent} is a file, not a directory")
    try:
        with tempfile.TemporaryFile(dir=parent):
            pass
    except OSError as exc:
        raise ValueError(
            f"cannot write {p}: no file can be created in {parent} ({exc.strerror or exc})"
        ) from None
    return p


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it onto ``path`` on success.

    Parameters
    ----------
    path
        Final destination.
    suffix
        Suffix of the temporary file (defaults to the destination's, so that
        libraries choosing a format by extension still work).

    Yields
    ------
    pathlib.Path
        Where the caller must write the complete file. If the ``with`` block
        raises, the temporary file is removed and ``path`` is left untouched; an
        ``OSError`` that names no file, or the temporary one, then names ``path``.
    """
    target = Path(path)
    tmp: Path | None = None
    try:
        for parent in target.parents:  # a file where a directory is needed
            if parent.exists():
                if not parent.is_dir():
                    raise NotADirectoryError(errno.ENOTDIR, os.strerror(errno.ENOTDIR), str(parent))
                break
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(
            prefix=f".{target.name}.",
            suffix=(target.suffix if suffix is None else suffix) + ".tmp",
            dir=target.parent,
        )
        os.close(fd)
        tmp = Path(tmp_name)
        yield tmp
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        # mkstemp creates 0600 files; give the result the usual umask-governed mode
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target)
    except BaseException as exc:
        if tmp is not None:
            with contextlib.suppress(FileNotFoundError):
                tmp.unlink()
        if isinstance(exc, OSError) and (
            exc.filename is None
            or Path(os.fsdecode(exc.filename)).name.startswith(f".{target.name}.")
        ):
            # a full disk or a failed write names the file the user asked for, not the
            # hidden temporary (or nothing, as some writers leave it)
            exc.filename, exc.filename2 = str(target), None
        raise


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8) and return the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)
