"""A guard between raw timestamped samples and the tactile pipeline: clean, regular chunks.

A live sensor stream is a sequence of records ``(t_s, values)``, ``values`` of shape
``(n_whiskers, n_channels)``, at a rate the user states (the pipeline's,
``pipeline.sample_rate_hz``). :class:`StreamGuard` hands the pipeline
(:class:`vibrissa.framework.TactilePipeline`, or anything with its ``feed``,
``flush``, ``break_stream`` and ``sample_rate_hz``, ``n_whiskers``, ``n_channels``)
samples on a regular grid at that rate, and survives hostile input. Each problem is
a :class:`StreamIssue` reported the first time its kind appears; later occurrences
are counted (:attr:`StreamGuard.issue_counts`), not repeated, and the stream goes on
so that no later contact is lost:

``time_backwards``, ``time_repeated``, ``bad_time``
    A record whose time is before, equal to, or not after the latest time seen, or
    not finite: dropped.
``nan_samples``
    A record whose every whisker has a NaN or infinite value: dropped, so that it
    leaves a gap (below).
``gap``
    More than ``gap_periods`` (1.5) sample spacings between two records: the
    pipeline's stream is broken (``break_stream()``: contacts in progress are
    dropped) and a new regular grid starts at the next record. No sample is made up
    across a gap.
``whisker_dropout``
    A record in which some (not all) whiskers have a NaN or infinite value: each such
    whisker is broken (``break_stream([w])``) when it drops out and again when it
    returns; in between its values are held at its last good value (0 before it has
    ever had one) and nothing it does is reported. At the end of the stream the
    whiskers still out are broken before the pipeline flushes, so a held value is
    never reported as a contact.
``wrong_rate``, ``rate_change``
    The stream's spacing, the median of the last ``rate_window`` (16) intervals, is
    off the stated rate by more than ``rate_tolerance`` (10 %) (``wrong_rate``), or
    has moved by more than that from the spacing measured before (``rate_change``).

**Time is never mislabelled: every sample is resampled from the timestamps.** The
pipeline sample ``k`` of a grid that starts at record time ``t0`` is the stream's
value at ``t0 + k / rate``, linearly interpolated between the two records around it
(taken as it is when a record lies on the grid point, to 1e-6 of a spacing or the
timestamps' own precision). A stream at the stated rate passes through unchanged; a
stream at a wrong or changing rate is reported and resampled, so the pipeline's
samples are always at their true times (a source slower than the stated rate then
carries no content above its own Nyquist frequency; a faster one is decimated
without an anti-alias filter). The choice to resample rather than refuse is what lets
a contact after a rate fault still be reported; the report tells the user the rate is
not what they stated. The gap threshold follows the measured spacing
(``gap_periods`` times the larger of the stated and the measured spacing), so a slow
stream is not one gap per record once its rate is known (until then, for the first
few intervals, it is).

The pipeline's contact times count samples from its first; the guard maps them back
to stream time (``onset_s``, ``end_s`` of every :class:`ContactReport` it returns are
times of the stream's own clock), across gaps too. Everything is vectorised over a
batch of records: Python loops run once per gap, drop-out, return and rate change,
never per record.
"""

from __future__ import annotations

import bisect
import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from vibrissa._validate import in_range, positive

__all__ = ["ISSUE_KINDS", "IssueLog", "StreamGuard", "StreamIssue"]

#: Every kind of :class:`StreamIssue` the guard and the sources report.
ISSUE_KINDS = (
    "bad_line",
    "bad_time",
    "time_backwards",
    "time_repeated",
    "nan_samples",
    "gap",
    "whisker_dropout",
    "wrong_rate",
    "rate_change",
)

#: Fewest intervals whose median is taken as the stream's spacing.
_MIN_INTERVALS = 5
#: Interpolation weights this close to 0 or 1 take the record as it is.
_SNAP = 1e-6


@dataclass(frozen=True)
class StreamIssue:
    """One problem of a live stream, reported the first time its kind appears.

    Attributes
    ----------
    kind : str
        One of :data:`ISSUE_KINDS`.
    at_s : float
        Stream time at which it appeared (``nan`` when no time is known yet, e.g. a
        malformed first line).
    message : str
        One line saying what was wrong and what was done about it.
    """

    kind: str
    at_s: float
    message: str

    def to_dict(self) -> dict[str, Any]:
        """The issue as a JSON-ready line: ``{"type": "stream_issue", "kind", "at_s", "message"}``.

        ``at_s`` is ``None`` when not finite.
        """
        at = float(self.at_s)
        return {
            "type": "stream_issue",
            "kind": self.kind,
            "at_s": at if math.isfinite(at) else None,
            "message": self.message,
        }


class IssueLog:
    """Stream issues reported once per kind and counted every time.

    A source (:mod:`vibrissa.framework.sources`) and a :class:`StreamGuard` may share
    one log, so that a malformed line and a time fault appear in one place.
    """

    def __init__(self) -> None:
        self.counts: dict[str, int] = {}
        self.first: dict[str, StreamIssue] = {}
        self._new: list[StreamIssue] = []

    def report(self, kind: str, at_s: float, message: str, count: int = 1) -> None:
        """Count ``count`` occurrences of ``kind``; keep the issue if the kind is new.

        Parameters
        ----------
        kind : str
            One of :data:`ISSUE_KINDS`.
        at_s : float
            Stream time of the first of these occurrences.
        message : str
            What was wrong and what was done (used only the first time).
        count : int, default=1
            Occurrences (e.g. records dropped).
        """
        if kind not in ISSUE_KINDS:
            raise ValueError(f"kind must be one of {', '.join(ISSUE_KINDS)}, got {kind!r}")
        if count <= 0:
            return
        if kind not in self.counts:
            issue = StreamIssue(kind, float(at_s), message)
            self.first[kind] = issue
            self._new.append(issue)
        self.counts[kind] = self.counts.get(kind, 0) + int(count)

    def drain(self) -> list[StreamIssue]:
        """The issues first reported since the last call, in order of reporting."""
        out, self._new = self._new, []
        return out


def _median_rows(a: np.ndarray) -> np.ndarray:
    """Median of each row (cheaper than ``np.median`` for many short rows)."""
    s = np.sort(a, axis=1)
    n = a.shape[1]
    return 0.5 * (s[:, (n - 1) // 2] + s[:, n // 2])


def _fmt_hz(spacing_s: float) -> str:
    return f"{1.0 / spacing_s:.4g} Hz ({spacing_s * 1e3:.4g} ms)"


class StreamGuard:
    """Regular, clean chunks for the pipeline out of a hostile timestamped stream.

    Parameters
    ----------
    pipeline : TactilePipeline
        Anything with ``feed(samples) -> list``, ``flush() -> list``,
        ``break_stream(whiskers=None)`` and the attributes ``sample_rate_hz`` (the
        stream's stated rate), ``n_whiskers``, ``n_channels``.
    gap_periods : float, default=1.5
        An interval longer than this many spacings is a gap (``> 1``).
    rate_tolerance : float, default=0.1
        Relative departure of the measured spacing that is reported (in (0, 1)).
    rate_window : int, default=16
        Intervals whose median is the measured spacing (at least 5).
    log : IssueLog, optional
        Where issues go (shared with a source); a new one by default.

    Notes
    -----
    :meth:`push` and :meth:`flush` return the issues first reported since the last
    call (sources' issues too, when the log is shared), then the pipeline's contact
    reports with their times on the stream's clock. See the module docstring for what
    is done with each fault.
    """

    def __init__(
        self,
        pipeline: Any,
        *,
        gap_periods: float = 1.5,
        rate_tolerance: float = 0.1,
        rate_window: int = 16,
        log: IssueLog | None = None,
    ) -> None:
        for attr in ("feed", "flush", "break_stream"):
            if not callable(getattr(pipeline, attr, None)):
                raise TypeError(f"pipeline must have a {attr}() method, got {type(pipeline)}")
        self.pipeline = pipeline
        self.sample_rate_hz = positive("pipeline.sample_rate_hz", pipeline.sample_rate_hz)
        self.n_whiskers = int(pipeline.n_whiskers)
        self.n_channels = int(pipeline.n_channels)
        self.gap_periods = positive("gap_periods", gap_periods)
        if self.gap_periods <= 1:
            raise ValueError(f"gap_periods must exceed 1, got {gap_periods!r}")
        self.rate_tolerance = in_range("rate_tolerance", rate_tolerance, 1e-6, 0.999)
        if isinstance(rate_window, bool) or not isinstance(rate_window, int | np.integer):
            raise TypeError(f"rate_window must be an int, got {rate_window!r}")
        if rate_window < _MIN_INTERVALS:
            raise ValueError(f"rate_window must be at least {_MIN_INTERVALS}, got {rate_window}")
        self.rate_window = int(rate_window)
        self.log = IssueLog() if log is None else log
        self.period_s = 1.0 / self.sample_rate_hz
        self.spacing_s = self.period_s  # the stream's spacing as measured (stated until then)
        self._measured = False
        self._holdoff = 0  # intervals to come before the spacing may change again
        self._pending: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # before the first
        self._intervals = np.empty(0)  # the last rate_window - 1 intervals
        self._max_t = -math.inf  # latest time seen (records dropped for NaN included)
        self._last_t: float | None = None  # last record kept in the current grid
        self._last_v = np.zeros((self.n_whiskers, self.n_channels))
        self._held = np.zeros((self.n_whiskers, self.n_channels))  # last good value
        self._out = np.zeros(self.n_whiskers, dtype=bool)  # whiskers dropped out
        self._seg_t0 = math.nan  # stream time of the current grid's sample 0
        self._seg_k = 0  # next grid sample to produce
        self._seg_starts: list[int] = []  # pipeline sample index of each grid's sample 0
        self._seg_times: list[float] = []  # and its stream time
        self.samples = 0  # samples fed to the pipeline
        self.records = 0  # records pushed
        self.contacts = 0
        self.decisions = 0

    # -- public --------------------------------------------------------------------------
    @property
    def issue_counts(self) -> dict[str, int]:
        """Occurrences of each issue kind so far (shared log included)."""
        return dict(self.log.counts)

    @property
    def seconds(self) -> float:
        """Seconds of stream fed to the pipeline (samples over the rate; gaps not counted)."""
        return self.samples / self.sample_rate_hz

    def push(self, t_s: Any, values: Any) -> list[Any]:
        """Check a batch of records and feed the pipeline the clean, regular samples.

        Parameters
        ----------
        t_s : array-like of shape (n,)
            Record times, seconds on the stream's clock.
        values : array-like of shape (n, n_whiskers, n_channels)
            NaN or infinite where missing.

        Returns
        -------
        list of StreamIssue and ContactReport
            Issues first reported by this batch, then contacts the pipeline reported,
            their times on the stream's clock.
        """
        t, v = self._check(t_s, values)
        self.records += t.shape[0]
        reports: list[Any] = []
        if t.shape[0]:
            t, v = self._order(t, v)
            t, v, good = self._missing(t, v)
            if self._last_t is None:  # the first records wait until the rate is measured
                self._pending.append((t, v, good))
                if sum(p[0].shape[0] for p in self._pending) <= _MIN_INTERVALS:
                    return self.log.drain()
                t, v, good = self._take_pending()
            if t.shape[0]:
                reports = self._advance(t, v, good)
        return [*self.log.drain(), *reports]

    def _take_pending(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        parts, self._pending = self._pending, []
        t, v, good = (np.concatenate([p[i] for p in parts]) for i in range(3))
        return t, v, good

    def flush(self) -> list[Any]:
        """End the stream: whiskers still out are broken, then the pipeline flushes.

        Returns
        -------
        list of StreamIssue and ContactReport
            As :meth:`push`.
        """
        reports: list[Any] = []
        if self._pending:
            t, v, good = self._take_pending()
            if t.shape[0]:
                reports = self._advance(t, v, good)
        if self._out.any():
            self.pipeline.break_stream([int(w) for w in np.flatnonzero(self._out)])
        reports += self._timed(self.pipeline.flush())
        return [*self.log.drain(), *reports]

    # -- checks --------------------------------------------------------------------------
    def _check(self, t_s: Any, values: Any) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(t_s, dtype=float)
        if t.ndim != 1:
            raise ValueError(f"t_s must be 1-D (one time per record), got shape {t.shape}")
        v = np.asarray(values, dtype=float)
        want = (t.shape[0], self.n_whiskers, self.n_channels)
        if v.shape != want:
            raise ValueError(
                f"values must have shape {want} (record, whisker, channel), got {v.shape}"
            )
        return t, v

    def _order(self, t: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Drop records whose time is not finite or not after every earlier one."""
        finite = np.isfinite(t)
        if not finite.all():
            k = int(np.count_nonzero(~finite))
            at = self._max_t if math.isfinite(self._max_t) else math.nan
            self.log.report("bad_time", at, f"{k} record(s) without a finite time: dropped", k)
            t, v = t[finite], v[finite]
        if not t.shape[0]:
            return t, v
        before = np.maximum.accumulate(np.concatenate([[self._max_t], t]))[:-1]
        back = t < before
        same = t == before
        for kind, mask, what in (
            ("time_backwards", back, "before"),
            ("time_repeated", same, "equal to"),
        ):
            if mask.any():
                i = int(np.flatnonzero(mask)[0])
                self.log.report(
                    kind,
                    float(t[i]),
                    f"record at t = {t[i]:.6g} s is {what} the latest time "
                    f"{before[i]:.6g} s: records out of order are dropped",
                    int(np.count_nonzero(mask)),
                )
        keep = ~(back | same)
        self._max_t = max(self._max_t, float(t.max()))
        return t[keep], v[keep]

    def _missing(self, t: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Drop records with no whisker at all; hold the values of whiskers out."""
        good = np.isfinite(v).all(axis=2)  # (n, W)
        none = ~good.any(axis=1)
        if none.any():
            i = int(np.flatnonzero(none)[0])
            self.log.report(
                "nan_samples",
                float(t[i]),
                f"record at t = {t[i]:.6g} s has NaN or infinite values on every whisker: "
                "treated as missing (a gap)",
                int(np.count_nonzero(none)),
            )
            t, v, good = t[~none], v[~none], good[~none]
        if t.shape[0] and not good.all():
            # forward fill of each whisker's last good value (the held one before the batch)
            n = t.shape[0]
            idx = np.where(good, np.arange(n)[:, None], -1)
            last = np.maximum.accumulate(idx, axis=0)  # (n, W): last good record, -1 none
            prev = np.concatenate([self._held[None], v], axis=0)  # row 0: held before
            v = prev[last + 1, np.arange(self.n_whiskers)[None, :]]
        return t, v, good

    # -- rate and gaps -------------------------------------------------------------------
    def _medians(self, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Medians at each new interval of the last ``rate_window`` and of its later half.

        ``nan`` where fewer than five intervals are known.
        """
        h = self._intervals.size
        hist = np.concatenate([self._intervals, dt])
        med = np.full(dt.size, np.nan)
        recent = np.full(dt.size, np.nan)
        n_win, half = self.rate_window, self.rate_window // 2
        ends = h + np.arange(dt.size) + 1  # intervals known at each new one
        full = ends >= n_win
        if full.any():
            win = sliding_window_view(hist, n_win)[ends[full] - n_win]
            med[full] = _median_rows(win)
            recent[full] = _median_rows(win[:, -half:])
        for i in np.flatnonzero(~full & (ends >= _MIN_INTERVALS)):  # the stream's start only
            med[i] = np.median(hist[: ends[i]])
            recent[i] = np.median(hist[max(0, ends[i] - half) : ends[i]])
        return med, recent

    def _rate_change(self, med: np.ndarray) -> int:
        """Index of the first interval whose median moves the spacing (-1: none)."""
        ok = ~np.isnan(med)
        off = np.zeros(med.shape, dtype=bool)
        off[ok] = np.abs(med[ok] / self.spacing_s - 1.0) > self.rate_tolerance
        off[: self._holdoff] = False  # the window still holds intervals from before a change
        if not self._measured and ok.any():
            first = int(np.flatnonzero(ok)[0])
            if not off[first]:
                self._measured = True
                off[:first] = False
        hits = np.flatnonzero(off)
        return int(hits[0]) if hits.size else -1

    def _set_spacing(self, spacing_s: float, at_s: float) -> None:
        before, was_measured = self.spacing_s, self._measured
        self.spacing_s, self._measured = float(spacing_s), True
        self._holdoff = self.rate_window
        off = abs(self.spacing_s / self.period_s - 1.0) > self.rate_tolerance
        if was_measured:
            self.log.report(
                "rate_change",
                at_s,
                f"the stream's rate changed from {_fmt_hz(before)} to {_fmt_hz(self.spacing_s)} "
                f"at t = {at_s:.6g} s; samples are resampled to {self.sample_rate_hz:g} Hz "
                "from their timestamps",
            )
        if off:
            self.log.report(
                "wrong_rate",
                at_s,
                f"the stream's rate is {_fmt_hz(self.spacing_s)}, not the stated "
                f"{self.sample_rate_hz:g} Hz; samples are resampled to {self.sample_rate_hz:g} Hz "
                "from their timestamps",
            )

    # -- feeding -------------------------------------------------------------------------
    def _advance(self, t: np.ndarray, v: np.ndarray, good: np.ndarray) -> list[Any]:
        """Feed records ``t, v`` (in order, finite, held) to the pipeline; return reports."""
        reports: list[Any] = []
        start = 0
        while start < t.shape[0]:
            stop = t.shape[0]
            tt = t[start:]
            prev_t = self._last_t
            dt = np.diff(tt) if prev_t is None else np.diff(np.concatenate([[prev_t], tt]))
            first = 1 if prev_t is None else 0  # record index of dt[0]'s later record
            if dt.size:
                med, recent = self._medians(dt)
                j = self._rate_change(med)
                if j >= 0 and not self._measured:  # the first measurement: from the start
                    self._set_spacing(float(recent[j]), float(t[start + first + j]))
                    continue
                if j >= 0:  # the spacing changes at dt[j]: this pass stops before it
                    stop = start + first + j
                    if stop == start:  # the change is at the batch's first interval
                        self._set_spacing(float(recent[j]), float(t[start]))
                        continue
            reports += self._run(t[start:stop], v[start:stop], good[start:stop])
            if stop < t.shape[0]:
                self._set_spacing(float(recent[j]), float(t[stop]))
            start = stop
        return reports

    def _run(self, t: np.ndarray, v: np.ndarray, good: np.ndarray) -> list[Any]:
        """Feed records at one spacing: a new grid after each gap."""
        prev_t = self._last_t  # None only before the stream's first record
        dt = np.diff(t) if prev_t is None else np.diff(np.concatenate([[prev_t], t]))
        self._intervals = np.concatenate([self._intervals, dt])[-(self.rate_window - 1) :]
        self._holdoff = max(0, self._holdoff - dt.size)
        limit = self.gap_periods * max(self.spacing_s, self.period_s)
        gaps = (np.flatnonzero(dt > limit) + (1 if prev_t is None else 0)).tolist()
        starts = [0, *gaps] if prev_t is None else gaps
        reports: list[Any] = []
        head = starts[0] if starts else t.shape[0]
        reports += self._segment(t[:head], v[:head], good[:head])
        bounds = [*starts, t.shape[0]]
        for a, b in zip(bounds[:-1], bounds[1:], strict=True):
            if prev_t is not None or a > 0:
                span = t[a] - (prev_t if a == 0 else t[a - 1])
                self.log.report(
                    "gap",
                    float(t[a]),
                    f"{span * 1e3:.4g} ms without samples before t = {t[a]:.6g} s "
                    f"(more than {self.gap_periods:g} spacings): contacts in progress are "
                    "dropped and detection restarts",
                )
                self.pipeline.break_stream()
            self._new_grid(float(t[a]))
            reports += self._segment(t[a:b], v[a:b], good[a:b])
        return reports

    def _new_grid(self, t0: float) -> None:
        self._seg_t0, self._seg_k, self._last_t = t0, 0, None
        self._seg_starts.append(self.samples)
        self._seg_times.append(t0)

    def _segment(self, t: np.ndarray, v: np.ndarray, good: np.ndarray) -> list[Any]:
        """Records without a gap, continuing the current grid: resample and feed."""
        if not t.shape[0]:
            return []
        if self._last_t is None:  # a new grid: its sample 0 is this first record
            tr, vr = t, v
        else:
            tr = np.concatenate([[self._last_t], t])
            vr = np.concatenate([self._last_v[None], v])
        fs = self.sample_rate_hz
        k_last = math.floor((tr[-1] - self._seg_t0) * fs + _SNAP + self._tol(tr[-1]) * fs)
        ks = np.arange(self._seg_k, k_last + 1)
        grid = self._seg_t0 + ks / fs
        samples = self._interpolate(tr, vr, grid)
        events: dict[int, set[int]] = {}
        if good.all() and not self._out.any():
            self._held = v[-1].copy()
        else:
            events = self._whisker_events(t, v, good, grid)
        reports: list[Any] = []
        cut = 0
        for at in sorted(events):
            reports += self._feed(samples[cut:at])
            self.pipeline.break_stream(sorted(events[at]))
            cut = at
        reports += self._feed(samples[cut:])
        self._seg_k = int(k_last) + 1
        self._last_t, self._last_v = float(tr[-1]), vr[-1].copy()
        return reports

    def _whisker_events(
        self, t: np.ndarray, v: np.ndarray, good: np.ndarray, grid: np.ndarray
    ) -> dict[int, set[int]]:
        """Grid positions at which whiskers are broken -> those whiskers; held values kept.

        A whisker dropping out at record ``i`` is broken before the first grid time at
        or after ``t[i]``; one returning at ``i`` after the last grid time at or before
        ``t[i - 1]`` (the samples between ramp from its held value to its new one).
        """
        out = ~good
        prev = np.concatenate([self._out[None], out[:-1]])
        events: dict[int, set[int]] = {}
        for i, w in zip(*np.nonzero(out & ~prev), strict=True):
            at = int(np.searchsorted(grid, t[i] - self._tol(t[i]), side="left"))
            self.log.report(
                "whisker_dropout",
                float(t[i]),
                f"whisker {w} has NaN or infinite values from t = {t[i]:.6g} s: its "
                "contacts in progress are dropped and its values held until it returns",
            )
            events.setdefault(at, set()).add(int(w))
        for i, w in zip(*np.nonzero(~out & prev), strict=True):
            before = t[i - 1] if i > 0 else self._last_t
            at = (
                0
                if before is None
                else int(np.searchsorted(grid, before + self._tol(before), side="right"))
            )
            events.setdefault(at, set()).add(int(w))
        self._out = out[-1].copy()
        li = np.where(good, np.arange(good.shape[0])[:, None], -1).max(axis=0)
        has = li >= 0
        self._held[has] = v[li[has], np.flatnonzero(has)]
        return events

    @staticmethod
    def _tol(t: float) -> float:
        return 4.0 * float(np.spacing(abs(t)))

    def _interpolate(self, tr: np.ndarray, vr: np.ndarray, grid: np.ndarray) -> np.ndarray:
        """Values at the grid times by linear interpolation between records (exact on them)."""
        if not grid.size:
            return np.empty((0, self.n_whiskers, self.n_channels))
        if tr.size == 1:
            return np.repeat(vr[:1], grid.size, axis=0)
        j = np.clip(np.searchsorted(tr, grid, side="right") - 1, 0, tr.size - 2)
        span = tr[j + 1] - tr[j]
        w = (grid - tr[j]) / span
        tol = _SNAP + 4.0 * np.spacing(np.abs(grid)) / span
        w = np.where(w < tol, 0.0, np.where(w > 1.0 - tol, 1.0, np.clip(w, 0.0, 1.0)))
        a, b = vr[j], vr[j + 1]
        wb = w[:, None, None]
        return np.where(wb == 0.0, a, np.where(wb == 1.0, b, a + wb * (b - a)))

    def _feed(self, samples: np.ndarray) -> list[Any]:
        if not samples.shape[0]:
            return []
        self.samples += samples.shape[0]
        return self._timed(self.pipeline.feed(samples))

    def _timed(self, reports: Sequence[Any]) -> list[Any]:
        """Reports with ``onset_s`` and ``end_s`` on the stream's clock."""
        out = []
        fs = self.sample_rate_hz
        origin = float(getattr(self.pipeline, "start_time_s", 0.0))  # its sample 0's time
        for r in reports:
            self.contacts += 1
            if getattr(r, "decision", None) is not None:
                self.decisions += 1
            if not hasattr(r, "onset_s") or not self._seg_starts:
                out.append(r)
                continue
            onset_i = round((float(r.onset_s) - origin) * fs)
            g = max(0, bisect.bisect_right(self._seg_starts, onset_i) - 1)
            i0, t0 = self._seg_starts[g], self._seg_times[g]
            end_i = round((float(r.end_s) - origin) * fs)
            out.append(
                dataclasses.replace(
                    r, onset_s=t0 + (onset_i - i0) / fs, end_s=t0 + (end_i - i0) / fs
                )
            )
        return out
