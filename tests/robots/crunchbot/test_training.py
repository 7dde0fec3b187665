"""Training data collected on the simulated robot (6.5.4, 6.5.5.3) and the wiring."""

from __future__ import annotations

import math

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
    recs, angles = training.collect_angle_training(
        seed=2, runs_per_angle=1, angles_deg=np.array([40, 140])
    )
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
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The wiring: each collection feeds its classifier (collections replaced by data of
    known shape, the classifiers real)."""
    rng = np.random.default_rng(0)
    asked: dict = {}

    def floor(textures, seconds, seed):
        asked["textures"] = textures
        labels = [t for t in textures for _ in range(4)]
        return rng.normal(size=(len(labels), 200, 2)) + np.repeat(np.arange(len(textures)), 4)[
            :, None, None
        ], labels

    monkeypatch.setattr(
        training,
        "collect_radial_training",
        lambda seed, n: {w: (np.arange(3.0), 0.1 + 0.01 * np.arange(3.0)) for w in range(4)},
    )
    monkeypatch.setattr(
        training,
        "collect_angle_training",
        lambda seed, n: (rng.normal(size=(2, 4000, 8)), np.array([0.5, 1.0])),
    )
    monkeypatch.setattr(training, "collect_floor_training", floor)
    clf = training.train_classifiers(seed=0, quick=True)
    assert isinstance(clf, RealtimeClassifiers) and len(clf.radial) == 4
    assert clf.radial[2].predict(1.0) == pytest.approx(0.11)
    assert asked["textures"] == training.TILE_TEXTURES
    assert set(clf.floor.classes_) == set(training.TILE_TEXTURES)
    assert clf.angle.predict(rng.normal(size=(100, 8))) in (0.5, 1.0)
