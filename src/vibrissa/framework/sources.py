"""Live sample sources: batches of ``(t_s, values)`` from text streams, sockets and datasets.

Every source is an iterable of batches ``(t_s, values)``: ``t_s`` of shape ``(n,)``
(seconds on the stream's clock) and ``values`` of shape ``(n, n_whiskers,
n_channels)`` (NaN where missing), what :meth:`vibrissa.framework.StreamGuard.push`
takes. A batch is yielded as soon as the input has no more data ready, so a live
stream is passed on with the latency of its own arrival.

Two text formats, one record a line:

CSV
    ``t`` then ``n_whiskers * n_channels`` numbers, whisker-major (``w0c0, w0c1,
    w1c0, ...``). A header is optional: a first line naming the columns ``t`` then
    ``w{i}c{j}`` (any order) places them by name; any other header with the right
    number of columns is skipped and the columns are taken by position. An empty
    field or ``nan`` is a missing value; ``#`` starts a comment line.
JSON lines
    ``{"t": 0.001, "x": [[...], [...]]}``: ``x`` of shape ``(n_whiskers,
    n_channels)`` (or flat, whisker-major); ``null`` is a missing value.

``fmt=None`` takes JSON lines when the first line that is not blank starts with
``{``, else CSV. A line that cannot be read (wrong count, not a number, no finite
time) is a ``bad_line`` :class:`StreamIssue` in the source's :class:`IssueLog`
(reported once, counted every time), never an exception.

The sources: :class:`TextSource` (a file object, e.g. standard input, or a file
read once, or a growing file followed with ``follow=True`` until it has been idle
``idle_timeout_s``), :class:`UdpSource` (``udp://HOST:PORT``, each datagram one or
more lines), :class:`SerialSource` (``serial:///dev/ttyUSB0?baud=115200``, with
pyserial, the optional extra ``vibrissa[serial]``), all made by
:func:`open_source`; and :func:`replay_dataset`, a Dataset file played back in real
time as one whisker's stream.
"""

from __future__ import annotations

import codecs
import contextlib
import json
import math
import os
import re
import socket
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any
from urllib.parse import parse_qs, urlsplit

import numpy as np

from vibrissa._validate import non_negative, positive
from vibrissa.framework.stream import IssueLog

__all__ = [
    "FORMATS",
    "LineParser",
    "ReplaySource",
    "SerialSource",
    "TextSource",
    "UdpSource",
    "open_source",
    "replay_dataset",
]

#: The text formats.
FORMATS = ("csv", "jsonl")
_CHUNK_BYTES = 1 << 16
_COLUMN = re.compile(r"^w(\d+)c(\d+)$")
_TIME_NAMES = {"t", "t_s", "time", "time_s"}

Batch = tuple[np.ndarray, np.ndarray]


def _count(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


class LineParser:
    """Text lines -> records, for one stream's shape and format.

    Parameters
    ----------
    n_whiskers, n_channels : int
        Shape of one record's values.
    fmt : {"csv", "jsonl"} or None
        ``None``: decided by the first line that is not blank.
    log : IssueLog, optional
        Where ``bad_line`` issues go (a new one by default).
    """

    def __init__(
        self,
        n_whiskers: int,
        n_channels: int,
        fmt: str | None = None,
        log: IssueLog | None = None,
    ) -> None:
        self.n_whiskers = _count("n_whiskers", n_whiskers)
        self.n_channels = _count("n_channels", n_channels)
        if fmt is not None and fmt not in FORMATS:
            raise ValueError(f"fmt must be one of {', '.join(FORMATS)}, got {fmt!r}")
        self.fmt = fmt
        self.log = IssueLog() if log is None else log
        self.line_number = 0
        self.last_t = math.nan
        self._width = self.n_whiskers * self.n_channels
        self._order: np.ndarray | None = None  # CSV column of each value (by name)
        self._seen_first = False

    def parse(self, lines: Sequence[str]) -> Batch:
        """Records of ``lines`` (without their newlines); bad lines reported and skipped.

        Parameters
        ----------
        lines : sequence of str

        Returns
        -------
        t_s : ndarray of shape (n,)
        values : ndarray of shape (n, n_whiskers, n_channels)
        """
        ts: list[float] = []
        rows: list[list[float]] = []
        for line in lines:
            self.line_number += 1
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            if not self._seen_first:
                self._seen_first = True
                if self.fmt is None:
                    self.fmt = "jsonl" if text.startswith("{") else "csv"
                if self.fmt == "csv" and self._header(text):
                    continue
            got = self._jsonl(text) if self.fmt == "jsonl" else self._csv(text)
            if isinstance(got, str):
                self.log.report(
                    "bad_line",
                    self.last_t,
                    f"line {self.line_number}: {got}; the line is skipped",
                )
                continue
            t, row = got
            ts.append(t)
            rows.append(row)
            self.last_t = t
        values = np.array(rows, dtype=float).reshape(len(rows), self.n_whiskers, self.n_channels)
        return np.array(ts, dtype=float), values

    # -- CSV -----------------------------------------------------------------------------
    def _header(self, text: str) -> bool:
        """Whether the first line is a header (placing the columns by name if it names them)."""
        fields = [f.strip().strip('"').lower() for f in text.split(",")]
        try:
            float(fields[0])
            return False
        except ValueError:
            pass
        if len(fields) != 1 + self._width:
            raise ValueError(
                f"the CSV header has {len(fields)} columns, expected {1 + self._width} "
                f"(t, then {self.n_whiskers} whiskers x {self.n_channels} channels)"
            )
        names = [_COLUMN.match(f) for f in fields[1:]]
        if fields[0] in _TIME_NAMES and all(names):
            index = [int(m.group(1)) * self.n_channels + int(m.group(2)) for m in names if m]
            ok = all(
                int(m.group(1)) < self.n_whiskers and int(m.group(2)) < self.n_channels
                for m in names
                if m
            )
            if not ok or sorted(index) != list(range(self._width)):
                raise ValueError(
                    f"the CSV header's columns {', '.join(fields[1:])} are not w0c0 .. "
                    f"w{self.n_whiskers - 1}c{self.n_channels - 1}, each once"
                )
            order = np.empty(self._width, dtype=int)
            order[index] = np.arange(self._width)
            self._order = order
        return True

    def _csv(self, text: str) -> tuple[float, list[float]] | str:
        fields = text.split(",")
        if len(fields) != 1 + self._width:
            return f"expected {1 + self._width} comma-separated fields, got {len(fields)}"
        try:
            t = float(fields[0])
            row = [float(f) if f.strip() else math.nan for f in fields[1:]]
        except ValueError:
            return "a field is not a number"
        if not math.isfinite(t):
            return "the time is not a finite number"
        if self._order is not None:
            row = [row[i] for i in self._order]
        return t, row

    # -- JSON lines ----------------------------------------------------------------------
    def _jsonl(self, text: str) -> tuple[float, list[float]] | str:
        try:
            obj = json.loads(text)
        except ValueError:
            return "not valid JSON"
        if not isinstance(obj, dict) or "t" not in obj or "x" not in obj:
            return 'expected an object with "t" and "x"'
        t = obj["t"]
        if isinstance(t, bool) or not isinstance(t, int | float) or not math.isfinite(t):
            return '"t" is not a finite number'
        try:
            x = np.array(obj["x"], dtype=float)  # None -> nan
        except (TypeError, ValueError):
            return '"x" is not an array of numbers'
        if x.shape not in ((self.n_whiskers, self.n_channels), (self._width,)):
            return (
                f'"x" has shape {x.shape}, expected ({self.n_whiskers}, {self.n_channels}) '
                f"or ({self._width},)"
            )
        return float(t), x.ravel().tolist()


class _Lines:
    """Bytes in chunks -> complete lines (a partial last line kept for the next chunk)."""

    def __init__(self) -> None:
        self._decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")
        self._tail = ""

    def feed(self, data: bytes | str, final: bool = False) -> list[str]:
        """The complete lines of what came so far (all of them when ``final``)."""
        text = data if isinstance(data, str) else self._decoder.decode(data, final)
        lines = (self._tail + text).split("\n")
        self._tail = lines.pop()
        if final and self._tail:
            lines.append(self._tail)
            self._tail = ""
        return [ln.rstrip("\r") for ln in lines]


class _Base:
    """What every text source shares: the parser and the batches."""

    def __init__(
        self, n_whiskers: int, n_channels: int, fmt: str | None, log: IssueLog | None
    ) -> None:
        self.parser = LineParser(n_whiskers, n_channels, fmt, log)
        self.log = self.parser.log

    def _batch(self, lines: list[str]) -> Batch | None:
        t, v = self.parser.parse(lines)
        return (t, v) if t.shape[0] else None


class TextSource(_Base):
    """Records from a file object (e.g. standard input) or a file, optionally followed.

    Parameters
    ----------
    source : path-like or file object
        A path is opened (binary); a file object is read as it is (a text one too).
    n_whiskers, n_channels : int
    fmt : {"csv", "jsonl"} or None
    follow : bool, default=False
        Keep reading a file as it grows (``tail -f``) until it has not grown for
        ``idle_timeout_s``; a file that shrinks is read again from its start.
    idle_timeout_s : float or None
        With ``follow``: seconds without new data that end the stream (``None``:
        never).
    poll_s : float, default=0.05
        With ``follow``: how often the file is looked at.
    log : IssueLog, optional
    """

    def __init__(
        self,
        source: str | os.PathLike[str] | IO[Any],
        n_whiskers: int,
        n_channels: int,
        fmt: str | None = None,
        *,
        follow: bool = False,
        idle_timeout_s: float | None = None,
        poll_s: float = 0.05,
        log: IssueLog | None = None,
    ) -> None:
        super().__init__(n_whiskers, n_channels, fmt, log)
        self.source = source
        self.follow = bool(follow)
        if follow and not isinstance(source, str | os.PathLike):
            raise ValueError("follow needs a file path, not an open stream")
        self.idle_timeout_s = (
            None if idle_timeout_s is None else positive("idle_timeout_s", idle_timeout_s)
        )
        self.poll_s = positive("poll_s", poll_s)

    def __iter__(self) -> Iterator[Batch]:
        """Batches of records as they are read."""
        if isinstance(self.source, str | os.PathLike):
            with open(self.source, "rb") as fh:
                yield from self._read(fh)
        else:
            yield from self._read(self.source)

    def _read(self, fh: IO[Any]) -> Iterator[Batch]:
        lines = _Lines()
        read = _reader(fh)
        idle_since = time.monotonic()
        while True:
            data = read()
            if data:
                idle_since = time.monotonic()
                batch = self._batch(lines.feed(data))
                if batch is not None:
                    yield batch
                continue
            if not self.follow:
                break
            if self._truncated(fh):
                self.log.report(
                    "bad_line",
                    self.parser.last_t,
                    f"{self.source} shrank: read again from its start",
                )
                os.lseek(fh.fileno(), 0, os.SEEK_SET)
                lines = _Lines()
                continue
            if (
                self.idle_timeout_s is not None
                and time.monotonic() - idle_since >= self.idle_timeout_s
            ):
                break
            time.sleep(self.poll_s)
        batch = self._batch(lines.feed(b"", final=True))
        if batch is not None:
            yield batch

    @staticmethod
    def _truncated(fh: IO[Any]) -> bool:
        fd = _fileno(fh)
        if fd is None:
            return False
        return os.fstat(fd).st_size < os.lseek(fd, 0, os.SEEK_CUR)


def _fileno(fh: Any) -> int | None:
    try:
        return int(fh.fileno())
    except (AttributeError, OSError, ValueError):
        return None


def _reader(fh: Any) -> Callable[[], bytes | str]:
    """A function returning the next data ready (empty at the end of what is there).

    An operating-system file is read with ``os.read``, which returns as soon as some
    data is there (a pipe's lines are passed on at once); a Python stream (no file
    descriptor) with ``read1`` or ``read``.
    """
    fd = _fileno(fh)
    if fd is not None:
        return lambda: os.read(fd, _CHUNK_BYTES)
    buf = getattr(fh, "buffer", None)
    if buf is not None and hasattr(buf, "read1"):
        return lambda: buf.read1(_CHUNK_BYTES)
    if hasattr(fh, "read1"):
        return lambda: fh.read1(_CHUNK_BYTES)
    return lambda: fh.read(_CHUNK_BYTES)


class UdpSource(_Base):
    """Records from UDP datagrams, each one or more whole lines.

    The socket is bound when the source is made (port 0: an ephemeral one, see
    :attr:`address`), so a port in use is an error before any work.

    Parameters
    ----------
    host : str
    port : int
        0 to 65535.
    n_whiskers, n_channels : int
    fmt : {"csv", "jsonl"} or None
    idle_timeout_s : float or None
        Seconds without a datagram that end the stream (``None``: never).
    poll_s : float, default=0.05
        How long one wait for a datagram lasts (the granularity of the timeout).
    log : IssueLog, optional
    """

    def __init__(
        self,
        host: str,
        port: int,
        n_whiskers: int,
        n_channels: int,
        fmt: str | None = None,
        *,
        idle_timeout_s: float | None = None,
        poll_s: float = 0.05,
        log: IssueLog | None = None,
    ) -> None:
        super().__init__(n_whiskers, n_channels, fmt, log)
        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
            raise ValueError(f"port must be an integer in [0, 65535], got {port!r}")
        self.idle_timeout_s = (
            None if idle_timeout_s is None else positive("idle_timeout_s", idle_timeout_s)
        )
        self.poll_s = positive("poll_s", poll_s)
        try:
            family = socket.getaddrinfo(host, port, type=socket.SOCK_DGRAM)[0][0]
        except socket.gaierror as exc:
            raise ValueError(f"udp://{host}:{port}: unknown host ({exc.strerror})") from None
        self._sock = socket.socket(family, socket.SOCK_DGRAM)
        with contextlib.suppress(OSError):  # room for bursts (the kernel may cap it)
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
        try:
            self._sock.bind((host, port))
        except OSError as exc:
            self._sock.close()
            raise ValueError(f"udp://{host}:{port}: cannot listen ({exc.strerror})") from None
        self._sock.settimeout(self.poll_s)

    @property
    def address(self) -> tuple[str, int]:
        """The bound ``(host, port)``."""
        host, port = self._sock.getsockname()[:2]
        return str(host), int(port)

    def close(self) -> None:
        """Close the socket."""
        self._sock.close()

    def __iter__(self) -> Iterator[Batch]:
        """Batches of records: every datagram waiting is taken at once."""
        idle_since = time.monotonic()
        try:
            while True:
                try:
                    data = self._sock.recv(_CHUNK_BYTES)
                except TimeoutError:
                    if (
                        self.idle_timeout_s is not None
                        and time.monotonic() - idle_since >= self.idle_timeout_s
                    ):
                        return
                    continue
                idle_since = time.monotonic()
                lines = data.decode("utf-8", errors="replace").splitlines()
                self._sock.setblocking(False)
                try:
                    while True:  # what else has arrived already
                        lines += (
                            self._sock.recv(_CHUNK_BYTES)
                            .decode("utf-8", errors="replace")
                            .splitlines()
                        )
                except (BlockingIOError, InterruptedError):
                    pass
                finally:
                    self._sock.settimeout(self.poll_s)
                batch = self._batch(lines)
                if batch is not None:
                    yield batch
        finally:
            self.close()


class SerialSource(_Base):
    """Records from a serial port, through pyserial (the optional extra ``vibrissa[serial]``).

    The port is opened when the source is made, so a missing device or pyserial is
    an error before any work.

    Parameters
    ----------
    device : str
        E.g. ``/dev/ttyUSB0`` or ``COM3``.
    baud : int, default=115200
    n_whiskers, n_channels : int
    fmt : {"csv", "jsonl"} or None
    idle_timeout_s : float or None
        Seconds without data that end the stream (``None``: never).
    poll_s : float, default=0.05
    log : IssueLog, optional
    """

    def __init__(
        self,
        device: str,
        n_whiskers: int,
        n_channels: int,
        fmt: str | None = None,
        *,
        baud: int = 115200,
        idle_timeout_s: float | None = None,
        poll_s: float = 0.05,
        log: IssueLog | None = None,
    ) -> None:
        super().__init__(n_whiskers, n_channels, fmt, log)
        try:
            import serial  # type: ignore[import-untyped]
        except ImportError:
            raise ValueError(
                "serial input needs pyserial: pip install 'vibrissa[serial]'"
            ) from None
        baud = _count("baud", baud)
        self.idle_timeout_s = (
            None if idle_timeout_s is None else positive("idle_timeout_s", idle_timeout_s)
        )
        self.poll_s = positive("poll_s", poll_s)
        try:
            self._port = serial.Serial(device, baud, timeout=self.poll_s)
        except (OSError, ValueError, serial.SerialException) as exc:
            raise ValueError(f"serial://{device}: cannot open ({exc})") from None

    def __iter__(self) -> Iterator[Batch]:
        """Batches of records as bytes arrive."""
        lines = _Lines()
        idle_since = time.monotonic()
        try:
            while True:
                data = self._port.read(max(1, int(getattr(self._port, "in_waiting", 0) or 0)))
                if not data:
                    if (
                        self.idle_timeout_s is not None
                        and time.monotonic() - idle_since >= self.idle_timeout_s
                    ):
                        break
                    continue
                idle_since = time.monotonic()
                batch = self._batch(lines.feed(data))
                if batch is not None:
                    yield batch
            batch = self._batch(lines.feed(b"", final=True))
            if batch is not None:
                yield batch
        finally:
            self._port.close()


def open_source(
    spec: str,
    n_whiskers: int,
    n_channels: int,
    fmt: str | None = None,
    *,
    follow: bool = False,
    idle_timeout_s: float | None = None,
    log: IssueLog | None = None,
) -> TextSource | UdpSource | SerialSource:
    """The source named by ``spec``, opened (files checked, sockets bound, ports opened).

    Parameters
    ----------
    spec : str
        ``-`` (standard input), a path to a regular file, ``udp://HOST:PORT`` or
        ``serial://DEVICE[?baud=N]`` (``serial:///dev/ttyUSB0?baud=115200``).
    n_whiskers, n_channels : int
    fmt : {"csv", "jsonl"} or None
    follow : bool, default=False
        Follow a growing file (paths only).
    idle_timeout_s : float or None
        Seconds without data that end a followed file, UDP or serial stream.
    log : IssueLog, optional

    Returns
    -------
    TextSource, UdpSource or SerialSource

    Raises
    ------
    ValueError
        Naming the input: not a regular file, unknown host, port in use or out of
        range, no pyserial, ``follow`` with something other than a file.
    """
    if not isinstance(spec, str) or not spec:
        raise ValueError(f"input must be -, a file, udp://HOST:PORT or serial://DEVICE: {spec!r}")
    scheme = spec.split("://", 1)[0].lower() if "://" in spec else ""
    if follow and (spec == "-" or scheme):
        raise ValueError(f"follow needs a file path, not {spec}")
    if scheme == "udp":
        parts = urlsplit(spec)
        try:
            port = parts.port
        except ValueError:
            raise ValueError(f"{spec}: the port must be an integer in [0, 65535]") from None
        if not parts.hostname or port is None:
            raise ValueError(f"{spec}: expected udp://HOST:PORT")
        return UdpSource(
            parts.hostname,
            port,
            n_whiskers,
            n_channels,
            fmt,
            idle_timeout_s=idle_timeout_s,
            log=log,
        )
    if scheme == "serial":
        parts = urlsplit(spec)
        device = parts.netloc + parts.path
        if not device:
            raise ValueError(f"{spec}: expected serial://DEVICE (serial:///dev/ttyUSB0)")
        query = parse_qs(parts.query)
        unknown = sorted(set(query) - {"baud"})
        if unknown:
            raise ValueError(f"{spec}: unknown setting {unknown[0]!r} (only baud)")
        baud_text = query.get("baud", ["115200"])[-1]
        if not baud_text.isdigit() or int(baud_text) < 1:
            raise ValueError(f"{spec}: baud must be a positive integer, got {baud_text!r}")
        return SerialSource(
            device,
            n_whiskers,
            n_channels,
            fmt,
            baud=int(baud_text),
            idle_timeout_s=idle_timeout_s,
            log=log,
        )
    if scheme:
        raise ValueError(f"{spec}: unknown input scheme {scheme!r} (udp://, serial://)")
    if spec == "-":
        stdin = sys.stdin
        return TextSource(getattr(stdin, "buffer", stdin), n_whiskers, n_channels, fmt, log=log)
    path = Path(spec)
    if not path.is_file():
        what = "does not exist" if not path.exists() else "is not a regular file"
        raise ValueError(f"{spec} {what}")
    if not os.access(path, os.R_OK):
        raise ValueError(f"{spec} is not readable")
    return TextSource(
        path, n_whiskers, n_channels, fmt, follow=follow, idle_timeout_s=idle_timeout_s, log=log
    )


class ReplaySource:
    """A Dataset file played back as one whisker's continuous stream, trial after trial.

    Made by :func:`replay_dataset`. Sample ``i`` of the concatenated trials has time
    ``i / sample_rate_hz`` and is yielded once ``i / (sample_rate_hz * speed)``
    seconds have passed since the iteration began (``speed`` 0: at once, in batches
    of 4096).

    Attributes
    ----------
    sample_rate_hz : float
        The dataset's ``sample_rate_hz``.
    n_whiskers : int
        1.
    n_channels : int
    n_samples : int
    trials : ndarray
        Indices of the trials played, in order.
    """

    n_whiskers = 1

    def __init__(
        self,
        signal: np.ndarray,
        sample_rate_hz: float,
        trials: np.ndarray,
        speed: float,
        batch_s: float = 0.02,
    ) -> None:
        self.sample_rate_hz = float(sample_rate_hz)
        self.trials = trials
        x = np.asarray(signal, dtype=float)[trials]  # (k, C, T)
        self.n_channels = int(x.shape[1])
        self.values = x.transpose(0, 2, 1).reshape(-1, 1, self.n_channels)
        self.n_samples = int(self.values.shape[0])
        self.speed = speed
        self.batch_s = batch_s

    @property
    def duration_s(self) -> float:
        """Seconds of stream."""
        return self.n_samples / self.sample_rate_hz

    def __iter__(self) -> Iterator[Batch]:
        """Batches ``(t_s, values)`` as they become due."""
        n, fs = self.n_samples, self.sample_rate_hz
        t = np.arange(n) / fs
        if self.speed == 0:
            for a in range(0, n, 4096):
                yield t[a : a + 4096], self.values[a : a + 4096]
            return
        rate = fs * self.speed  # samples per wall-clock second
        per_batch = max(1, math.ceil(self.batch_s * rate))
        start = time.monotonic()
        sent = 0
        while sent < n:
            due = min(n, math.floor((time.monotonic() - start) * rate) + 1)
            if due > sent:
                yield t[sent:due], self.values[sent:due]
                sent = due
                if sent >= n:
                    return
            wait = (min(sent + per_batch, n) - 1) / rate - (time.monotonic() - start)
            if wait > 0:
                time.sleep(wait)


def replay_dataset(
    path: str | os.PathLike[str],
    speed: float = 1.0,
    trials: slice | Sequence[int] | None = None,
) -> ReplaySource:
    """Play a vibrissa Dataset file as one whisker's stream, trial after trial.

    Parameters
    ----------
    path : path-like
        A Dataset file (:func:`vibrissa.data.netcdf.load_dataset`); its signal
        ``(n_trials, n_channels, n_time)`` at ``attrs["sample_rate_hz"]``.
    speed : float, default=1.0
        Multiple of real time; 0 plays as fast as possible.
    trials : slice or sequence of int, optional
        The trials to play, in order (default: all).

    Returns
    -------
    ReplaySource
        An iterable of batches ``(t_s, values)``, ``values`` of shape ``(n, 1,
        n_channels)``, yielded as they become due.

    Raises
    ------
    ValueError
        Naming ``path``, ``speed`` or ``trials``.
    """
    from vibrissa.data.netcdf import load_dataset

    speed = non_negative("speed", speed)
    ds = load_dataset(path)
    signal = ds["signal"].transpose("trial", "channel", "time").values
    n_trials = signal.shape[0]
    if trials is None:
        index = np.arange(n_trials)
    elif isinstance(trials, slice):
        index = np.arange(n_trials)[trials]
    else:
        index = np.asarray(list(trials))
        if index.dtype.kind not in "iu":
            raise TypeError(f"trials must be a slice or integers, got {trials!r}")
        if index.size and (index.min() < -n_trials or index.max() >= n_trials):
            raise ValueError(f"trials must lie in [0, {n_trials - 1}], got {trials!r}")
    if not index.size:
        raise ValueError(f"trials {trials!r} selects none of the {n_trials} trials of {path}")
    return ReplaySource(signal, float(ds.attrs["sample_rate_hz"]), index, speed)
