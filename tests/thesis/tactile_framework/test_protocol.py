"""The closed loop of the tactile framework: calibration, episodes, policies, the dataset."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.robots.boxworld import box_world, first_contact
from vibrissa.thesis.tactile_framework.protocol import (
    KIND_CODES,
    FrameworkProtocol,
    angle_class,
    framework_protocol,
    radial_class,
)


def test_classes():
    assert angle_class(44.0) == 45.0 and angle_class(-3.0) == -15.0 and angle_class(61.0) == 75.0
    # a tip contact is the length; a corner its 20 mm bin, kept out of the tip zone
    assert radial_class("tip", 185.0, 185.0, 5.0) == 185.0
    assert radial_class("shaft", 121.0, 185.0, 5.0) == 130.0
    assert radial_class("shaft", 183.0, 185.0, 5.0) == 170.0


def test_bad_parameters_are_refused_by_name():
    for kw, name in (
        ({"n_episodes": 0}, "n_episodes"),
        ({"step_mm": -1.0}, "step_mm"),
        ({"odometry_noise": 1.5}, "odometry_noise"),
        ({"world": "moon"}, "moon"),
        ({"seed": -1}, "seed"),
    ):
        with pytest.raises(ValueError, match=name):
            FrameworkProtocol(**kw)


def test_episode_starts_are_clear_and_in_reach():
    p = framework_protocol(quick=True)
    world = box_world(p.world)
    for i in range(4):
        pose = p.episode_start(i)
        geo = [first_contact(world, pose, p.head, w) for w in range(p.head.n_whiskers)]
        assert not any(g is not None and g.kind == "pressed" for g in geo)
        assert world.clearance_mm((pose.x_mm, pose.y_mm)) > 150.0
    assert p.episode_start(2) == p.episode_start(2)


@pytest.fixture(scope="module")
def small():
    """A tiny session: two calibration patrols, one episode per policy."""
    p = framework_protocol(quick=True, n_calibration=40, n_episodes=1, n_whisks=6)
    calib = p.calibrate(workers=1)
    pipe = p.fit_pipeline(calib)
    episodes = [p.run_episode(pol, 0, pipe) for pol in ("passive", "active", "oracle")]
    return p, calib, pipe, episodes


def test_calibration_contacts_are_labelled_from_the_truth(small):
    p, calib, _, _ = small
    n = calib["kind"].size
    assert n >= 4 and calib["window"].shape == (n, 2, int(0.4 * p.head.sample_rate_hz))
    tip = calib["kind"] == KIND_CODES["tip"]
    assert np.all(calib["radial_class_mm"][tip] == p.length_mm)
    assert np.all(calib["radial_class_mm"][~tip] < p.tip_radial_distance_mm)
    assert np.all(np.isin(calib["texture_code"][tip], [0, 1, 2, 3]))
    assert np.all(calib["texture_code"][~tip] == -1)


def test_episodes_report_every_contact_with_its_window_and_posterior(small):
    p, _, pipe, episodes = small
    n_classes = pipe.what.estimator.classes_.shape[0]
    for e in episodes:
        assert len(e["moves"]) >= p.n_whisks
        for r in e["rows"]:
            assert r["window"].shape[0] == 2
            assert r["what_log_proba"].shape == (n_classes,)
            assert 0.0 <= r["p_tip"] <= 1.0
            assert r["tip"] == (r["p_tip"] >= 0.5)


def test_policies_share_starts_and_only_active_and_oracle_reposition(small):
    _, _, _, episodes = small
    passive, active, oracle = episodes
    first = [e["moves"][0] for e in episodes]
    # every policy's first whisk is the same (same start, same noise streams)
    if passive["rows"] and active["rows"]:
        assert passive["rows"][0]["onset_s"] == active["rows"][0]["onset_s"]
    assert all(m["kind"] != 1 for m in passive["moves"])
    for e in (active, oracle):
        shafts = [r for r in e["rows"] if (not r["tip"] if e is active else r["truth_kind"] == 2)]
        repositions = [m for m in e["moves"] if m["kind"] == 1]
        assert bool(repositions) == bool(shafts)
    assert {m["episode"] for m in first} == {0}


def test_the_dataset_holds_calibration_trials_episodes_and_ground_truth(small):
    p, calib, pipe, episodes = small
    ds = p.build_dataset(calib, episodes, pipe)
    assert ds.sizes["trial"] == calib["kind"].size
    assert ds["ep_window"].dims == ("contact", "channel", "time")
    assert ds["gt_occupancy"].shape == ds["gt_texture_code"].shape
    assert int(ds["gt_arena"].sum()) > 0
    assert float(ds.attrs["gt_cell_mm"]) == 25.0
    assert (
        p.fingerprint()
        == framework_protocol(quick=True, n_calibration=40, n_episodes=1, n_whisks=6).fingerprint()
    )
