"""Cut the analysed window out of a longer recording, after filtering the whole recording.

A thesis preset (:func:`vibrissa.classify.chapter4_classifiers`) is a
:class:`sklearn.pipeline.Pipeline` whose first step is a :class:`RecordingWindow`:
it filters each whole recording first (as the thesis author's code did, so that a
causal filter has warmed up before the window starts), then cuts either the
author's onset window (750 samples from 100 samples before ``x`` first exceeds
0.1 V above rest) or the text's window about the peak (+/-325 ms, 4.2).

Recordings of other lengths: the window is ``n_samples`` long whatever the length
of the recordings, so recordings longer than the window (of any length, also
another than at ``fit``) are accepted and give the same window; recordings
shorter than the window are refused (a window cannot fit in them).
"""

from __future__ import annotations

import warnings
from typing import Any, Literal

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_array

from vibrissa import signal as vsig
from vibrissa._validate import finite, positive
from vibrissa.classify._base import SampleRateMixin, check_magnitude

__all__ = ["RecordingWindow"]

_ALIGN = ("onset", "peak", "none")
_SIGNALS = ("raw", "velocity", "lowpass")


def trials_3d(X: Any) -> np.ndarray:
    """Validate trials for a transformer step: finite float64 ``(n, channels, time)``.

    A 2-D ``(n_trials, n_timepoints)`` input is one channel. Values beyond
    :data:`~vibrissa.classify._base.MAX_ABS_INPUT` in magnitude are refused.
    """
    arr = X if hasattr(X, "ndim") and hasattr(X, "shape") else np.asarray(X)
    nd = arr.ndim
    if nd not in (2, 3):
        # check_array's own message ("Reshape your data ...") for 1-D input
        check_array(arr, allow_nd=True, ensure_all_finite=True, input_name="X")
        raise ValueError(
            "X must have shape (n_trials, n_channels, n_timepoints) or "
            f"(n_trials, n_timepoints), got {nd}-D input"
        )
    a = check_array(arr, allow_nd=True, dtype=np.float64, ensure_all_finite=True, input_name="X")
    check_magnitude(a)
    return a if a.ndim == 3 else a[:, None, :]


def _int(name: str, value: Any, low: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if low is not None and value < low:
        raise ValueError(f"{name} must be >= {low}, got {value!r}")
    return int(value)


class RecordingWindow(SampleRateMixin, TransformerMixin, BaseEstimator):
    """Filter whole recordings, then cut a fixed-length window aligned to onset or peak.

    Stateless: ``fit`` only validates the parameters and the input, and records the
    number of channels and the sample rate.

    **Recording lengths.** The window is cut from whole recordings, which are
    longer than the window (the chapter-4 datasets keep 1,301 samples per trial at
    1 kHz for windows of 750 or 651 samples):

    - a recording *shorter* than the window (``n_timepoints < n_samples``) is
      refused by ``fit`` and ``transform`` with a ``ValueError`` naming both
      lengths;
    - recordings *longer* than the window give the window of the documented
      alignment, whatever their length, so ``transform`` accepts recordings of
      another length than those seen by ``fit`` (unlike a scikit-learn transformer
      that keeps every input feature; the window's output always has
      ``n_samples`` samples). The number of channels must be the one seen by
      ``fit``;
    - a window that still reaches outside its recording (an onset or peak close to
      either end) repeats the recording's first or last sample, with a
      ``RuntimeWarning`` naming the trials.

    Parameters
    ----------
    align : {"onset", "peak", "none"}, default="onset"
        ``"onset"``: the window starts ``offset_samples`` after the first sample at
        which channel ``reference_channel`` exceeds ``rest_v + onset_threshold_v``
        (a recording that never does is aligned to its peak instead, with a
        warning). ``"peak"``: ``offset_samples`` after the sample of largest
        ``|x - rest_v|``. ``"none"``: ``offset_samples`` after the first sample.
        Alignment is always found on the raw (unfiltered) reference channel.
    offset_samples : int, default=-99
        Start of the window relative to the alignment sample. The author's code
        cut ``x(t + (1:750))`` with ``t = find(x > 0.1, 1) - 100``: the onset is
        the 100th sample of the window, so ``-99``. The text's peak window is
        ``-325`` at 1 kHz.
    n_samples : int, default=750
        Window length (750 in the author's code; 651 for +/-325 ms at 1 kHz).
    channels : tuple of int or None, default=(0,)
        Channels kept (the author's code used ``x`` only); ``None`` keeps all.
    signal : {"raw", "velocity", "lowpass"}, default="raw"
        What is windowed: the raw recording; its velocity by
        :func:`vibrissa.signal.causal_gaussian_velocity` (V/s; first difference and
        a causal ``2 h + 1``-tap Gaussian of ``velocity_sigma_samples``); or a
        causal Butterworth low-pass (:func:`vibrissa.signal.causal_lowpass`).
        Filters run over the whole recording before the window is cut.
    sample_rate_hz : float, default=1000.0
        Sampling rate, Hz (of the filters; ``offset_samples`` and ``n_samples``
        count samples). Data at another rate are refused (see
        :class:`~vibrissa.classify.SampleRateMixin`).
    rest_v : float, default=2.5
        Sensor output at rest, V (onset and peak are found on ``|x - rest_v|``).
    onset_threshold_v : float, default=0.1
        Onset threshold above rest, V.
    reference_channel : int, default=0
        Channel on which onset and peak are found.
    velocity_sigma_samples : float, default=15.0
    velocity_half_width_samples : int, default=50
    lowpass_hz : float, default=20.0
    lowpass_order : int, default=10

    Attributes
    ----------
    n_features_in_ : int
        ``n_channels * n_timepoints`` of the recordings seen by ``fit``.
    n_channels_ : int
        Channels of the recordings seen by ``fit``.
    sample_rate_hz_ : float
        The rate it was fitted at, Hz.
    """

    def __init__(
        self,
        align: Literal["onset", "peak", "none"] = "onset",
        offset_samples: int = -99,
        n_samples: int = 750,
        channels: tuple[int, ...] | None = (0,),
        signal: Literal["raw", "velocity", "lowpass"] = "raw",
        sample_rate_hz: float = 1000.0,
        rest_v: float = 2.5,
        onset_threshold_v: float = 0.1,
        reference_channel: int = 0,
        velocity_sigma_samples: float = 15.0,
        velocity_half_width_samples: int = 50,
        lowpass_hz: float = 20.0,
        lowpass_order: int = 10,
    ) -> None:
        self.align = align
        self.offset_samples = offset_samples
        self.n_samples = n_samples
        self.channels = channels
        self.signal = signal
        self.sample_rate_hz = sample_rate_hz
        self.rest_v = rest_v
        self.onset_threshold_v = onset_threshold_v
        self.reference_channel = reference_channel
        self.velocity_sigma_samples = velocity_sigma_samples
        self.velocity_half_width_samples = velocity_half_width_samples
        self.lowpass_hz = lowpass_hz
        self.lowpass_order = lowpass_order

    def _check_params(self, n_channels: int) -> list[int]:
        if self.align not in _ALIGN:
            raise ValueError(f"align must be one of {_ALIGN}, got {self.align!r}")
        if self.signal not in _SIGNALS:
            raise ValueError(f"signal must be one of {_SIGNALS}, got {self.signal!r}")
        _int("offset_samples", self.offset_samples)
        _int("n_samples", self.n_samples, 1)
        positive("sample_rate_hz", self.sample_rate_hz)
        finite("rest_v", self.rest_v)
        finite("onset_threshold_v", self.onset_threshold_v)
        ref = _int("reference_channel", self.reference_channel, 0)
        if ref >= n_channels:
            raise ValueError(f"reference_channel={ref} but X has {n_channels} channel(s)")
        chans = list(range(n_channels)) if self.channels is None else list(self.channels)
        if not chans:
            raise ValueError("channels must name at least one channel (or be None)")
        for c in chans:
            if _int("channels", c, 0) >= n_channels:
                raise ValueError(f"channel {c} is out of range for X with {n_channels} channel(s)")
        return [int(c) for c in chans]

    def _as3d(self, X: Any) -> np.ndarray:
        """Validated 3-D trials, refused when shorter than the window."""
        X3 = trials_3d(X)
        n = _int("n_samples", self.n_samples, 1)
        if X3.shape[2] < n:
            raise ValueError(
                f"X has recordings of {X3.shape[2]} samples, shorter than the window of "
                f"{n} samples (n_samples); {type(self).__name__} needs recordings at least "
                "as long as its window"
            )
        return X3

    def fit(self, X: Any, y: Any = None, sample_rate_hz: float | None = None) -> RecordingWindow:
        """Validate the parameters against ``X`` (nothing is learned).

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
            Recordings of at least ``n_samples`` samples.
        y : ignored
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not the constructor's.

        Returns
        -------
        self
        """
        rate = self._fit_rate(sample_rate_hz)
        X3 = self._as3d(X)
        self._check_params(X3.shape[1])
        self.n_features_in_ = X3.shape[1] * X3.shape[2]
        self.n_channels_ = X3.shape[1]
        self.sample_rate_hz_ = rate
        self.fitted_ = True
        return self

    def alignment_index(self, X: Any) -> np.ndarray:
        """Sample of each recording the window is aligned to (onset, peak or 0).

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)

        Returns
        -------
        numpy.ndarray of int, shape (n_trials,)
        """
        X3 = self._as3d(X)
        self._check_params(X3.shape[1])
        ref = X3[:, int(self.reference_channel)]
        if self.align == "none":
            return np.zeros(X3.shape[0], dtype=np.int64)
        peak = vsig.peak_index(ref, rest_v=self.rest_v)
        if self.align == "peak":
            return peak
        onset = vsig.onset_index(ref, threshold_v=self.onset_threshold_v, rest_v=self.rest_v)
        missing = onset < 0
        if missing.any():
            warnings.warn(
                f"{int(missing.sum())} recording(s) never exceed rest + "
                f"{self.onset_threshold_v} V on channel {self.reference_channel}; their "
                "window is aligned to the peak instead",
                RuntimeWarning,
                stacklevel=2,
            )
        return np.where(missing, peak, onset)

    def transform(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Filter each whole recording, then cut its window.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints) or (n_trials, n_timepoints)
            Recordings of at least ``n_samples`` samples (of any length), with the
            channels seen by ``fit``.
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        numpy.ndarray of shape (n_trials, len(channels), n_samples)
        """
        self._check_predict_rate(sample_rate_hz)
        X3 = self._as3d(X)
        if X3.shape[1] != self.n_channels_:
            raise ValueError(
                f"X has {X3.shape[1]} channels, but {type(self).__name__} is expecting "
                f"{self.n_channels_} channels as input"
            )
        chans = self._check_params(X3.shape[1])
        start = self.alignment_index(X3) + int(self.offset_samples)
        S = X3[:, chans]
        fs = float(self.sample_rate_hz)
        if self.signal == "velocity":
            S = vsig.causal_gaussian_velocity(
                S, fs, self.velocity_sigma_samples, self.velocity_half_width_samples
            )
        elif self.signal == "lowpass":
            S = vsig.causal_lowpass(S, self.lowpass_hz, fs, self.lowpass_order)
        win, padded = vsig.cut_windows(S, start, int(self.n_samples))
        if padded.any():
            bad = np.flatnonzero(padded)
            warnings.warn(
                f"{bad.size} window(s) reach outside their recording ({int(padded.sum())} samples "
                f"repeated from the ends), e.g. trial(s) {bad[:5].tolist()}: the onset or "
                "peak lies too close to the start or end of the recording for this window",
                RuntimeWarning,
                stacklevel=2,
            )
        return win

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.requires_fit = True
        return tags
