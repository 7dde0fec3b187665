"""Preprocessing building blocks for whisker signals, vectorised along the last axis.

Arrays follow the package layout ``(n_trials, n_channels, n_timepoints)`` (any
leading shape works; time is always the last axis). Units are in argument
names: ``sample_rate_hz``, ``cutoff_hz``, ``threshold_v``, ``sigma_s``.

- filters: :func:`lowpass`, :func:`highpass`, :func:`bandpass` (Butterworth,
  second-order sections, zero phase) and :func:`notch` (``iirnotch``);
- derivatives: :func:`smooth`, :func:`velocity`, :func:`acceleration`
  (Gaussian-derivative kernels, thesis 4.3.5);
- :func:`remove_baseline` (2.5 V Hall rest level or pre-contact mean);
- spectra: :func:`magnitude_spectrum`, :func:`spectrum_frequencies` (eq. 4.3);
- the thesis author's own preprocessing (:mod:`._causal`):
  :func:`causal_gaussian_velocity`, :func:`causal_lowpass`, :func:`onset_index`,
  :func:`peak_index`, :func:`cut_windows`;
- chapter-4 features: :func:`peak_magnitude` (f1, eq. 4.5) and
  :func:`contact_duration` (f2, eqs. 4.6-4.8);
- :func:`ring_down`: damped frequency and damping ratio of a free decay;
- continuous recordings (thesis 6.2.1): :func:`active_packets`, :func:`packet_windows`
  (drop quiet packets, cut windows) and :func:`odd_even_split`.
"""

from vibrissa.signal._baseline import HALL_REST_V, remove_baseline
from vibrissa.signal._causal import (
    causal_gaussian_kernel,
    causal_gaussian_velocity,
    causal_lowpass,
    cut_windows,
    onset_index,
    peak_index,
)
from vibrissa.signal._derivatives import DEFAULT_SIGMA_SAMPLES, acceleration, smooth, velocity
from vibrissa.signal._features import contact_duration, peak_magnitude
from vibrissa.signal._filters import bandpass, highpass, lowpass, notch
from vibrissa.signal._packets import (
    PACKET_SAMPLES,
    QUIET_VARIANCE_V2,
    WINDOW_SAMPLES,
    active_packets,
    odd_even_split,
    packet_windows,
)
from vibrissa.signal._ringdown import ring_down
from vibrissa.signal._spectra import magnitude_spectrum, spectrum_frequencies

__all__ = [
    "DEFAULT_SIGMA_SAMPLES",
    "HALL_REST_V",
    "PACKET_SAMPLES",
    "QUIET_VARIANCE_V2",
    "WINDOW_SAMPLES",
    "acceleration",
    "active_packets",
    "bandpass",
    "causal_gaussian_kernel",
    "causal_gaussian_velocity",
    "causal_lowpass",
    "cut_windows",
    "contact_duration",
    "highpass",
    "lowpass",
    "magnitude_spectrum",
    "notch",
    "odd_even_split",
    "onset_index",
    "packet_windows",
    "peak_index",
    "peak_magnitude",
    "remove_baseline",
    "ring_down",
    "smooth",
    "spectrum_frequencies",
    "velocity",
]
