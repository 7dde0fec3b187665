"""The thesis author's causal preprocessing, against hand-computed cases."""

import numpy as np
import pytest

from vibrissa import signal as vsig


def test_kernel_is_normalised_gaussian_of_101_taps():
    g = vsig.causal_gaussian_kernel(15.0, 50)
    assert g.shape == (101,)
    assert g.sum() == pytest.approx(1.0)
    # ratio of the centre tap to a tap 15 samples (one sigma) away
    assert g[50] / g[65] == pytest.approx(np.exp(0.5))
    assert np.argmax(g) == 50


def test_velocity_of_a_ramp_is_its_slope_after_the_warm_up():
    fs = 1000.0
    x = 2.5 + 0.002 * np.arange(400.0)  # 0.002 V per sample = 2 V/s
    v = vsig.causal_gaussian_velocity(x, fs)
    # once all 101 taps see the ramp, the smoothed derivative is exact
    assert np.allclose(v[100:], 2.0)
    # during the warm-up the zero initial state shows: tap sums grow from g[0]
    g = vsig.causal_gaussian_kernel()
    assert v[0] == pytest.approx(2.0 * g[0])
    assert v[10] == pytest.approx(2.0 * g[:11].sum())


def test_velocity_is_delayed_by_half_the_kernel():
    fs = 1000.0
    x = np.zeros(600)
    x[200:] = 1.0  # a step: its difference is an impulse at sample 200
    v = vsig.causal_gaussian_velocity(x, fs)
    assert int(np.argmax(v)) == 250
    assert v.sum() / fs == pytest.approx(1.0)


def test_causal_lowpass_passes_dc_and_is_causal():
    fs = 1000.0
    x = np.zeros(2000)
    x[500:] = 1.0
    y = vsig.causal_lowpass(x, 20.0, fs, order=10)
    assert np.all(y[:500] == 0.0)  # nothing before the step
    assert y[-1] == pytest.approx(1.0, abs=1e-6)
    with pytest.raises(ValueError, match="Nyquist"):
        vsig.causal_lowpass(x, 600.0, fs)


def test_onset_and_peak_index():
    x = np.full((2, 10), 2.5)
    x[0, 4:7] = [2.55, 2.61, 3.0]
    assert vsig.onset_index(x, 0.1, 2.5).tolist() == [5, -1]
    assert vsig.peak_index(x, 2.5).tolist() == [6, 0]


def test_cut_windows_pads_with_end_samples():
    X = np.arange(10.0).reshape(1, 1, 10)
    X = np.concatenate([X, X + 100])
    win, pad = vsig.cut_windows(X, [-2, 7], 5)
    assert win[0, 0].tolist() == [0, 0, 0, 1, 2]
    assert win[1, 0].tolist() == [107, 108, 109, 109, 109]
    assert pad.tolist() == [2, 2]
    with pytest.raises(ValueError, match="entries"):
        vsig.cut_windows(X, [0], 3)
