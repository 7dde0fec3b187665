"""Training data collected on the simulated robot (6.5.4, 6.5.5.3) and the wiring."""

from __future__ import annotations

import math
import sys
import types

import numpy as np
import pytest

from vibrissa.robots.crunchbot import training
from vibrissa.robots.crunchbot.robot import RealtimeClassifiers


def test_radial_contacts_land_at_their_points_and_deflect_less_toward_the_tip() -> None:
    data = training.collect_radial_training(seed=1, contacts_per_point=1, whiskers=(1,))
    peak, dist = data[1]
    assert len(peak) == len(training.RADIAL_POINTS_M)
    np.testing.assert_allclose(dist, training.RADIAL_POINTS_M, atol=0.005)
    assert np.all(np.diff(peak) > 0)  # points listed tip first: the peak grows toward the base


def test_angle_drives_record_two_seconds_of_eight_channels_from_hit_1() -> None:
    recs, angles = training.collect_angle_training(seed=2, runs_per_angle=1,
                                                   angles_deg=np.array([40, 140]))
    assert recs.shape == (2, 4000, 8) and np.isfinite(recs).all()
    assert angles == pytest.approx(np.radians([40, 140]))
    touched = np.abs(recs).max(axis=1) > 0.05
    assert touched.any(axis=1).all()
    assert not np.array_equal(touched[0], touched[1])  # mirrored walls, other whiskers


def test_the_body_whisk_turns_toward_then_away_and_backs_off() -> None:
    cmds = training.body_whisk(toward=-1)
    assert [c.linear_m_s < 0 for c in cmds] == [True, False, False, True]
    assert cmds[1].angular_rad_s == pytest.approx(-math.pi / 24) and cmds[1].duration_s == 1.0
    assert sum(c.angular_rad_s * c.duration_s for c in cmds) == pytest.approx(0.0)


def test_train_classifiers_fits_one_radial_model_per_whisker(
        monkeypatch: pytest.MonkeyPatch) -> None:
    fitted: list = []

    class Model:
        def fit(self, *args):
            fitted.append((type(self).__name__, [np.shape(a) for a in args]))
            return self

    fake = types.ModuleType("vibrissa.classify.realtime")
    fake.FloorTextureNB = type("FloorTextureNB", (Model,), {})
    fake.RadialDistanceLinear = type("RadialDistanceLinear", (Model,), {})
    fake.SurfaceAngleTemplates = type("SurfaceAngleTemplates", (Model,), {})
    fake.peak_deflection = lambda h: 0.0
    floor = types.ModuleType("vibrissa.robots.crunchbot.floor_whiskers")
    floor.collect_floor_training = lambda textures, seconds, seed: (
        np.zeros((3, 200, 2)), ["vinyl"] * 3)
    monkeypatch.setitem(sys.modules, "vibrissa.classify.realtime", fake)
    monkeypatch.setitem(sys.modules, "vibrissa.robots.crunchbot.floor_whiskers", floor)
    monkeypatch.setattr(training, "collect_radial_training", lambda seed, n, peak: {
        w: (np.arange(3.0), np.arange(3.0)) for w in range(4)})
    monkeypatch.setattr(training, "collect_angle_training", lambda seed, n: (
        np.zeros((2, 4000, 8)), np.array([0.5, 1.0])))
    clf = training.train_classifiers(seed=0, quick=True)
    assert isinstance(clf, RealtimeClassifiers) and len(clf.radial) == 4
    names = [n for n, _ in fitted]
    assert names.count("RadialDistanceLinear") == 4
    assert ("SurfaceAngleTemplates", [(2, 4000, 8), (2,), ()]) in fitted
