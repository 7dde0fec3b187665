"""The simulated CrunchBot's run loop: the record, its log's rows, seeds, bad input."""

from __future__ import annotations

import time

import numpy as np
import pytest

from vibrissa.robots.crunchbot import fsm
from vibrissa.robots.crunchbot.arena import Arena, Pose
from vibrissa.robots.crunchbot.record import CLASSIFIERS
from vibrissa.robots.crunchbot.robot import RealtimeClassifiers, run_crunchbot

#: Starts 0.16 m from the right wall, heading for it: contact within a few steps.
NEAR_WALL = Arena(
    "near-wall",
    1.25,
    Pose(0.8, 0.6, 0.0),
    tiles=(("vinyl", "rough-carpet"), ("smooth-carpet", "vinyl")),
    tile_m=0.625,
)


@pytest.fixture(scope="module")
def truth_run():
    return run_crunchbot(NEAR_WALL, 4.0, seed=2, floor="off")


def test_bad_input_is_one_line() -> None:
    for kw in ({"seconds": 0.0}, {"seconds": -1.0}, {"seconds": 1.0, "floor": "sometimes"}):
        with pytest.raises(ValueError) as err:
            run_crunchbot(NEAR_WALL, **kw)
        assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="floor"):
        run_crunchbot(NEAR_WALL, 1.0, floor="sometimes")


def test_record_shapes_and_floor_off(truth_run) -> None:
    rec = truth_run
    n = len(rec.time_s)
    assert rec.hall_v.dtype == np.float32 and rec.hall_v.shape == (n, 6, 2)
    assert rec.pose.shape == (n, 3) and rec.step_start[-1] == n
    assert np.isnan(rec.hall_v[:, 4:]).all() and np.isfinite(rec.hall_v[:, :4]).all()
    assert rec.log.floor_loglik is None
    assert rec.seconds >= 4.0
    # the log's true pose is the record's pose at the step boundaries, in the map frame
    off = NEAR_WALL.map_offset_m(2.5, 0.05)
    ends = rec.step_start[1:] - 1
    moved = np.diff(rec.step_start) > 0
    np.testing.assert_allclose(rec.log.true_pose[1:][moved, :2] - off, rec.pose[ends[moved], :2])


def test_truth_mode_logs_true_distances_and_zero_length_hit_rows(truth_run) -> None:
    rec = truth_run
    states = list(rec.log.state)
    assert fsm.HIT_1 in states and fsm.FWD_2 in states
    lengths = np.diff(rec.step_start)
    for i, s in enumerate(states):
        if s in (fsm.HIT_1, fsm.HIT_2, fsm.ABORT):
            assert lengths[i] == 0
            np.testing.assert_array_equal(rec.log.contact[i], rec.log.contact[i - 1])
    moved = lengths > 0
    c = rec.log.contact[moved]
    np.testing.assert_allclose(rec.log.radial_distance_m[moved][c], rec.contact_true_m[moved][c])
    assert np.isnan(rec.log.surface_angle_rad).all()
    assert all(len(rec.latency_s[k]) == 0 for k in CLASSIFIERS)


def test_same_seed_same_bytes(truth_run) -> None:
    again = run_crunchbot(NEAR_WALL, 4.0, seed=2, floor="off")
    assert again.hall_v.tobytes() == truth_run.hall_v.tobytes()
    assert again.log.odometry.tobytes() == truth_run.log.odometry.tobytes()
    other = run_crunchbot(NEAR_WALL, 4.0, seed=3, floor="off")
    assert other.hall_v.tobytes() != truth_run.hall_v.tobytes()


def test_whiskers_on_threads_give_the_same_bytes(truth_run, monkeypatch) -> None:
    # the truth run used this machine's cores; one thread must give the same record
    import vibrissa.robots.crunchbot.obstacle_whiskers as ow

    monkeypatch.setattr(ow, "default_workers", lambda: 1)
    alone = run_crunchbot(NEAR_WALL, 4.0, seed=2, floor="off")
    assert alone.hall_v.tobytes() == truth_run.hall_v.tobytes()
    assert alone.contact_true_m.tobytes() == truth_run.contact_true_m.tobytes()


class _FakeFloor:
    """Stands in for helper B's FloorWhiskers: a constant signal per texture."""

    def __init__(self, arena, rate, seed) -> None:
        self.arena = arena

    def advance(self, time_s, pose, window_s=None):
        out = np.full((len(time_s), 2, 2), 2.5, np.float32)
        out[:, :, 0] += 0.1 * (pose[:, 0] > 0.625)[:, None]
        return out


class _Nb:
    classes_ = ("rough-carpet", "vinyl")

    def loglik(self, window):
        assert window.shape == (200, 2)
        return np.array([window[:, 0].mean(), -window[:, 0].mean()])


class _Radial:
    peaks: list[float] = []  # every peak deflection the loop asked about (V)

    def predict(self, peak):
        self.peaks.append(float(peak))
        return 0.1


class _Angle:
    def predict(self, rec):
        assert rec.shape[1] == 8
        return 1.2


def test_classifiers_are_called_and_timed() -> None:
    _Radial.peaks.clear()
    clf = RealtimeClassifiers(floor=_Nb(), radial=(_Radial(),) * 4, angle=_Angle())
    rec = run_crunchbot(
        NEAR_WALL, 4.0, seed=2, classifiers=clf, floor="continuous", floor_factory=_FakeFloor
    )
    assert np.isfinite(rec.hall_v).all()
    assert rec.log.textures == _Nb.classes_ and rec.log.floor_loglik.shape[1:] == (2, 2)
    c = rec.log.contact
    assert c.any() and np.all(rec.log.radial_distance_m[c] == 0.1)
    assert len(rec.latency_s["radial_distance"]) > 0 and len(rec.latency_s["floor_texture"]) > 0
    # the radial feature is the deflection about the sensor's rest output: from 0 up to
    # the rail, never the rest voltage counted twice (which gave ~3.5 V for every step)
    peaks = np.array(_Radial.peaks)
    assert peaks.size and np.all((peaks >= 0) & (peaks < 2.5)) and peaks.max() > 0.01
    hit2 = rec.log.state == fsm.HIT_2
    assert np.all(np.isnan(rec.log.surface_angle_rad[~hit2]))
    if hit2.any():
        assert np.allclose(rec.log.surface_angle_rad[hit2], 1.2)
    assert set(rec.floor_texture_pred.ravel()) <= {"", *_Nb.classes_}


class _RampFloor(_FakeFloor):
    """A floor signal that differs at every sample, so a window read from the wrong
    samples gives another report."""

    def advance(self, time_s, pose, window_s=None):
        out = np.empty((len(time_s), 2, 2), np.float32)
        out[:] = (1.0 + np.asarray(time_s, np.float32))[:, None, None]
        out[:, 1] *= 2.0
        return out


def test_the_floor_report_of_each_step_reads_that_steps_latest_window() -> None:
    # the floor whiskers run beside the next step's obstacle whiskers: each row must
    # still carry the classifier's report on the 200 samples ending with its own step
    # (or the report before it when its step gave no full window)
    rec = run_crunchbot(
        NEAR_WALL,
        4.0,
        seed=2,
        classifiers=RealtimeClassifiers(floor=_Nb(), radial=(_Radial(),) * 4, angle=None),
        floor="continuous",
        floor_factory=_RampFloor,
    )
    floor = rec.hall_v[:, 4:6].astype(float)
    expected, last = [], np.zeros((2, 2))
    for j in range(len(rec.log.state)):
        end = rec.step_start[j + 1]
        if end > rec.step_start[j] and end >= 200:
            window = floor[end - 200 : end]
            last = np.stack([_Nb().loglik(window[:, k]) for k in range(2)])
        expected.append(last)
    assert len({float(x) for x in rec.log.floor_loglik[:, 0, 0]}) > 5
    np.testing.assert_array_equal(rec.log.floor_loglik, np.array(expected))
    assert len(rec.latency_s["floor_texture"]) == 2 * sum(
        e > s and e >= 200 for s, e in zip(rec.step_start[:-1], rec.step_start[1:], strict=True)
    )


class _SlowFloor(_FakeFloor):
    running = False

    def advance(self, time_s, pose, window_s=None):
        _SlowFloor.running = True
        time.sleep(0.05)  # longer than an obstacle step near the wall
        _SlowFloor.running = False
        return super().advance(time_s, pose, window_s)


class _Watching:
    """Classifiers that note whether a floor simulation ran while they were called."""

    overlaps = 0
    calls = 0

    def _check(self) -> None:
        _Watching.calls += 1
        _Watching.overlaps += int(_SlowFloor.running)

    def loglik(self, window):
        self._check()
        return _Nb().loglik(window)

    def predict(self, x):
        self._check()
        return 1.2 if np.ndim(x) == 2 else 0.1


def test_no_floor_simulation_runs_while_a_classifier_is_timed() -> None:
    _Watching.overlaps = _Watching.calls = 0
    w = _Watching()
    w.classes_ = _Nb.classes_
    run_crunchbot(
        NEAR_WALL,
        4.0,
        seed=2,
        floor="window",
        floor_factory=_SlowFloor,
        classifiers=RealtimeClassifiers(floor=w, radial=(w,) * 4, angle=w),
    )
    assert _Watching.calls > 10 and _Watching.overlaps == 0
