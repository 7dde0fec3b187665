"""`vibrissa live`: a live sensor stream through a saved tactile pipeline, as JSON lines.

Every option is checked before any work (the pipeline file loads, the input is a
regular file, ``-``, a UDP address that can be listened on or a serial port that
opens, the dataset to replay loads and matches the pipeline, the output can be
written, numbers are finite and in range); a bad one is one ``error:`` line and exit
status 2, and nothing is created.

The output is one JSON object a line: ``{"type": "contact", ...}`` per contact (the
pipeline's :class:`~vibrissa.framework.ContactReport`, times on the stream's clock),
``{"type": "stream_issue", "kind", "at_s", "message"}`` the first time each kind of
stream fault appears (:mod:`vibrissa.framework.stream`), and last ``{"type":
"summary", "samples", "seconds", "contacts", "decisions", "issues"}``. A file given
to ``--out`` is appended to line by line, each line flushed as it is written, not
written atomically at the end: it is a live log, which a reader follows with ``tail
-f`` while the stream runs, and which keeps everything up to an interruption.
SIGINT and SIGTERM end the stream: the pipeline is flushed (contacts in progress
reported), the summary written, then ``interrupted: ...`` on standard error and
exit status 130 or 143.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import IO, Any

import numpy as np
import typer

from vibrissa._atomic import check_writable
from vibrissa._validate import non_negative, positive
from vibrissa.cli._common import regular_file, user_errors
from vibrissa.cli._interrupt import interruptible, uninterrupted

__all__ = ["register"]

_FORMATS = ("csv", "jsonl")


def register(app: typer.Typer) -> None:
    """Register ``vibrissa live`` on the top-level ``app``."""
    app.command("live")(live_cmd)


def _option(name: str, exc: BaseException) -> ValueError:
    from vibrissa.cli._common import error_message

    return ValueError(f"{name}: {error_message(exc)}")


def _number(name: str, value: float | None, *, zero: bool = False) -> float | None:
    if value is None:
        return None
    try:
        return non_negative(name, value) if zero else positive(name, value)
    except (TypeError, ValueError) as exc:
        reason = "a non-negative" if zero else "a positive"
        raise ValueError(f"{name}: expected {reason} finite number, got {value!r}") from exc


def _trials(text: str | None) -> slice | None:
    if text is None:
        return None
    a, sep, b = text.partition(":")
    ok = sep and all(not part or part.strip().isdigit() for part in (a, b))
    if not ok:
        raise ValueError(
            f"--trials: expected A:B (trial indices, either may be left out), got {text!r}"
        )
    return slice(int(a) if a.strip() else None, int(b) if b.strip() else None)


def _finite(obj: Any) -> Any:
    """``obj`` with every non-finite float as ``None`` (strict JSON)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    return obj


class _Writer:
    """JSON lines to standard output or appended to a file, each flushed at once."""

    def __init__(self, out: str) -> None:
        self.out = out
        self._fh: IO[str] | None = None
        self.lines = 0

    def write(self, obj: dict[str, Any]) -> None:
        if self._fh is None:
            self._fh = (
                sys.stdout
                if self.out == "-"
                else open(self.out, "a", buffering=1, encoding="utf-8")
            )
        self._fh.write(json.dumps(_finite(obj), allow_nan=False) + "\n")
        self._fh.flush()
        self.lines += 1

    def close(self) -> None:
        if self._fh is not None and self._fh is not sys.stdout:
            self._fh.close()


def _event(item: Any) -> dict[str, Any]:
    d = item.to_dict()
    return d if d.get("type") == "stream_issue" else {"type": "contact", **d}


def _limited(
    batches: Iterable[tuple[np.ndarray, np.ndarray]], max_seconds: float | None
) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Batches up to ``max_seconds`` of stream time after the first record."""
    end = math.inf
    for t, v in batches:
        if max_seconds is not None and t.shape[0] and not math.isfinite(end):
            end = float(t[0]) + max_seconds
        keep = t < end
        if not keep.all():
            if keep.any():
                yield t[keep], v[keep]
            return
        yield t, v


@user_errors
def live_cmd(
    pipeline: Path = typer.Option(
        ..., "--pipeline", help="A saved tactile pipeline (TactilePipeline.save)."
    ),
    input_: str | None = typer.Option(
        None,
        "--input",
        help="- (standard input, the default), a file, udp://HOST:PORT or "
        "serial://DEVICE[?baud=N] (needs pyserial: vibrissa\\[serial]).",
    ),
    fmt: str | None = typer.Option(
        None, "--format", help="csv or jsonl (default: from the first line)."
    ),
    follow: bool = typer.Option(
        False, "--follow", help="Keep reading a file as it grows (until --idle-timeout-s)."
    ),
    idle_timeout_s: float | None = typer.Option(
        None,
        "--idle-timeout-s",
        help="End after this many seconds without data (--follow, udp, serial; default never).",
    ),
    rate_hz: float | None = typer.Option(
        None,
        "--rate-hz",
        help="The stream's sample rate; must be the pipeline's (the default).",
    ),
    out: str = typer.Option(
        "-", "--out", help="JSON lines to this file (appended, flushed per line) or - (stdout)."
    ),
    replay: Path | None = typer.Option(
        None,
        "--replay",
        help="Play a Dataset file as one whisker's stream, trial after trial, instead of --input.",
    ),
    speed: float | None = typer.Option(
        None, "--speed", help="With --replay: multiple of real time (default 1; 0: at once)."
    ),
    trials: str | None = typer.Option(
        None, "--trials", help="With --replay: the trials A:B to play (default all)."
    ),
    max_seconds: float | None = typer.Option(
        None, "--max-seconds", help="Stop after this many seconds of stream time."
    ),
) -> None:
    """Run a live sensor stream through a saved tactile pipeline; JSON lines out.

    Each record is a time (s) and n_whiskers x n_channels values: CSV lines
    (t,w0c0,w0c1,...; header optional) or JSON lines ({"t": ..., "x": [[...]]}).

    Faults (gaps, time going backwards, NaN samples, a whisker dropping out, a
    wrong or changing rate, malformed lines) are reported once each and
    skipped; the stream is resampled to the pipeline's rate from its
    timestamps.

    Output: one JSON object a line: each contact, each kind of stream issue
    the first time, then a summary.
    """
    from vibrissa.framework import TactilePipeline
    from vibrissa.framework.sources import open_source, replay_dataset
    from vibrissa.framework.stream import IssueLog, StreamGuard

    # -- every option, before any work ------------------------------------------------
    idle = _number("--idle-timeout-s", idle_timeout_s)
    rate = _number("--rate-hz", rate_hz)
    limit = _number("--max-seconds", max_seconds)
    play_speed = _number("--speed", speed, zero=True)
    if fmt is not None and fmt not in _FORMATS:
        raise ValueError(f"--format: expected csv or jsonl, got {fmt!r}")
    if replay is None:
        for name, given in (("--speed", speed is not None), ("--trials", trials is not None)):
            if given:
                raise ValueError(f"{name}: only with --replay")
    else:
        for name, given in (
            ("--input", input_ is not None),
            ("--follow", follow),
            ("--format", fmt is not None),
            ("--idle-timeout-s", idle_timeout_s is not None),
        ):
            if given:
                raise ValueError(f"{name}: not with --replay (a dataset is played instead)")
    selection = _trials(trials)
    regular_file("--pipeline", pipeline)
    try:
        pipe = TactilePipeline.load(pipeline)
    except (ValueError, TypeError, OSError) as exc:
        raise _option("--pipeline", exc) from None
    if rate is not None and not math.isclose(rate, pipe.sample_rate_hz, rel_tol=1e-9):
        raise ValueError(
            f"--rate-hz: the stream's {rate:g} Hz is not the pipeline's "
            f"{pipe.sample_rate_hz:g} Hz; use a pipeline built for {rate:g} Hz"
        )
    if out != "-":
        try:
            check_writable(out)
        except ValueError as exc:
            raise _option("--out", exc) from None
    log = IssueLog()
    source: Any
    if replay is not None:
        regular_file("--replay", replay)
        try:
            source = replay_dataset(
                replay, 1.0 if play_speed is None else play_speed, trials=selection
            )
        except (ValueError, TypeError, OSError, KeyError) as exc:
            raise _option("--trials" if "trials" in str(exc) else "--replay", exc) from None
        if pipe.n_whiskers != 1 or source.n_channels != pipe.n_channels:
            raise ValueError(
                f"--replay: a dataset plays as 1 whisker x {source.n_channels} channels; the "
                f"pipeline takes {pipe.n_whiskers} whiskers x {pipe.n_channels} channels"
            )
        if not math.isclose(source.sample_rate_hz, pipe.sample_rate_hz, rel_tol=1e-9):
            raise ValueError(
                f"--replay: the dataset is at {source.sample_rate_hz:g} Hz, the pipeline at "
                f"{pipe.sample_rate_hz:g} Hz"
            )
        what = (
            f"{replay} (trials {', '.join(map(str, source.trials[:3]))}"
            f"{', ...' if len(source.trials) > 3 else ''}; {source.duration_s:g} s at "
            f"{'full speed' if source.speed == 0 else f'{source.speed:g}x real time'})"
        )
    else:
        spec = "-" if input_ is None else input_
        try:
            source = open_source(
                spec,
                pipe.n_whiskers,
                pipe.n_channels,
                fmt,
                follow=follow,
                idle_timeout_s=idle,
                log=log,
            )
        except (ValueError, TypeError, OSError) as exc:
            raise _option("--input", exc) from None
        what = "standard input" if spec == "-" else spec
    # -- the work ------------------------------------------------------------------------
    guard = StreamGuard(pipe, log=log)
    writer = _Writer(out)
    print(
        f"live: reading {what} at {pipe.sample_rate_hz:g} Hz, {pipe.n_whiskers} whiskers x "
        f"{pipe.n_channels} channels -> {'standard output' if out == '-' else out}",
        file=sys.stderr,
    )

    def kept() -> str:
        where = "standard output" if out == "-" else out
        return (
            f"{guard.records} records read, {guard.contacts} contacts and the summary "
            f"written to {where}"
        )

    with interruptible(kept):
        try:
            for t, v in _limited(source, limit):
                with uninterrupted():  # a batch is counted, processed and logged whole
                    for item in guard.push(t, v):
                        writer.write(_event(item))
        finally:
            try:
                for item in guard.flush():
                    writer.write(_event(item))
                writer.write(
                    {
                        "type": "summary",
                        "samples": guard.samples,
                        "seconds": guard.seconds,
                        "contacts": guard.contacts,
                        "decisions": guard.decisions,
                        "issues": guard.issue_counts,
                    }
                )
            finally:
                writer.close()
                close = getattr(source, "close", None)
                if callable(close):
                    close()
