"""Streaming contact detection on multi-whisker sensor streams (thesis 2.5, figure 2.17).

Samples arrive in chunks of any size ``n >= 0`` as arrays ``(n, n_whiskers,
n_channels)`` (time first). For each whisker the *departure* of a sample is the
Euclidean norm, over the detecting channels, of ``sample - rest``. A contact starts
at the first sample whose departure exceeds ``threshold`` (the thesis author's onset
rule, :func:`vibrissa.signal.onset_index`, 0.1 V above rest) and ends at the first
sample of a run of ``hold_s`` during which the departure stays below ``release``.
Contacts shorter than ``min_duration_s`` are dropped as noise. Each contact carries
a fixed-length window of all channels of its whisker, from ``pre_s`` before onset,
``window_s`` long: the input of the classifiers (:mod:`vibrissa.framework.models`).

The detector is a state machine per whisker run on whole chunks with numpy (one
Python step per threshold crossing, never per sample), so its output does not depend
on how the stream is cut into chunks: :func:`contact_windows` (push everything, then
flush) gives the windows of a training set exactly as the live pipeline sees them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vibrissa._validate import finite, non_negative, positive

__all__ = ["ContactDetector", "DetectedContact", "DetectorSettings", "contact_windows"]


@dataclass(frozen=True)
class DetectorSettings:
    """Settings of :class:`ContactDetector` (times in seconds, departures in signal units).

    Attributes
    ----------
    threshold : float, default=0.1
        Departure from rest that starts a contact (V): the thesis author's onset
        threshold (:func:`vibrissa.signal.onset_index`).
    release : float or None, default=None
        Departure below which a contact may end (``None``: ``threshold / 2``); at most
        ``threshold``.
    hold_s : float, default=0.02
        The departure must stay below ``release`` this long to end the contact; the
        contact's end is the first sample of that quiet run.
    min_duration_s : float, default=0.005
        Contacts shorter than this are dropped (noise spikes).
    pre_s : float, default=0.05
        The classifier window starts this long before onset.
    window_s : float, default=0.5
        Length of the classifier window (fixed: the classifiers' input).
    rest : tuple of float or None, default=None
        Rest level of each channel (the same for every whisker); ``None``: estimated
        per whisker and channel as the median of the first ``rest_s`` of the stream.
    rest_s : float, default=0.05
        Length of the stream's start whose median is the rest level.
    channels : tuple of int or None, default=None
        Channels whose departure detects contacts (``None``: all).
    """

    threshold: float = 0.1
    release: float | None = None
    hold_s: float = 0.02
    min_duration_s: float = 0.005
    pre_s: float = 0.05
    window_s: float = 0.5
    rest: tuple[float, ...] | None = None
    rest_s: float = 0.05
    channels: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        """Check every setting, naming the one that is wrong."""
        positive("threshold", self.threshold)
        if self.release is not None:
            positive("release", self.release)
            if self.release > self.threshold:
                raise ValueError(
                    f"release must not exceed threshold ({self.threshold!r}), got {self.release!r}"
                )
        positive("hold_s", self.hold_s)
        non_negative("min_duration_s", self.min_duration_s)
        non_negative("pre_s", self.pre_s)
        positive("window_s", self.window_s)
        positive("rest_s", self.rest_s)
        if self.rest is not None:
            if not isinstance(self.rest, tuple) or not self.rest:
                raise TypeError(f"rest must be a non-empty tuple of numbers, got {self.rest!r}")
            for i, v in enumerate(self.rest):
                finite(f"rest[{i}]", v)
        if self.channels is not None:
            if not isinstance(self.channels, tuple) or not self.channels:
                raise TypeError(
                    f"channels must be a non-empty tuple of ints or None, got {self.channels!r}"
                )
            for c in self.channels:
                if isinstance(c, bool) or not isinstance(c, int | np.integer) or c < 0:
                    raise ValueError(f"channels must hold non-negative ints, got {self.channels!r}")
            if len(set(self.channels)) != len(self.channels):
                raise ValueError(f"channels must not repeat, got {self.channels!r}")

    @property
    def release_level(self) -> float:
        """The release departure in force (``release``, else ``threshold / 2``)."""
        return float(self.threshold) / 2 if self.release is None else float(self.release)

    def to_dict(self) -> dict[str, Any]:
        """The settings as a JSON-ready dict (:meth:`from_dict` inverts it)."""
        return {
            "threshold": float(self.threshold),
            "release": None if self.release is None else float(self.release),
            "hold_s": float(self.hold_s),
            "min_duration_s": float(self.min_duration_s),
            "pre_s": float(self.pre_s),
            "window_s": float(self.window_s),
            "rest": None if self.rest is None else [float(v) for v in self.rest],
            "rest_s": float(self.rest_s),
            "channels": None if self.channels is None else [int(c) for c in self.channels],
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> DetectorSettings:
        """Settings from :meth:`to_dict`'s output.

        Parameters
        ----------
        d : dict

        Returns
        -------
        DetectorSettings
        """
        d = dict(d)
        for key in ("rest", "channels"):
            if d.get(key) is not None:
                d[key] = tuple(d[key])
        return cls(**d)


@dataclass(frozen=True)
class DetectedContact:
    """One contact of one whisker, with its classifier window.

    Attributes
    ----------
    whisker : int
    onset_index : int
        Stream sample index (from the first sample ever fed) of the onset.
    end_index : int
        First sample of the quiet run that ended the contact.
    peak_departure : float
        Largest departure from rest during the contact (signal units).
    window : ndarray of shape (n_channels, n_window)
        Samples ``[onset - pre, onset - pre + n_window)`` of every channel of the
        whisker; samples before the stream start (or before a
        :meth:`ContactDetector.break_stream`) are the rest level.
    truncated : bool
        The window was incomplete when the stream ended (or broke): padded with the
        last sample.
    """

    whisker: int
    onset_index: int
    end_index: int
    peak_departure: float
    window: np.ndarray = field(repr=False, compare=False)
    truncated: bool = False

    def same_as(self, other: DetectedContact) -> bool:
        """Whether two contacts are equal, windows compared element by element."""
        return (
            (self.whisker, self.onset_index, self.end_index, self.truncated)
            == (other.whisker, other.onset_index, other.end_index, other.truncated)
            and self.peak_departure == other.peak_departure
            and np.array_equal(self.window, other.window)
        )


class _Contact:
    """A contact being tracked (mutable, internal)."""

    __slots__ = ("whisker", "onset", "end", "confirm", "peak", "last_loud", "window")

    def __init__(self, whisker: int, onset: int, peak: float) -> None:
        self.whisker = whisker
        self.onset = onset
        self.end: int | None = None
        self.confirm: int | None = None
        self.peak = peak
        self.last_loud = onset
        self.window: np.ndarray | None = None


def _samples(seconds: float, rate: float) -> int:
    return int(round(seconds * rate))


class ContactDetector:
    """Detect whisker contacts in a stream fed in chunks of any size.

    Parameters
    ----------
    n_whiskers, n_channels : int
        Shape of one sample.
    sample_rate_hz : float
        Sampling rate of the stream, Hz.
    settings : DetectorSettings, optional

    Notes
    -----
    Until the rest level is known (the first ``rest_s`` of the stream, when
    ``settings.rest`` is ``None``) samples are buffered and nothing is detected; the
    contacts are then found from the first sample on. The rest levels are kept for
    the life of the detector. Output order: by the sample index at which a contact
    could first be emitted (ended and window complete), then by whisker.
    """

    def __init__(
        self,
        n_whiskers: int,
        n_channels: int,
        sample_rate_hz: float,
        settings: DetectorSettings | None = None,
    ) -> None:
        for name, v in (("n_whiskers", n_whiskers), ("n_channels", n_channels)):
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
                raise ValueError(f"{name} must be a positive integer, got {v!r}")
        self.n_whiskers = int(n_whiskers)
        self.n_channels = int(n_channels)
        self.sample_rate_hz = positive("sample_rate_hz", sample_rate_hz)
        s = DetectorSettings() if settings is None else settings
        if not isinstance(s, DetectorSettings):
            raise TypeError(f"settings must be a DetectorSettings, got {type(s).__name__}")
        self.settings = s
        fs = self.sample_rate_hz
        if s.channels is not None and max(s.channels) >= self.n_channels:
            raise ValueError(
                f"settings.channels {s.channels} name a channel beyond the {self.n_channels} "
                "of the stream"
            )
        if s.rest is not None and len(s.rest) != self.n_channels:
            raise ValueError(
                f"settings.rest has {len(s.rest)} values but the stream has "
                f"{self.n_channels} channels"
            )
        self._det_channels = (
            np.arange(self.n_channels) if s.channels is None else np.asarray(s.channels)
        )
        self.n_window = max(1, _samples(s.window_s, fs))
        self.n_pre = _samples(s.pre_s, fs)
        self.n_hold = max(1, _samples(s.hold_s, fs))
        self.n_min = _samples(s.min_duration_s, fs)
        self.n_rest = max(1, _samples(s.rest_s, fs))
        self._threshold = float(s.threshold)
        self._release = s.release_level
        self._ring_len = self.n_pre + self.n_window
        self._rest: np.ndarray | None = (
            None
            if s.rest is None
            else np.broadcast_to(np.asarray(s.rest, float), (self.n_whiskers, self.n_channels))
        )
        self._pending: list[np.ndarray] = []  # samples fed before the rest level is known
        self._n_pending = 0
        self._reset_stream()

    # -- state ---------------------------------------------------------------------------
    def _reset_stream(self) -> None:
        self.n_seen = 0  # samples fed (pending ones included)
        self._n_done = 0  # samples run through detection
        # sample i (of the last ring_len run through detection) at row i % ring_len
        self._ring = np.zeros((self._ring_len, self.n_whiskers, self.n_channels))
        self._history_start = np.zeros(self.n_whiskers, dtype=np.int64)
        self._search_from = np.zeros(self.n_whiskers, dtype=np.int64)
        self._active: list[_Contact | None] = [None] * self.n_whiskers
        self._waiting: list[_Contact] = []  # ended, window not complete yet
        self._ready: list[tuple[int, _Contact, bool]] = []  # (emit index, contact, truncated)

    @property
    def rest_level(self) -> np.ndarray | None:
        """Rest level per whisker and channel ``(n_whiskers, n_channels)``; ``None`` until known."""
        return None if self._rest is None else np.array(self._rest)

    # -- feeding -------------------------------------------------------------------------
    def _check(self, samples: Any) -> np.ndarray:
        x = np.asarray(samples, dtype=float)
        want = (self.n_whiskers, self.n_channels)
        if x.ndim != 3 or x.shape[1:] != want:
            raise ValueError(
                f"samples must have shape (n, {want[0]}, {want[1]}) (time, whisker, channel), "
                f"got {x.shape}"
            )
        if not np.all(np.isfinite(x)):
            bad = int(x.size - np.count_nonzero(np.isfinite(x)))
            raise ValueError(f"samples contain {bad} NaN or infinite value(s)")
        return x

    def push(self, samples: Any) -> list[DetectedContact]:
        """Feed a chunk of samples; return the contacts complete by its end.

        Parameters
        ----------
        samples : array-like of shape (n, n_whiskers, n_channels)
            Finite; ``n`` may be 0.

        Returns
        -------
        list of DetectedContact
            In order of emission sample index, then whisker.
        """
        x = self._check(samples)
        self.n_seen += x.shape[0]
        if self._rest is None:
            if x.shape[0]:
                self._pending.append(x)
                self._n_pending += x.shape[0]
            if self._n_pending < self.n_rest:
                return self._emit()
            x = self._take_pending()
        self._process(x)
        return self._emit()

    def _take_pending(self) -> np.ndarray:
        x = (
            np.concatenate(self._pending)
            if self._pending
            else np.empty((0, self.n_whiskers, self.n_channels))
        )
        self._pending, self._n_pending = [], 0
        if self._rest is None and x.shape[0]:
            self._rest = np.median(x[: self.n_rest], axis=0)
        return x

    def flush(self) -> list[DetectedContact]:
        """End the stream: emit every contact in progress and every incomplete window.

        Contacts in progress end at the first sample after their last loud one;
        windows not complete are padded with the whisker's last sample
        (``truncated``). Afterwards the detector starts a new stream (rest levels
        kept; sample indices continue).

        Returns
        -------
        list of DetectedContact
            Those emitted before the end in order, then the rest by whisker and onset.
        """
        if self._rest is None:
            x = self._take_pending()
            if self._rest is None:  # nothing was ever fed
                return self._emit()
            self._process(x)
        self._finish(range(self.n_whiskers))
        out = self._emit()
        self._restart(range(self.n_whiskers))
        return out

    def break_stream(self, whiskers: Any = None) -> None:
        """Restart detection of some whiskers as if their stream began at the next sample.

        A contact in progress is dropped; a contact that has ended but whose window is
        incomplete is emitted (truncated) with the next output. Samples before the
        break count as the rest level in later windows. Rest levels, once known, are
        kept.

        Parameters
        ----------
        whiskers : iterable of int or None
            Whiskers to restart (``None``: all).
        """
        ws = self._whiskers(whiskers)
        if self._rest is None:  # detection has not started: only move the history start
            self._history_start[ws] = self.n_seen
            return
        for w in ws:
            self._active[w] = None
        self._finish(ws)
        self._restart(ws)

    def _whiskers(self, whiskers: Any) -> list[int]:
        if whiskers is None:
            return list(range(self.n_whiskers))
        ws = [whiskers] if isinstance(whiskers, int | np.integer) else list(whiskers)
        for w in ws:
            if isinstance(w, bool) or not isinstance(w, int | np.integer):
                raise TypeError(f"whiskers must hold ints, got {w!r}")
            if not 0 <= w < self.n_whiskers:
                raise ValueError(f"whiskers must lie in [0, {self.n_whiskers - 1}], got {w!r}")
        return [int(w) for w in ws]

    def _restart(self, ws: Any) -> None:
        for w in ws:
            self._active[w] = None
            self._history_start[w] = self.n_seen
            self._search_from[w] = self.n_seen

    # -- detection -----------------------------------------------------------------------
    def _departure(self, x: np.ndarray, start: int) -> np.ndarray:
        assert self._rest is not None
        ch = self._det_channels
        # element by element (no reduction whose rounding could depend on the chunk's size)
        dev = x[:, :, ch[0]] - self._rest[None, :, ch[0]]
        if len(ch) == 1:
            d = np.abs(dev)
        else:
            sq = dev * dev
            for c in ch[1:]:
                dev = x[:, :, c] - self._rest[None, :, c]
                sq += dev * dev
            d = np.sqrt(sq)
        idx = start + np.arange(x.shape[0])
        # samples before a whisker's (re)start are not looked at
        return np.where(idx[:, None] >= self._history_start[None, :], d, 0.0)

    def _process(self, x: np.ndarray) -> None:
        """Run detection over ``x`` (samples ``[_n_done, _n_done + len(x))``)."""
        c0 = self._n_done
        c1 = c0 + x.shape[0]
        if x.shape[0]:
            d = self._departure(x, c0)
            above = d > self._threshold
            loud = d >= self._release
            candidates = np.asarray(above.any(axis=0), dtype=bool)
            for w in range(self.n_whiskers):
                if self._active[w] is not None or candidates[w]:
                    self._run_whisker(w, d[:, w], above[:, w], loud[:, w], c0, c1)
        self._fill_windows(x, c0, c1)
        k = min(x.shape[0], self._ring_len)
        if k:
            self._ring[np.arange(c1 - k, c1) % self._ring_len] = x[x.shape[0] - k :]
        self._n_done = c1
        still = []
        for c in self._waiting:
            if c.window is not None:
                assert c.confirm is not None
                self._ready.append((max(c.confirm, self._window_last(c)), c, False))
            else:
                still.append(c)
        self._waiting = still

    def _window_last(self, c: _Contact) -> int:
        return c.onset - self.n_pre + self.n_window - 1

    def _run_whisker(
        self, w: int, d: np.ndarray, above: np.ndarray, loud: np.ndarray, c0: int, c1: int
    ) -> None:
        c = self._active[w]
        if c is not None and loud.all():
            # the common case: in contact throughout the chunk. A contact active at a
            # chunk's start has had fewer than n_hold quiet samples since its last loud
            # one (else the previous chunk would have ended it), so it goes on.
            c.peak = max(c.peak, float(d.max()))
            c.last_loud = c1 - 1
            return
        on_idx = np.flatnonzero(above) + c0
        loud_idx = np.flatnonzero(loud) + c0
        pos = c0
        while True:
            c = self._active[w]
            if c is None:
                start = max(pos, int(self._search_from[w]))
                k = np.searchsorted(on_idx, start)
                if k >= on_idx.size:
                    return
                onset = int(on_idx[k])
                c = _Contact(w, onset, float(d[onset - c0]))
                self._active[w] = c
                pos = onset + 1
            # the contact is active: look for a quiet run of n_hold samples
            later = loud_idx[np.searchsorted(loud_idx, pos) :]
            marks = np.concatenate([[c.last_loud], later])
            gaps = np.diff(marks) - 1
            long = np.flatnonzero(gaps >= self.n_hold)
            if long.size:
                last = int(marks[long[0]])
            elif int(marks[-1]) + self.n_hold <= c1 - 1:
                last = int(marks[-1])
            else:  # still in contact at the chunk's end
                if pos < c1:
                    c.peak = max(c.peak, float(d[pos - c0 :].max()))
                c.last_loud = int(marks[-1])
                return
            end = last + 1
            if pos < end:
                c.peak = max(c.peak, float(d[pos - c0 : end - c0].max()))
            self._end(c, end, last + self.n_hold)
            pos = end

    def _end(self, c: _Contact, end: int, confirm: int) -> None:
        w = c.whisker
        self._active[w] = None
        self._search_from[w] = end
        if end - c.onset < self.n_min:
            return
        c.end, c.confirm = end, confirm
        self._waiting.append(c)

    def _fill_windows(self, x: np.ndarray, c0: int, done: int) -> None:
        """Cut the windows completed by sample ``done - 1`` (chunk ``x`` starts at ``c0``)."""
        tracked = self._waiting + [c for c in self._active if c is not None]
        for c in tracked:
            if c.window is None and self._window_last(c) < done:
                c.window = self._cut(c, x, c0, done)

    def _cut(self, c: _Contact, x: np.ndarray, c0: int, done: int) -> np.ndarray:
        """The window of ``c``: rest before its whisker's history, last sample after ``done``.

        Samples from ``c0`` on are read from the chunk ``x``, earlier ones from the ring
        (which holds the ``pre + window`` samples before ``c0``).
        """
        assert self._rest is not None
        w = c.whisker
        a = c.onset - self.n_pre
        b = a + self.n_window
        hs = int(self._history_start[w])
        win = np.empty((self.n_window, self.n_channels))
        lo, hi = max(a, hs), min(b, done)  # real samples [lo, hi)
        win[: max(0, min(b, hs) - a)] = self._rest[w]  # before the whisker's history
        if lo < hi:
            if lo < c0 - self._ring_len:  # cannot happen: the ring keeps pre + window samples
                raise RuntimeError("contact window left the ring buffer")
            r_hi = min(hi, c0)
            if lo < r_hi:  # from the ring (at most ring_len samples), wrapping at its end
                start = lo % self._ring_len
                n = min(r_hi - lo, self._ring_len - start)
                win[lo - a : lo - a + n] = self._ring[start : start + n, w]
                win[lo - a + n : r_hi - a] = self._ring[: r_hi - lo - n, w]
            x_lo = max(lo, c0)
            if x_lo < hi:
                win[x_lo - a : hi - a] = x[x_lo - c0 : hi - c0, w]
        if done < b:  # after the stream's end: its last sample
            if done - 1 < hs:
                last = self._rest[w]
            elif done - 1 >= c0:
                last = x[done - 1 - c0, w]
            else:
                last = self._ring[(done - 1) % self._ring_len, w]
            win[max(0, done - a) :] = last
        return win.T.copy()

    def _finish(self, ws: Any) -> None:
        """End the contacts of whiskers ``ws`` in progress and cut their incomplete windows."""
        ws = set(ws)
        done = self._n_done
        for w in ws:
            c = self._active[w]
            if c is not None:
                self._end(c, c.last_loud + 1, done)
        keep = []
        for c in self._waiting:
            if c.whisker in ws:
                trunc = c.window is None
                if trunc:
                    c.window = self._cut(c, self._ring[:0], done, done)
                self._ready.append((done, c, trunc))
            else:
                keep.append(c)
        self._waiting = keep

    def _emit(self) -> list[DetectedContact]:
        """Every ready contact (each ended and with its window by the last sample run)."""
        ready = sorted(self._ready, key=lambda r: (r[0], r[1].whisker, r[1].onset))
        self._ready = []
        out = []
        for _, c, trunc in ready:
            assert c.end is not None and c.window is not None
            out.append(
                DetectedContact(
                    whisker=c.whisker,
                    onset_index=c.onset,
                    end_index=c.end,
                    peak_departure=c.peak,
                    window=c.window,
                    truncated=trunc,
                )
            )
        return out


def contact_windows(
    samples: Any, sample_rate_hz: float, settings: DetectorSettings | None = None
) -> list[DetectedContact]:
    """Every contact of a recorded stream (push all samples, then flush).

    Parameters
    ----------
    samples : array-like of shape (n, n_whiskers, n_channels)
    sample_rate_hz : float
    settings : DetectorSettings, optional

    Returns
    -------
    list of DetectedContact
        Exactly what a :class:`ContactDetector` fed the stream in any chunks gives.
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim != 3:
        raise ValueError(
            f"samples must have shape (n, n_whiskers, n_channels) (time first), got {x.shape}"
        )
    det = ContactDetector(x.shape[1], x.shape[2], sample_rate_hz, settings)
    return det.push(x) + det.flush()
