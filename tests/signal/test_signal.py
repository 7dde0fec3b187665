"""Tests of vibrissa.signal: filters, derivatives, baseline, spectra, ch.4 features."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa import signal as vs

FS = 1000.0


def _sine(freq_hz: float, n: int = 2000, fs: float = FS) -> np.ndarray:
    t = np.arange(n) / fs
    return np.sin(2 * np.pi * freq_hz * t)


def _gain(y: np.ndarray, x: np.ndarray) -> float:
    mid = slice(len(x) // 4, 3 * len(x) // 4)  # ignore edge transients
    return float(np.std(y[mid]) / np.std(x[mid]))


def test_lowpass_passes_low_and_stops_high() -> None:
    lo, hi = _sine(5.0), _sine(200.0)
    assert _gain(vs.lowpass(lo, 50.0, FS), lo) == pytest.approx(1.0, abs=1e-3)
    assert _gain(vs.lowpass(hi, 50.0, FS), hi) < 1e-4


def test_highpass_and_bandpass() -> None:
    lo, mid, hi = _sine(2.0), _sine(60.0), _sine(300.0)
    assert _gain(vs.highpass(lo, 30.0, FS), lo) < 1e-3
    assert _gain(vs.highpass(hi, 30.0, FS), hi) == pytest.approx(1.0, abs=1e-3)
    assert _gain(vs.bandpass(mid, 40.0, 90.0, FS), mid) == pytest.approx(1.0, abs=2e-2)
    assert _gain(vs.bandpass(lo, 40.0, 90.0, FS), lo) < 1e-3
    assert _gain(vs.bandpass(hi, 40.0, 90.0, FS), hi) < 1e-3


def test_filters_are_zero_phase_and_keep_alignment() -> None:
    # A symmetric pulse centred at the middle stays centred after filtering.
    n = 651
    t = np.arange(n) - n // 2
    pulse = np.exp(-0.5 * (t / 20.0) ** 2)
    y = vs.lowpass(pulse, 30.0, FS, order=6)
    assert int(np.argmax(y)) == n // 2


def test_notch_removes_its_frequency_only() -> None:
    hum, keep = _sine(50.0), _sine(10.0)
    assert _gain(vs.notch(hum, 50.0, FS, quality=10.0), hum) < 1e-2
    assert _gain(vs.notch(keep, 50.0, FS, quality=10.0), keep) == pytest.approx(1.0, abs=1e-2)


def test_filters_vectorise_along_last_axis() -> None:
    rng = np.random.default_rng(0)
    x = rng.normal(size=(4, 2, 300))
    y = vs.lowpass(x, 40.0, FS)
    assert y.shape == x.shape
    np.testing.assert_allclose(y[2, 1], vs.lowpass(x[2, 1], 40.0, FS))


def test_filters_handle_short_signals() -> None:
    x = np.random.default_rng(1).normal(size=(3, 5))
    assert vs.lowpass(x, 40.0, FS).shape == (3, 5)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda x: vs.lowpass(x, 600.0, FS), "cutoff_hz"),
        (lambda x: vs.lowpass(x, -1.0, FS), "cutoff_hz"),
        (lambda x: vs.lowpass(x, 10.0, 0.0), "sample_rate_hz"),
        (lambda x: vs.lowpass(x, 10.0, FS, order=0), "order"),
        (lambda x: vs.bandpass(x, 90.0, 40.0, FS), "low_cutoff_hz"),
        (lambda x: vs.notch(x, 500.0, FS), "notch_hz"),
        (lambda x: vs.velocity(x, FS, sigma_samples=2.0, sigma_s=0.01), "either"),
        (lambda x: vs.velocity(x, FS, sigma_samples=-1.0), "sigma_samples"),
        (lambda x: vs.contact_duration(x, FS, mode="middle"), "mode"),
        (lambda x: vs.remove_baseline(x, n_pre_samples=0), "n_pre_samples"),
    ],
)
def test_bad_parameters_are_named(call, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        call(np.zeros((2, 100)))


def test_velocity_and_acceleration_of_polynomials() -> None:
    t = np.arange(400) / FS
    x = 3.0 * t**2 + 2.0 * t  # v = 6 t + 2, a = 6
    mid = slice(50, 350)
    v = vs.velocity(x, FS, sigma_samples=4.0)
    a = vs.acceleration(x, FS, sigma_s=0.004)
    np.testing.assert_allclose(v[mid], (6 * t + 2)[mid], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(a[mid], 6.0, rtol=1e-4)


def test_velocity_sigma_seconds_equals_samples() -> None:
    x = np.random.default_rng(2).normal(size=(2, 200))
    np.testing.assert_allclose(
        vs.velocity(x, FS, sigma_s=0.005), vs.velocity(x, FS, sigma_samples=5.0)
    )
    np.testing.assert_allclose(vs.smooth(x), vs.smooth(x, sigma_samples=3.0))


def test_remove_baseline() -> None:
    x = np.full((2, 1, 10), 2.5)
    x[..., 5:] += 1.0
    np.testing.assert_allclose(vs.remove_baseline(x)[..., :5], 0.0)
    y = vs.remove_baseline(x + 0.1, n_pre_samples=5)
    np.testing.assert_allclose(y[..., :5], 0.0, atol=1e-12)
    np.testing.assert_allclose(y[..., 5:], 1.0)


def test_magnitude_spectrum() -> None:
    n = 1000
    x = 2.5 + 0.5 * _sine(40.0, n)
    spec = vs.magnitude_spectrum(x)
    freqs = vs.spectrum_frequencies(n, FS)
    assert spec.shape == freqs.shape == (n // 2 + 1,)
    assert spec[0] == pytest.approx(2.5 * n)
    k = int(np.argmax(spec[1:])) + 1
    assert freqs[k] == pytest.approx(40.0)
    assert spec[k] == pytest.approx(0.5 * n / 2)
    assert vs.magnitude_spectrum(x, detrend=True)[0] == pytest.approx(0.0, abs=1e-9)


def test_peak_magnitude_and_duration_of_a_known_pulse() -> None:
    x = np.full((2, 651), 2.5)
    x[0, 300:351] += 0.4  # 51 samples above threshold, peak 0.4 V
    x[1, 200:220] -= 1.2  # negative direction counts by magnitude
    np.testing.assert_allclose(vs.peak_magnitude(x), [0.4, 1.2])
    np.testing.assert_allclose(vs.contact_duration(x, FS, 0.05), [0.051, 0.020])
    np.testing.assert_allclose(vs.contact_duration(x, FS, 0.05, mode="peak"), [0.051, 0.020])


def test_duration_modes_differ_on_early_noise_crossing() -> None:
    x = np.full(651, 2.5)
    x[10] += 0.1  # brief early crossing
    x[300:330] += 0.5
    assert vs.contact_duration(x, FS, 0.05, mode="first") == pytest.approx(0.001)
    assert vs.contact_duration(x, FS, 0.05, mode="peak") == pytest.approx(0.030)


def test_duration_edge_cases() -> None:
    flat = np.full(100, 2.5)
    assert vs.contact_duration(flat, FS, 0.05) == 0.0
    assert vs.contact_duration(flat, FS, 0.05, mode="peak") == 0.0
    tail = flat.copy()
    tail[60:] += 1.0  # still deflected at the end
    assert vs.contact_duration(tail, FS, 0.05) == pytest.approx(0.040)
    assert vs.contact_duration(tail, FS, 0.05, mode="peak") == pytest.approx(0.040)
