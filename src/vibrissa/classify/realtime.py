"""CrunchBot's real-time classifiers (thesis 6.5.2, 6.5.4, 6.5.5.3), on plain arrays.

Three small classifiers the robot's control loop calls between its 0.5 s steps:

- :class:`FloorTextureNB`: stationary naive Bayes (4.3.5, through
  :class:`~vibrissa.classify.StationaryNaiveBayes`) on the latest 100 ms (200 samples at
  2 kHz) of a floor whisker; :meth:`FloorTextureNB.loglik` returns the per-class
  log-likelihoods that go straight to the SLAM weights (6.5.2: "the present method feeds
  the likelihoods directly into the navigation system", not through Bayes' rule);
- :class:`RadialDistanceLinear`: one whisker's least-squares line from peak deflection
  magnitude (:func:`peak_deflection`) to radial distance of contact (6.5.4);
- :class:`SurfaceAngleTemplates`: multi-whisker templates of the 8 Hall channels of the
  four obstacle whiskers over 2 s from HIT_1, one per trained wall angle (6.5.5.3);
  the nearest template by mean squared error (4.3.3) wins.

Arrays are ``(time, channel)`` as the robot logs them (the scikit-learn estimators of
:mod:`vibrissa.classify` take ``(trial, channel, time)``). Bad input raises one
``ValueError`` naming the argument. Nothing here imports the simulator: the classifiers
run the same on a real robot's recordings.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, Self

import numpy as np
from scipy import signal as _sig
from scipy.ndimage import uniform_filter1d

from vibrissa import signal as vsig
from vibrissa._validate import positive
from vibrissa.classify import StationaryNaiveBayes

__all__ = [
    "FloorTextureNB",
    "RadialDistanceLinear",
    "SurfaceAngleTemplates",
    "peak_deflection",
]


def _array(name: str, x: object, ndim: int) -> np.ndarray:
    """``x`` as a finite float array of ``ndim`` dimensions, else a ValueError naming it."""
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array") from None
    if arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape})")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return arr


def _check_rate(owner: object, sample_rate_hz: float | None) -> None:
    """Refuse a sample rate other than the one ``owner`` was fitted at."""
    if sample_rate_hz is None:
        return
    rate = positive("sample_rate_hz", sample_rate_hz)
    fitted = owner.sample_rate_hz_  # type: ignore[attr-defined]
    if not np.isclose(rate, fitted, rtol=1e-9, atol=0.0):
        raise ValueError(
            f"{type(owner).__name__} was fitted at {fitted:g} Hz, but the data "
            f"are sampled at {rate:g} Hz"
        )


def _fitted(owner: object, attribute: str) -> None:
    if not hasattr(owner, attribute):
        raise ValueError(f"{type(owner).__name__} is not fitted yet; call fit first")


def peak_deflection(hall_xy: np.ndarray, rest_v: float = vsig.HALL_REST_V) -> float:
    """Peak deflection magnitude of one whisker: ``max_t |(x, y)(t) - rest_v|`` (V).

    The feature f1 of 4.3.4 (eq. 4.5) over both Hall channels, the "deflection
    magnitude" of 6.5.4.

    Parameters
    ----------
    hall_xy : ndarray of shape (n, 2)
        One whisker's Hall outputs (x, y), V.
    rest_v : float
        Output at rest, V.

    Returns
    -------
    float
    """
    h = _array("hall_xy", hall_xy, 2)
    if h.shape[1] != 2:
        raise ValueError(f"hall_xy must have shape (n, 2), got {h.shape}")
    d = h - float(rest_v)
    return float(np.sqrt(np.max(d[:, 0] ** 2 + d[:, 1] ** 2)))


class FloorTextureNB:
    """Stationary naive Bayes floor-texture classifier on a 100 ms window (6.5.2).

    "The methodology is the same as that outlined in Section 4.3.5": :meth:`fit` trains a
    :class:`~vibrissa.classify.StationaryNaiveBayes` (one histogram per class and
    channel of the whisker velocity, flat priors) on the training windows;
    :meth:`loglik` evaluates a new window against its fitted tables
    (``bin_edges_``, ``log_likelihood_``) in a few vectorised NumPy operations, without
    the estimator's input checks, so one call costs tens of microseconds.

    Parameters
    ----------
    signal : {"velocity", "raw"}
        Histogram the Gaussian-smoothed velocity (4.3.5, the default) or the raw volts.
    n_bins, value_range, smoothing_sigma, derivative_sigma_samples
        As :class:`~vibrissa.classify.StationaryNaiveBayes` (its defaults: 100 bins over
        the central 99 % of the training values, sigma 1 bin, velocity sigma 3 samples).

    Attributes
    ----------
    classes_ : tuple of str
        Texture names, sorted.
    sample_rate_hz_ : float
    n_samples_, n_channels_ : int
        Window shape seen in training.
    estimator_ : StationaryNaiveBayes
        The fitted estimator (its ``predict`` gives the same decisions).
    """

    def __init__(
        self,
        signal: Literal["velocity", "raw"] = "velocity",
        n_bins: int = 100,
        value_range: tuple[float, float] | str | None = "robust",
        smoothing_sigma: float = 1.0,
        derivative_sigma_samples: float = 3.0,
    ) -> None:
        self.signal = signal
        self.n_bins = n_bins
        self.value_range = value_range
        self.smoothing_sigma = smoothing_sigma
        self.derivative_sigma_samples = derivative_sigma_samples

    def fit(self, windows: np.ndarray, labels: Sequence[str], sample_rate_hz: float) -> Self:
        """Learn each texture's per-channel likelihood histograms.

        Parameters
        ----------
        windows : ndarray of shape (n, n_samples, n_channels)
            Training windows (200 samples at 2 kHz on CrunchBot), V.
        labels : sequence of str, length n
            Texture of each window (at least two different ones).
        sample_rate_hz : float
        """
        w = _array("windows", windows, 3)
        fs = positive("sample_rate_hz", sample_rate_hz)
        y = np.asarray(labels, dtype=object)
        if y.shape != (w.shape[0],):
            raise ValueError(
                f"labels must hold one texture per window ({w.shape[0]}), got shape {y.shape}"
            )
        if w.shape[1] < 2:
            raise ValueError(f"windows need at least 2 samples, got {w.shape[1]}")
        y = y.astype(str)
        est = StationaryNaiveBayes(
            signal=self.signal,
            n_bins=self.n_bins,
            value_range=self.value_range,
            smoothing_sigma=self.smoothing_sigma,
            sample_rate_hz=fs,
            derivative_sigma_samples=self.derivative_sigma_samples,
        ).fit(np.ascontiguousarray(np.moveaxis(w, 2, 1)), y, sample_rate_hz=fs)
        edges = est.bin_edges_
        b = edges.shape[1] - 1
        self.estimator_ = est
        self.classes_ = tuple(str(c) for c in est.classes_)
        self.sample_rate_hz_ = fs
        self.n_samples_, self.n_channels_ = int(w.shape[1]), int(w.shape[2])
        self._lo = np.ascontiguousarray(edges[:, :1])
        self._width = ((edges[:, -1] - edges[:, 0]) / b)[:, None]
        self._top = b - 1
        # (n_channels, n_bins, n_classes): one gather per sample, then a sum
        self._table = np.ascontiguousarray(np.moveaxis(est.log_likelihood_, 0, -1))
        self._channel = np.arange(self.n_channels_)[:, None]
        return self

    def _transform(self, x: np.ndarray) -> np.ndarray:
        """``(n_channels, n_samples)`` -> the histogrammed signal (as the estimator)."""
        if self.signal == "raw":
            return x
        return vsig.velocity(x, self.sample_rate_hz_, sigma_samples=self.derivative_sigma_samples)

    def loglik(self, window: np.ndarray, sample_rate_hz: float | None = None) -> np.ndarray:
        """Log-likelihood of each texture of :attr:`classes_` for one window.

        ``sum over samples and channels of log P(x | texture)`` (eq. 4.10 without the
        prior), in the order of :attr:`classes_`.

        Parameters
        ----------
        window : ndarray of shape (n_samples, n_channels)
            The latest samples of one floor whisker, V (as in training).
        sample_rate_hz : float, optional
            The window's rate, checked against the training rate.

        Returns
        -------
        ndarray of shape (n_classes,)
        """
        _fitted(self, "classes_")
        _check_rate(self, sample_rate_hz)
        x = _array("window", window, 2)
        if x.shape != (self.n_samples_, self.n_channels_):
            raise ValueError(
                f"window must have shape ({self.n_samples_}, {self.n_channels_}) "
                f"as in training, got {x.shape}"
            )
        s = self._transform(x.T)
        k = np.clip(np.floor((s - self._lo) / self._width), 0, self._top).astype(np.intp)
        return self._table[self._channel, k].sum(axis=(0, 1))

    def predict(self, window: np.ndarray, sample_rate_hz: float | None = None) -> str:
        """The texture of largest log-likelihood (flat priors)."""
        return self.classes_[int(np.argmax(self.loglik(window, sample_rate_hz)))]


class RadialDistanceLinear:
    """One whisker's linear map from peak deflection to radial distance (6.5.4).

    "A linear regression was used as it was sufficient": ``distance = a + b * peak``
    fitted by least squares on the training contacts.

    Attributes
    ----------
    intercept_m_, slope_m_per_v_ : float
        ``a`` and ``b``.
    residual_std_m_ : float
        Standard deviation of the training residuals, ``sqrt(SSR / (n - 2))`` (m).
    """

    def fit(self, peak: np.ndarray, distance_m: np.ndarray) -> Self:
        """Fit the line on ``n >= 3`` contacts (peaks in V, distances in m)."""
        p = _array("peak", peak, 1)
        d = _array("distance_m", distance_m, 1)
        if p.shape != d.shape:
            raise ValueError(
                f"peak and distance_m must have the same length, got {p.size} and {d.size}"
            )
        if p.size < 3:
            raise ValueError(f"peak: at least 3 contacts are needed, got {p.size}")
        if np.ptp(p) == 0:
            raise ValueError("peak: all peaks are equal; a line cannot be fitted")
        A = np.column_stack([np.ones_like(p), p])
        coef, *_ = np.linalg.lstsq(A, d, rcond=None)
        res = d - A @ coef
        self.intercept_m_, self.slope_m_per_v_ = float(coef[0]), float(coef[1])
        self.residual_std_m_ = float(np.sqrt(np.sum(res**2) / (p.size - 2)))
        return self

    def predict(self, peak: float | np.ndarray) -> float | np.ndarray:
        """Radial distance (m from the base) of a peak (a float for a float)."""
        _fitted(self, "slope_m_per_v_")
        p = np.asarray(peak, dtype=float)
        if not np.all(np.isfinite(p)):
            raise ValueError("peak contains NaN or infinite values")
        out = self.intercept_m_ + self.slope_m_per_v_ * p
        return float(out) if out.ndim == 0 else out


#: 6.5.5.3's preprocessing: low-pass cut-off (Hz) and moving-average length (samples).
ANGLE_LOWPASS_HZ = 17.0
ANGLE_SMOOTHING_SAMPLES = 5


class SurfaceAngleTemplates:
    """Multi-whisker surface-angle templates (6.5.5.3).

    Each recording (8 channels from HIT_1) is low-pass filtered at 17 Hz and smoothed
    with a 5-point moving average; a template is the mean of the preprocessed runs of
    one angle. :meth:`predict` compares a recording with every template over the
    recording's length (mean squared error over samples and channels, as 4.3.3) and
    returns the angle of the nearest.

    Both filters are **causal** (a Butterworth low-pass in second-order sections,
    started in its steady state at the first sample, then the mean of each sample and
    the four before it): online the classifier sees only HIT_1 to HIT_2, often shorter
    than the 2 s templates, and a causal filter gives its first ``m`` samples exactly as
    it gives the first ``m`` samples of a full 2 s run, whereas a zero-phase filter
    would bend the end of a short recording differently from the template's middle.
    The delay (~20 ms) is the same in templates and recordings.

    Parameters
    ----------
    cutoff_hz : float
        Low-pass cut-off (6.5.5.3: 17 Hz).
    order : int
        Butterworth order (not given in the thesis; 4).
    smoothing_samples : int
        Moving-average length (6.5.5.3: 5).
    n_channels : int
        Channels per recording (four whiskers x (x, y) = 8).

    Attributes
    ----------
    angles_rad_ : ndarray of shape (n_angles,)
        The trained angles, sorted.
    templates_ : ndarray of shape (n_angles, n_samples, n_channels)
    sample_rate_hz_ : float
    """

    def __init__(
        self,
        cutoff_hz: float = ANGLE_LOWPASS_HZ,
        order: int = 4,
        smoothing_samples: int = ANGLE_SMOOTHING_SAMPLES,
        n_channels: int = 8,
    ) -> None:
        self.cutoff_hz = cutoff_hz
        self.order = order
        self.smoothing_samples = smoothing_samples
        self.n_channels = n_channels

    def preprocess(self, recording: np.ndarray) -> np.ndarray:
        """Causal low-pass then moving average along time (axis -2) of ``(..., n, ch)``."""
        x = np.swapaxes(np.asarray(recording, dtype=float), -1, -2)
        return np.swapaxes(self._preprocess_channels_first(x), -1, -2)

    def _preprocess_channels_first(self, x: np.ndarray) -> np.ndarray:
        """:meth:`preprocess` of ``(..., ch, n)``, time last, returned the same way."""
        # along the last axis of a contiguous copy, sosfilt and the moving average walk
        # contiguous memory (twice as fast as along axis -2)
        x = np.ascontiguousarray(x)
        z0 = self._unit_steady_state()
        zi = z0.reshape((z0.shape[0],) + (1,) * (x.ndim - 1) + (2,)) * x[None, ..., :1]
        y, _ = _sig.sosfilt(self._sos, x, axis=-1, zi=zi)
        k = int(self.smoothing_samples)
        # uniform_filter1d with origin (k - 1) // 2 averages each sample and the k - 1
        # before it; "nearest" repeats the first sample, the filter's steady state
        return uniform_filter1d(y, k, axis=-1, mode="nearest", origin=(k - 1) // 2)

    def _unit_steady_state(self) -> np.ndarray:
        """``(sections, 2)``: the low-pass's state at rest under a unit input (made once)."""
        cached = getattr(self, "_zi_unit", None)
        if cached is None or cached[0] is not self._sos:
            # solving for it costs more than filtering a short recording
            cached = (self._sos, _sig.sosfilt_zi(self._sos))
            self._zi_unit = cached
        return cached[1]

    def fit(self, recordings: np.ndarray, angles_rad: np.ndarray, sample_rate_hz: float) -> Self:
        """Build one template per angle from runs aligned to HIT_1.

        Parameters
        ----------
        recordings : ndarray of shape (n, n_samples, n_channels)
            Hall outputs from HIT_1 (2 s on CrunchBot), V.
        angles_rad : ndarray of shape (n,)
            Wall angle of each run (rad).
        sample_rate_hz : float
        """
        r = _array("recordings", recordings, 3)
        a = _array("angles_rad", angles_rad, 1)
        fs = positive("sample_rate_hz", sample_rate_hz)
        if r.shape[2] != self.n_channels:
            raise ValueError(
                f"recordings must have {self.n_channels} channels, got shape {r.shape}"
            )
        if a.shape != (r.shape[0],):
            raise ValueError(
                f"angles_rad must hold one angle per recording ({r.shape[0]}), got shape {a.shape}"
            )
        k = self.smoothing_samples
        if isinstance(k, bool) or not isinstance(k, int | np.integer) or k < 1:
            raise ValueError(f"smoothing_samples must be a positive integer, got {k!r}")
        cut = positive("cutoff_hz", self.cutoff_hz)
        if cut >= fs / 2:
            raise ValueError(
                f"cutoff_hz ({cut:g} Hz) must be below the Nyquist frequency ({fs / 2:g} Hz)"
            )
        self._sos = _sig.butter(int(self.order), cut, btype="lowpass", fs=fs, output="sos")
        angles, idx = np.unique(a, return_inverse=True)
        if angles.size < 2:
            raise ValueError("angles_rad: at least two different angles are needed")
        pre = self.preprocess(r)
        templates = np.zeros((angles.size,) + pre.shape[1:])
        np.add.at(templates, idx, pre)
        templates /= np.bincount(idx)[:, None, None]
        self.angles_rad_ = angles
        self.templates_ = templates
        self.sample_rate_hz_ = fs
        self._energy = None
        self._templates_cf = None
        # made here, not in the first timed call
        self._template_energy()
        self._channels_first()
        return self

    def scores(self, recording: np.ndarray, sample_rate_hz: float | None = None) -> np.ndarray:
        """Mean squared error (V^2) of each template against ``recording``.

        Over ``min(m, template length)`` samples, in the order of :attr:`angles_rad_`.
        """
        _fitted(self, "templates_")
        _check_rate(self, sample_rate_hz)
        x = _array("recording", recording, 2)
        if x.shape[1] != self.templates_.shape[2]:
            raise ValueError(
                f"recording must have {self.templates_.shape[2]} channels, got shape {x.shape}"
            )
        m = min(x.shape[0], self.templates_.shape[1])
        # sum (T - p)^2 = sum T^2 - 2 T.p + sum p^2, with the templates' running sums of
        # squares made once: one dot product per template, no (templates, samples,
        # channels) difference
        p = self._preprocess_channels_first(x[:m].T)  # (ch, m)
        # per channel one matrix-vector product over a view of the templates' first m
        # samples, time last (the robot's loop runs BLAS on one thread, so no idle BLAS
        # workers are woken)
        t = self._channels_first()
        cross = np.zeros(t.shape[0])
        for c in range(t.shape[1]):
            cross += t[:, c, :m] @ p[c]
        sq = self._template_energy()[:, m] - 2.0 * cross + float(np.sum(p * p))
        return np.maximum(sq, 0.0) / (m * x.shape[1])

    def _channels_first(self) -> np.ndarray:
        """The templates as ``(n_angles, n_channels, n_samples)``, time last (made once)."""
        cached = getattr(self, "_templates_cf", None)
        if cached is None or cached.shape != (
            self.templates_.shape[0],
            self.templates_.shape[2],
            self.templates_.shape[1],
        ):
            cached = np.ascontiguousarray(np.swapaxes(self.templates_, 1, 2))
            self._templates_cf = cached
        return cached

    def _template_energy(self) -> np.ndarray:
        """``(n_angles, n_samples + 1)``: each template's cumulative sum of squares.

        Column ``k`` holds each template's sum of squares over its first ``k`` samples.
        """
        cached = getattr(self, "_energy", None)
        if cached is None or cached.shape != (
            self.templates_.shape[0],
            self.templates_.shape[1] + 1,
        ):
            per_sample = np.sum(self.templates_ * self.templates_, axis=2)
            cached = np.concatenate(
                [np.zeros((per_sample.shape[0], 1)), np.cumsum(per_sample, axis=1)], axis=1
            )
            self._energy = cached
        return cached

    def predict(self, recording: np.ndarray, sample_rate_hz: float | None = None) -> float:
        """Angle (rad) of the nearest template.

        Parameters
        ----------
        recording : ndarray of shape (m, n_channels)
            Hall outputs from HIT_1 (``m`` may be shorter than the templates; longer
            recordings are compared over the templates' length).
        sample_rate_hz : float, optional
            Checked against the training rate.
        """
        best = int(np.argmin(self.scores(recording, sample_rate_hz)))
        return float(self.angles_rad_[best])
