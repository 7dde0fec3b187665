"""Tests of vibrissa.framework.detect: contacts found, windows cut, chunking-independent."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vibrissa.framework.detect import ContactDetector, DetectorSettings, contact_windows

FS = 2000.0
REST_V = 2.5
#: (radial_distance_mm, speed_mm_s) -> (bump amplitude V, bump duration s)
WHERE_SHAPES = {
    (30.0, 50.0): (1.0, 0.2),
    (30.0, 100.0): (1.0, 0.12),
    (60.0, 50.0): (0.4, 0.2),
    (60.0, 100.0): (0.4, 0.12),
}
#: angle_deg -> y / x deflection ratio
ANGLE_RATIO = {0.0: 0.1, 30.0: 0.7}
#: texture code -> amplitude (V) of a 150 Hz vibration on the bump
TEXTURE_VIBRATION_V = {0.0: 0.0, 3.0: 0.06}
ALL_CLASSES = [
    (r, s, a, t)
    for r in (30.0, 60.0)
    for s in (50.0, 100.0)
    for a in (0.0, 30.0)
    for t in (0.0, 3.0)
]


def bump(cls: tuple[float, float, float, float], rng: np.random.Generator) -> np.ndarray:
    """A contact of class ``(radial_mm, speed_mm_s, angle_deg, texture_code)``: (n, 2) V."""
    radial, speed, angle, texture = cls
    amp, dur = WHERE_SHAPES[(radial, speed)]
    t = np.arange(int(round(dur * FS))) / FS
    env = np.sin(np.pi * t / dur)
    vib = np.sin(2 * np.pi * 150.0 * t + rng.uniform(0, 2 * np.pi))
    x = amp * env + TEXTURE_VIBRATION_V[texture] * env * vib
    return np.stack([x, ANGLE_RATIO[angle] * x], axis=-1)


def synthetic_stream(
    seconds: float,
    n_whiskers: int,
    seed: int,
    classes=ALL_CLASSES,
    events_per_s: float = 2.0,
    noise_v: float = 0.005,
):
    """Rest + noise + class-shaped bumps: ``(samples, events)``, events ``(whisker, k, cls)``.

    ``classes`` is a list of classes drawn at random, or a callable ``(whisker, rng) -> cls``.
    """
    rng = np.random.default_rng(seed)
    n = int(round(seconds * FS))
    x = REST_V + noise_v * rng.standard_normal((n, n_whiskers, 2))
    events = []
    for w in range(n_whiskers):
        t = 0.2 + rng.exponential(1 / events_per_s)
        while t < seconds - 0.8:
            c = classes(w, rng) if callable(classes) else classes[rng.integers(len(classes))]
            b = bump(c, rng)
            k = int(round(t * FS))
            x[k : k + len(b), w] += b
            events.append((w, k, c))
            t += len(b) / FS + 0.06 + rng.exponential(1 / events_per_s)
    events.sort(key=lambda e: (e[1], e[0]))
    return x, events


def match(contacts, events, tolerance: int = 60):
    """The event of each contact (same whisker, onset within ``tolerance`` samples after it)."""
    out = []
    for c in contacts:
        cand = [e for e in events if e[0] == c.whisker and 0 <= c.onset_index - e[1] <= tolerance]
        assert len(cand) == 1, (c, cand)
        out.append(cand[0])
    return out


def chunked(det: ContactDetector, x: np.ndarray, cuts) -> list:
    out = []
    edges = [0, *cuts, len(x)]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        out += det.push(x[a:b])
    return out + det.flush()


def same(a, b) -> bool:
    return len(a) == len(b) and all(p.same_as(q) for p, q in zip(a, b, strict=True))


STREAM, EVENTS = synthetic_stream(6.0, 3, seed=1)
REFERENCE = contact_windows(STREAM, FS)


def test_every_contact_found_once_with_its_window():
    assert len(REFERENCE) == len(EVENTS) > 10
    matched = match(REFERENCE, EVENTS)
    assert len({(e[0], e[1]) for e in matched}) == len(EVENTS)
    s = DetectorSettings()
    for c, (w, k, cls) in zip(REFERENCE, matched, strict=True):
        amp, dur = WHERE_SHAPES[cls[:2]]
        assert c.window.shape == (2, 1000)
        assert not c.truncated
        a = c.onset_index - int(s.pre_s * FS)
        np.testing.assert_array_equal(c.window, STREAM[a : a + 1000, w].T)
        # ends where the bump falls below release (threshold / 2), within the hold
        assert abs(c.end_index - (k + dur * FS)) < 0.1 * dur * FS
        # departure: the norm over both channels (plus the texture's vibration)
        peak = (amp + TEXTURE_VIBRATION_V[cls[3]]) * np.hypot(1.0, ANGLE_RATIO[cls[2]])
        assert 0.9 * peak < c.peak_departure < 1.05 * peak


@pytest.mark.parametrize("size", [1, 7, 4096])
def test_chunk_size_does_not_change_the_output(size):
    det = ContactDetector(3, 2, FS)
    assert same(chunked(det, STREAM, range(size, len(STREAM), size)), REFERENCE)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.integers(0, len(STREAM)), max_size=30))
def test_any_partition_gives_the_same_output(cuts):
    det = ContactDetector(3, 2, FS)
    assert same(chunked(det, STREAM, sorted(cuts)), REFERENCE)


def test_output_ordered_by_emission_then_whisker():
    s = DetectorSettings()
    n_pre, n_win = int(s.pre_s * FS), int(s.window_s * FS)
    hold = int(s.hold_s * FS)
    keys = [
        (max(c.end_index + hold - 1, c.onset_index - n_pre + n_win - 1), c.whisker)
        for c in REFERENCE
    ]
    assert keys == sorted(keys)


def test_window_before_stream_start_is_rest_and_flush_truncates():
    x = np.full((300, 1, 2), 2.5)
    x[10:200, 0, 0] += 0.5  # onset 10 samples in: the window starts 90 samples before the stream
    det = ContactDetector(1, 2, FS, DetectorSettings(rest=(2.5, 2.5)))
    assert det.push(x) == []  # ended but its window (1000 samples) is incomplete
    (c,) = det.flush()
    assert c.truncated and c.onset_index == 10 and c.end_index == 200
    np.testing.assert_array_equal(c.window[:, :90], 2.5)  # before the stream: rest
    np.testing.assert_array_equal(c.window[:, 90:390], x[:, 0].T)
    np.testing.assert_array_equal(c.window[:, 390:], 2.5)  # padded with the last sample


def test_short_spikes_dropped_and_rest_estimated():
    rng = np.random.default_rng(0)
    x = 1.7 + 0.003 * rng.standard_normal((4000, 2, 1))
    x[1000:1005, 0, 0] += 1.0  # 2.5 ms < min_duration 5 ms
    x[2000:2400, 1, 0] += 0.3
    det = ContactDetector(2, 1, FS)
    out = det.push(x) + det.flush()
    assert [(c.whisker, c.onset_index, c.end_index) for c in out] == [(1, 2000, 2400)]
    np.testing.assert_allclose(det.rest_level, 1.7, atol=0.002)


def test_detecting_channels_and_release():
    x = np.full((3000, 1, 2), 2.5)
    x[500:900, 0, 1] += 0.5  # channel 1 only
    only0 = DetectorSettings(rest=(2.5, 2.5), channels=(0,))
    assert contact_windows(x, FS, only0) == []
    (c,) = contact_windows(x, FS, DetectorSettings(rest=(2.5, 2.5), channels=(1,)))
    assert (c.onset_index, c.end_index) == (500, 900)
    # a dip below release for less than hold_s does not end the contact
    x[600:620, 0, 1] = 2.5  # 10 ms < hold 20 ms
    (c,) = contact_windows(x, FS, DetectorSettings(rest=(2.5, 2.5)))
    assert (c.onset_index, c.end_index) == (500, 900)
    x[600:700, 0, 1] = 2.5  # 50 ms: two contacts
    out = contact_windows(x, FS, DetectorSettings(rest=(2.5, 2.5)))
    assert [(c.onset_index, c.end_index) for c in out] == [(500, 600), (700, 900)]


def test_break_stream_drops_contact_in_progress_and_restarts_history():
    x = np.full((4000, 2, 1), 2.5)
    x[100:1500, :, 0] += 0.5  # long contact on both whiskers
    x[2000:2200, 1, 0] += 0.5
    det = ContactDetector(2, 1, FS, DetectorSettings(rest=(2.5,)))
    assert det.push(x[:1000]) == []
    det.break_stream([0])
    out = det.push(x[1000:]) + det.flush()
    # whisker 0: dropped, then re-detected from the break (its window before the break is rest)
    w0 = [c for c in out if c.whisker == 0]
    assert [(c.onset_index, c.end_index) for c in w0] == [(1000, 1500)]
    np.testing.assert_array_equal(w0[0].window[0, :100], 2.5)
    w1 = [(c.onset_index, c.end_index) for c in out if c.whisker == 1]
    assert w1 == [(100, 1500), (2000, 2200)]


def test_empty_chunks_and_flush_without_samples():
    det = ContactDetector(2, 2, FS)
    assert det.push(np.empty((0, 2, 2))) == []
    assert det.flush() == []


@pytest.mark.parametrize(
    ("samples", "match_"),
    [
        (np.zeros((5, 2)), "shape"),
        (np.zeros((5, 3, 2)), "shape"),
        (np.full((5, 2, 2), np.nan), "NaN"),
        (np.full((5, 2, 2), np.inf), "infinite"),
    ],
)
def test_bad_samples_refused(samples, match_):
    with pytest.raises(ValueError, match=match_):
        ContactDetector(2, 2, FS).push(samples)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"threshold": -1.0}, "threshold"),
        ({"release": 0.2}, "release"),
        ({"hold_s": 0.0}, "hold_s"),
        ({"window_s": float("nan")}, "window_s"),
        ({"channels": (0, 0)}, "channels"),
        ({"rest": (2.5, float("inf"))}, r"rest\[1\]"),
    ],
)
def test_bad_settings_named(kwargs, name):
    with pytest.raises((ValueError, TypeError), match=name):
        DetectorSettings(**kwargs)


def test_settings_mismatching_the_stream_named():
    with pytest.raises(ValueError, match="channels"):
        ContactDetector(2, 2, FS, DetectorSettings(channels=(2,)))
    with pytest.raises(ValueError, match="rest"):
        ContactDetector(2, 2, FS, DetectorSettings(rest=(2.5,)))
    with pytest.raises(ValueError, match="n_whiskers"):
        ContactDetector(0, 2, FS)
    assert DetectorSettings.from_dict(DetectorSettings(rest=(1.0,)).to_dict()) == DetectorSettings(
        rest=(1.0,)
    )
