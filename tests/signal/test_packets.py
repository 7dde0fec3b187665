"""Packets and windows of a continuous recording (thesis 6.2.1): the counts the protocol implies."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.signal import (
    PACKET_SAMPLES,
    QUIET_VARIANCE_V2,
    WINDOW_SAMPLES,
    active_packets,
    odd_even_split,
    packet_windows,
)

FS = 2000.0
N_TRIAL = 16 * 2000  # a 16 s trial at 2 kHz


def _recording(quiet_packets: int, rng: np.random.Generator, n: int = N_TRIAL) -> np.ndarray:
    """Two channels: the first ``quiet_packets`` packets at rest (2.5 V, no noise), the
    rest moving (white noise of variance 1e-3 V^2 on channel x only)."""
    x = np.full((2, n), 2.5)
    start = quiet_packets * PACKET_SAMPLES
    x[0, start:] += rng.normal(0.0, np.sqrt(1e-3), n - start)
    return x


def test_a_16_s_trial_is_200_packets_and_40_windows():
    rng = np.random.default_rng(0)
    x = _recording(0, rng)
    assert active_packets(x).shape == (200,)
    w = packet_windows(x)
    assert w.shape == (40, 2, WINDOW_SAMPLES)
    train, test = odd_even_split(len(w))
    # 4 trials x 20 test windows = the 80 test windows per floor of tables 6.1-6.3
    assert 4 * len(test) == 80 and 4 * len(train) == 80


@pytest.mark.parametrize("quiet", [0, 1, 4, 5, 7, 37, 199, 200])
def test_windows_count_the_kept_packets(quiet):
    rng = np.random.default_rng(quiet)
    x = _recording(quiet, rng)
    keep = active_packets(x)
    assert keep.sum() == 200 - quiet
    assert not keep[:quiet].any()
    w = packet_windows(x)
    assert len(w) == (200 - quiet) * PACKET_SAMPLES // WINDOW_SAMPLES


def test_windows_are_the_kept_samples_in_order():
    x = np.tile(np.arange(20 * PACKET_SAMPLES, dtype=float), (2, 1)) * 1e-2
    x[:, 3 * PACKET_SAMPLES : 4 * PACKET_SAMPLES] = 1.0  # one quiet packet (constant)
    w = packet_windows(x)
    kept = np.concatenate([x[:, : 3 * PACKET_SAMPLES], x[:, 4 * PACKET_SAMPLES :]], axis=1)
    assert len(w) == 19 * PACKET_SAMPLES // WINDOW_SAMPLES
    np.testing.assert_array_equal(w[0], kept[:, :WINDOW_SAMPLES])
    np.testing.assert_array_equal(w[1], kept[:, WINDOW_SAMPLES : 2 * WINDOW_SAMPLES])


def test_either_channel_keeps_a_packet_and_the_threshold_is_inclusive():
    base = np.resize([-1.0, 1.0], PACKET_SAMPLES)  # variance exactly 1
    x = np.zeros((2, 3 * PACKET_SAMPLES))
    x[1, :PACKET_SAMPLES] = base * np.sqrt(QUIET_VARIANCE_V2)  # at the threshold: kept
    x[0, PACKET_SAMPLES : 2 * PACKET_SAMPLES] = base * np.sqrt(QUIET_VARIANCE_V2) * 0.999
    x[0, 2 * PACKET_SAMPLES :] = base * 0.1
    np.testing.assert_array_equal(active_packets(x), [True, False, True])


def test_an_incomplete_last_packet_is_dropped():
    x = np.random.default_rng(1).normal(0, 1, (2, 5 * PACKET_SAMPLES + 100))
    assert active_packets(x).shape == (5,)
    assert len(packet_windows(x)) == 1


def test_odd_numbered_windows_train():
    train, test = odd_even_split(5)
    np.testing.assert_array_equal(train, [0, 2, 4])  # windows 1, 3, 5
    np.testing.assert_array_equal(test, [1, 3])


@pytest.mark.parametrize("bad", [np.zeros(800), np.zeros((1, 2, 800))])
def test_refuses_a_recording_that_is_not_channels_by_samples(bad):
    with pytest.raises(ValueError, match="n_channels, n_samples"):
        packet_windows(bad)


def test_refuses_a_bad_packet_or_window_length():
    x = np.zeros((2, 1600))
    with pytest.raises(ValueError, match="packet"):
        active_packets(x, packet=1)
    with pytest.raises(ValueError, match="window"):
        packet_windows(x, window=0)
