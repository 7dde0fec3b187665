"""A surface sliding across the whisker's bending plane (Trajectory.lateral_mm)."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import SurfaceContact, Trajectory, simulate
from vibrissa.whisker.surfaces import Surface


def test_lateral_motion_is_checked_and_sampled():
    t = np.array([0.0, 1.0, 2.0])
    p = np.zeros((3, 2))
    tr = Trajectory(t, p, lateral_mm=np.array([0.0, 2.0, 6.0]))
    y, vy = tr.sample_lateral(np.array([0.5, 1.5]))
    np.testing.assert_allclose(y, [1.0, 4.0])
    np.testing.assert_allclose(vy, np.interp([0.5, 1.5], t, np.gradient([0.0, 2.0, 6.0], t)))
    y0, vy0 = Trajectory(t, p).sample_lateral(np.array([0.5]))
    assert y0[0] == 0.0 and vy0[0] == 0.0
    with pytest.raises(ValueError, match="lateral_mm must have shape"):
        Trajectory(t, p, lateral_mm=np.zeros(2))
    with pytest.raises(ValueError, match="needs lateral_mm"):
        Trajectory(t, p, lateral_velocity_mm_s=np.zeros(3))


def _drag(lateral_speed_mm_s: float) -> np.ndarray:
    """Mean magnet tangents of a whisker pressed 10 mm into a flat plane at 30 deg
    while the plane slides sideways at ``lateral_speed_mm_s``."""
    g = preset("scratchbot")
    model = RodModel(g, 12)
    flat = Surface(np.zeros((8, 8)), 1e-3, friction=0.5)
    c = SurfaceContact(flat, angle_deg=30.0)
    n, _, _ = c.frame()
    tip = np.array([0.0, 0.0, g.length_mm])
    t = np.linspace(0.0, 1.0, 101)
    press = np.clip(t / 0.3, 0.0, 1.0)[:, None]
    origin = tip - n * (2.0 + g.tip_radius_mm) + n * 12.0 * press
    slide = np.where(t > 0.4, (t - 0.4) * lateral_speed_mm_s, 0.0)
    res = simulate(model, c, Trajectory(t, origin[:, [0, 2]], lateral_mm=slide), 1.0)
    return res.tan_xy[res.time_s > 0.8].mean(axis=0)


def test_sliding_sideways_drags_the_whisker_sideways_by_friction():
    still, left, right = _drag(0.0), _drag(100.0), _drag(-100.0)
    assert abs(still[1]) < 1e-6
    assert abs(left[1]) > 1e-3
    assert right[1] == pytest.approx(-left[1], rel=0.05)
    assert np.sign(left[1]) != np.sign(right[1])
