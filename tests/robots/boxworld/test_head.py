"""Tests of vibrissa.robots.boxworld.head: poses, the head and its whiskers' frames."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.boxworld import HeadPose, WhiskingHead, whisker_frame


def test_pose_moves() -> None:
    p = HeadPose(10.0, 20.0, 90.0)
    q = p.moved(5.0, left_mm=2.0, turn_deg=10.0)
    assert (q.x_mm, q.y_mm, q.heading_deg) == pytest.approx((8.0, 25.0, 100.0))
    assert p.translated(1.0, -1.0) == HeadPose(11.0, 19.0, 90.0)
    with pytest.raises(TypeError, match="x_mm"):
        HeadPose("a", 0.0, 0.0)  # type: ignore[arg-type]


def test_default_head_sweeps_forward_on_the_right() -> None:
    head = WhiskingHead()
    pose = HeadPose(0.0, 0.0, 0.0)
    for i in range(head.n_whiskers):
        base, z, x = whisker_frame(pose, head, i)
        assert base[1] == pytest.approx(-40.0)  # on the right
        assert z[1] < 0.0  # pointing right
        assert float(z @ x) == pytest.approx(0.0, abs=1e-12)
        # protraction turns the whisker toward the heading (+x)
        t = math.radians(head.amplitude_deg)
        d = math.cos(t) * z + math.sin(t) * x
        assert d[0] > z[0]
        assert math.degrees(math.atan2(z[1], z[0])) == pytest.approx(-head.retracted_deg[i])
    assert head.length_mm == 185.0
    assert head.hall.sample_rate_hz == head.sample_rate_hz == 4000.0


def test_left_side_mirrors_the_right() -> None:
    pose = HeadPose(5.0, -3.0, 30.0)
    right, left = WhiskingHead(side=-1), WhiskingHead(side=1)
    h = np.radians(30.0)
    fwd = np.array([np.cos(h), np.sin(h)])
    for i in range(3):
        br, zr, xr = whisker_frame(pose, right, i)
        bl, zl, xl = whisker_frame(pose, left, i)
        # the same forward components, mirrored lateral ones
        assert float((br - pose.position_mm) @ fwd) == pytest.approx(
            float((bl - pose.position_mm) @ fwd)
        )
        assert float(zr @ fwd) == pytest.approx(float(zl @ fwd))
        assert float(xr @ fwd) == pytest.approx(float(xl @ fwd))


def test_contact_speeds_within_chapter_4_range() -> None:
    """The default whisk's fastest housing rate puts 80-185 mm contacts at <= 216 mm/s."""
    head = WhiskingHead()
    peak_rad_s = math.pi * head.frequency_hz * math.radians(head.amplitude_deg)
    assert 80.0 * peak_rad_s >= 36.0
    assert 185.0 * peak_rad_s <= 216.0


def test_head_validation() -> None:
    with pytest.raises(ValueError, match="pivots_mm"):
        WhiskingHead(n_whiskers=2)
    with pytest.raises(ValueError, match="amplitude_deg"):
        WhiskingHead(amplitude_deg=95.0)
    with pytest.raises(ValueError, match="side"):
        WhiskingHead(side=0)
    with pytest.raises(ValueError, match="whisker"):
        WhiskingHead(whisker="cat")
    with pytest.raises(ValueError, match="whisker index"):
        whisker_frame(HeadPose(), WhiskingHead(), 3)
