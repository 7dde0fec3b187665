"""Packets and windows of a continuous recording (thesis 6.2.1).

The Roomba's Labjack delivered data in packets of 160 samples (0.08 s at 2 kHz);
packets "where the variance in the signal was below 5x10^-5" (the robot standing
still) were removed, and the remaining packets "restructured to windows for
classification that were 800 recordings long"; odd-numbered windows train, even ones
test.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PACKET_SAMPLES",
    "QUIET_VARIANCE_V2",
    "WINDOW_SAMPLES",
    "active_packets",
    "odd_even_split",
    "packet_windows",
]

#: Samples per Labjack packet (6.2.1).
PACKET_SAMPLES = 160
#: Samples per classification window (6.2.1).
WINDOW_SAMPLES = 800
#: A packet whose variance is below this (V^2) is dropped (6.2.1).
QUIET_VARIANCE_V2 = 5e-5


def _check(recording: np.ndarray, packet: int) -> np.ndarray:
    x = np.asarray(recording, dtype=float)
    if x.ndim != 2:
        raise ValueError(f"recording must have shape (n_channels, n_samples), got {x.shape}")
    if isinstance(packet, bool) or not isinstance(packet, int | np.integer) or packet < 2:
        raise ValueError(f"packet must be an integer >= 2, got {packet!r}")
    return x


def active_packets(
    recording: np.ndarray, packet: int = PACKET_SAMPLES, threshold_v2: float = QUIET_VARIANCE_V2
) -> np.ndarray:
    """Which whole packets of a recording are kept.

    A packet is kept when its variance reaches ``threshold_v2`` in at least one
    channel (the thesis speaks of "the variance in the signal"; on a two-axis sensor
    the whisker may move in either axis). An incomplete last packet is never kept
    (the Labjack sends whole packets).

    Parameters
    ----------
    recording : ndarray, shape (n_channels, n_samples)
    packet : int
        Samples per packet.
    threshold_v2 : float
        Variance threshold (V^2).

    Returns
    -------
    ndarray of bool, shape (n_samples // packet,)
    """
    x = _check(recording, packet)
    n = x.shape[1] // packet
    var = x[:, : n * packet].reshape(x.shape[0], n, packet).var(axis=2)
    return np.any(var >= threshold_v2, axis=0)


def packet_windows(
    recording: np.ndarray,
    packet: int = PACKET_SAMPLES,
    window: int = WINDOW_SAMPLES,
    threshold_v2: float = QUIET_VARIANCE_V2,
) -> np.ndarray:
    """Drop the quiet packets, join the rest and cut consecutive windows.

    Parameters
    ----------
    recording : ndarray, shape (n_channels, n_samples)
    packet, window : int
        Samples per packet and per window; samples left over after the last whole
        window are discarded.
    threshold_v2 : float
        Variance threshold of :func:`active_packets`.

    Returns
    -------
    ndarray, shape (n_windows, n_channels, window)
        ``n_windows = (kept packets * packet) // window``.
    """
    x = _check(recording, packet)
    if isinstance(window, bool) or not isinstance(window, int | np.integer) or window < 1:
        raise ValueError(f"window must be a positive integer, got {window!r}")
    keep = active_packets(x, packet, threshold_v2)
    n = keep.size
    kept = x[:, : n * packet].reshape(x.shape[0], n, packet)[:, keep].reshape(x.shape[0], -1)
    m = kept.shape[1] // window
    return np.ascontiguousarray(
        kept[:, : m * window].reshape(x.shape[0], m, window).transpose(1, 0, 2)
    )


def odd_even_split(n_windows: int) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the odd-numbered (train) and even-numbered (test) windows.

    Windows are numbered from 1, so the training set is indices 0, 2, 4, ... and the
    test set 1, 3, 5, ...
    """
    idx = np.arange(int(n_windows))
    return idx[0::2], idx[1::2]
