"""Frequency-template classification (thesis 4.3.2, eq. 4.3)."""

from __future__ import annotations

from typing import Literal

import numpy as np

from vibrissa import signal as vsig
from vibrissa.classify._template import NearestTemplate

__all__ = ["FrequencyTemplateClassifier"]


class FrequencyTemplateClassifier(NearestTemplate):
    """Nearest template on DFT magnitude spectra (thesis 4.3.2, eq. 4.3).

    The method of 4.3.3 with an extra preprocessing step: each (low-pass
    filtered) trial is replaced by ``|X(k)|``, the magnitude of its discrete
    Fourier transform (eq. 4.3), per channel; templates are the training spectra
    and the nearest one (sum of squared errors) wins. Phase is discarded, so the
    classifier sees only the oscillation content of the contact (Kim and Moller,
    2004), which the thesis found to be a poor cue for radial distance (4.4.2).

    Parameters
    ----------
    sample_rate_hz : float, default=1000.0
        Sampling rate, Hz.
    cutoff_hz : float or None, default=100.0
        Low-pass cut-off applied before the transform, Hz (the thesis transforms
        "the filtered data" without giving the cut-off); ``None`` for none.
    filter_order : int, default=4
        Butterworth order.
    max_frequency_hz : float or None, default=None
        Keep only bins up to this frequency, Hz (``None``: all bins, 0 to Nyquist,
        as in the thesis).
    templates : {"all", "mean"}, default="all"
        Every training spectrum, or the mean spectrum of each joint class.
    chunk_size : int, default=512
        Test trials per matrix product.
    spectrum : {"magnitude", "abs_real"}, default="magnitude"
        ``|X(k)|`` (the text, 4.3.2) or ``|Re X(k)|`` (what the author's code
        computed, ``abs(real(fft(x)))``).
    one_sided : bool, default=True
        Bins 0 to Nyquist (``numpy.fft.rfft``); ``False``: all ``N`` bins of the
        full DFT, as MATLAB's ``fft`` returns them (each mirrored bin counts twice
        in the distance).
    zero_dc : bool, default=False
        Set bin 0 to zero (the author's code did).
    distance : {"sse", "l1"}, default="sse"
        Sum of squared errors (eq. 4.4) or of absolute errors (the author's code).

    Attributes
    ----------
    classes_, templates_, template_class_, center_, sse_scale_
        As for :class:`TimeTemplateClassifier`, on spectra.
    n_bins_ : int
        Frequency bins kept per channel.
    n_channels_, n_timepoints_, n_features_in_ : int
    """

    def __init__(
        self,
        sample_rate_hz: float = 1000.0,
        cutoff_hz: float | None = 100.0,
        filter_order: int = 4,
        max_frequency_hz: float | None = None,
        templates: Literal["all", "mean"] = "all",
        chunk_size: int = 512,
        spectrum: Literal["magnitude", "abs_real"] = "magnitude",
        one_sided: bool = True,
        zero_dc: bool = False,
        distance: Literal["sse", "l1"] = "sse",
    ) -> None:
        self.sample_rate_hz = sample_rate_hz
        self.cutoff_hz = cutoff_hz
        self.filter_order = filter_order
        self.max_frequency_hz = max_frequency_hz
        self.templates = templates
        self.chunk_size = chunk_size
        self.spectrum = spectrum
        self.one_sided = one_sided
        self.zero_dc = zero_dc
        self.distance = distance

    def _features(self, X: np.ndarray) -> np.ndarray:
        if self.spectrum not in ("magnitude", "abs_real"):
            raise ValueError(f"spectrum must be 'magnitude' or 'abs_real', got {self.spectrum!r}")
        if self.cutoff_hz is not None:
            X = vsig.lowpass(X, self.cutoff_hz, self.sample_rate_hz, order=self.filter_order)
        if self.spectrum == "magnitude" and self.one_sided:
            spec = vsig.magnitude_spectrum(X)
        else:
            dft = np.fft.rfft(X, axis=-1) if self.one_sided else np.fft.fft(X, axis=-1)
            spec = np.abs(dft.real) if self.spectrum == "abs_real" else np.abs(dft)
        if self.zero_dc:
            spec = spec.copy()
            spec[..., 0] = 0.0
        if self.max_frequency_hz is not None:
            n = X.shape[-1]
            freqs = (
                vsig.spectrum_frequencies(n, self.sample_rate_hz)
                if self.one_sided
                else np.abs(np.fft.fftfreq(n, 1.0 / self.sample_rate_hz))
            )
            keep = freqs <= float(self.max_frequency_hz)
            if not keep.any() or self.max_frequency_hz <= 0:
                raise ValueError(
                    f"max_frequency_hz must be positive, got {self.max_frequency_hz!r}"
                )
            spec = spec[..., keep]
        return spec.reshape(spec.shape[0], -1)

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        super()._fit(X, y, y_idx)
        self.n_bins_ = self.templates_.shape[1] // self.n_channels_
