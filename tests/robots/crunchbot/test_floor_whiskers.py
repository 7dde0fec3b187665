"""CrunchBot's floor whiskers on the simulated rod: contact, textures, tiles, window mode."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa import signal as vsig
from vibrissa.robots.crunchbot.arena import Arena, Pose
from vibrissa.robots.crunchbot.floor_whiskers import (
    FWD_SPEED_M_S,
    FloorWhiskers,
    collect_floor_training,
    texture_course,
)
from vibrissa.robots.crunchbot.synthetic import FLOOR_WHISKERS_M

FS = 2000.0
STEP = 1000  # 0.5 s


def _arena(*columns: str, start_x: float = 0.2) -> Arena:
    n = len(columns)
    return Arena(
        name="t", size_m=0.5 * n, start=Pose(start_x, 0.25 * n, 0.0), tiles=(tuple(columns),) * n
    )


def _straight(
    k: int, x0: float, y0: float, speed: float = FWD_SPEED_M_S, n: int = STEP
) -> tuple[np.ndarray, np.ndarray]:
    t = (np.arange(n) + 1 + k * n) / FS
    return t, np.column_stack([x0 + speed * t, np.full(n, y0), np.zeros(n)])


def _drive(fw: FloorWhiskers, steps: int, window_s: float | None = None) -> list[np.ndarray]:
    s = fw.arena.start
    return [fw.advance(*_straight(k, s.x_m, s.y_m), window_s=window_s) for k in range(steps)]


def _velocity_rms(hall: np.ndarray) -> float:
    """RMS of the Hall velocity (V/s) over samples, whiskers and channels."""
    h = np.moveaxis(np.asarray(hall, float), 0, -1)
    return float(vsig.velocity(h, FS, sigma_samples=3.0).std(axis=-1).mean())


def test_contact_is_held_throughout_on_a_flat_tile() -> None:
    fw = FloorWhiskers(_arena("vinyl", "vinyl"))
    hall = _drive(fw, 2)
    assert fw.last_contact_fraction == [1.0, 1.0]
    h = np.concatenate(hall)
    assert h.shape == (2 * STEP, 2, 2) and h.dtype == np.float32
    assert np.all(np.isfinite(h))
    # pressed on: deflected from the 2.5 V rest level all the time
    assert np.all(np.abs(h[:, :, 0] - 2.5) > 0.1)


def test_signal_rms_ranks_the_textures_as_the_roomba_floors() -> None:
    """Rough carpet > smooth carpet > vinyl, the order of the floors' relief."""
    rms = {}
    for tex in ("vinyl", "smooth-carpet", "rough-carpet"):
        fw = FloorWhiskers(_arena(tex, tex), seed=1)
        rms[tex] = _velocity_rms(np.concatenate(_drive(fw, 2))[STEP // 2 :])
    assert rms["rough-carpet"] > rms["smooth-carpet"] > rms["vinyl"]


def test_a_tile_boundary_changes_the_texture_mid_step() -> None:
    arena = _arena("vinyl", "smooth-carpet")
    fw = FloorWhiskers(arena)
    # the tips cross x = 0.5 m a quarter of a second into the second step
    x0 = 0.5 - FLOOR_WHISKERS_M[0, 0] - FWD_SPEED_M_S * 0.75
    t0, p0 = _straight(0, x0, 0.5)
    t1, p1 = _straight(1, x0, 0.5)
    fw.advance(t0, p0)
    assert fw.textures_at(p0[-1]) == ("vinyl", "vinyl")
    assert fw.last_segments[0] == ((0.0, "vinyl"),)
    h = fw.advance(t1, p1)
    assert fw.textures_at(p1[-1]) == ("smooth-carpet", "smooth-carpet")
    for w in range(2):
        (ta, a), (tb, b) = fw.last_segments[w]
        assert (a, b) == ("vinyl", "smooth-carpet")
        assert ta == pytest.approx(t0[-1]) and tb == pytest.approx(0.75, abs=2 / FS)
    assert fw.last_contact_fraction[0] > 0.95
    before, after = h[: STEP // 2 - 50], h[STEP // 2 + 150 :]
    assert _velocity_rms(after) > 1.5 * _velocity_rms(before)


def test_same_seed_same_bytes() -> None:
    def run(seed: int) -> bytes:
        fw = FloorWhiskers(_arena("vinyl", "vinyl"), seed=seed)
        return b"".join(h.tobytes() for h in _drive(fw, 2, window_s=None))

    assert run(4) == run(4)
    assert run(4) != run(5)


def test_window_mode_matches_continuous_statistics() -> None:
    """Each step's last 100 ms: the velocity RMS of window mode is that of a continuous
    run within 25 % (measured by scripts/floor_whisker_lead_in.py: within ~12 % on the
    three floors at the 0.15 s lead-in, over 20 steps)."""
    steps = 10
    cont = _drive(FloorWhiskers(_arena("vinyl", "vinyl"), seed=2), steps)
    win = _drive(FloorWhiskers(_arena("vinyl", "vinyl"), seed=2), steps, window_s=0.1)
    for h in win:
        assert np.all(np.isnan(h[:-200])) and np.all(np.isfinite(h[-200:]))
    ref = np.mean([_velocity_rms(h[-200:]) for h in cont[1:]])
    got = np.mean([_velocity_rms(h[-200:]) for h in win[1:]])
    assert got == pytest.approx(ref, rel=0.25)


def test_bad_input_is_refused() -> None:
    fw = FloorWhiskers(_arena("vinyl", "vinyl"))
    t, p = _straight(0, 0.3, 0.5, n=10)
    with pytest.raises(ValueError, match="pose must have shape"):
        fw.advance(t, p[:, :2])
    with pytest.raises(ValueError, match="one sample period"):
        fw.advance(t * 2, p)
    with pytest.raises(ValueError, match="finite"):
        fw.advance(t, np.where(p == p[3, 0], np.nan, p))
    with pytest.raises(ValueError, match="window_s"):
        fw.advance(t, p, window_s=0.0)
    fw.advance(t, p)
    with pytest.raises(ValueError, match="after the last call"):
        fw.advance(t, p)
    assert fw.advance(t[:0], p[:0]).shape == (0, 2, 2)
    with pytest.raises(ValueError, match="unknown floor texture"):
        FloorWhiskers(_arena("vinyl", "vinyl"), default_texture="lino")
    with pytest.raises(ValueError, match="seed"):
        FloorWhiskers(_arena("vinyl", "vinyl"), seed=-1)


def test_training_windows_carry_their_texture() -> None:
    windows, labels = collect_floor_training(("vinyl",), 0.25, seed=0)
    assert windows.shape == (4, 200, 2) and np.all(np.isfinite(windows))
    assert list(labels) == ["vinyl"] * 4
    with pytest.raises(ValueError, match="unknown floor texture"):
        collect_floor_training(("shag",), 0.25)


def test_texture_course_reports_every_100_ms() -> None:
    course = texture_course(("vinyl", "vinyl", "vinyl"), seconds=0.5)
    assert course.hall_v.shape == (1000, 2, 2)
    np.testing.assert_allclose(course.decision_time_s, [0.1, 0.2, 0.3, 0.4, 0.5])
    assert np.all(course.texture_true == "vinyl")
    assert np.isnan(course.accuracy())


def test_window_mode_takes_a_step_shorter_than_the_window() -> None:
    """A step cut short (the strain limit or the bumper stopped it after a few samples)
    still gives its samples: the lead-in reaches back into the previous step."""
    fw = FloorWhiskers(_arena("vinyl", "vinyl"), seed=2)
    s = fw.arena.start
    t, p = _straight(0, s.x_m, s.y_m)
    fw.advance(t, p, window_s=0.1)
    t2 = t[-1] + (np.arange(9) + 1) / FS
    p2 = np.column_stack([s.x_m + FWD_SPEED_M_S * t2, np.full(9, s.y_m), np.zeros(9)])
    h = fw.advance(t2, p2, window_s=0.1)
    assert h.shape == (9, 2, 2) and np.all(np.isfinite(h))
