"""The Roomba's kinematics and one recorded floor trial (thesis 6.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.robots.roomba import (
    CATCH_MIN_S,
    CONDITIONS,
    Roomba,
    _runs,
    base_motion,
    floor_slide,
    run_floor_trial,
    tip_path,
)
from vibrissa.signal import PACKET_SAMPLES, active_packets
from vibrissa.whisker.floors import FLOORS, make_floor
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSettings
from vibrissa.whisker.rod import RodModel


def _rng(k: int = 0) -> np.random.Generator:
    return np.random.default_rng(k)


@pytest.mark.parametrize("condition, sign", [("anticlockwise", 1.0), ("clockwise", -1.0)])
def test_spinning_in_place_at_the_wheel_speed(condition, sign):
    r = Roomba()
    t, fwd, yaw = base_motion(r, condition, 4.0, _rng())
    delay = _rng().uniform(*r.start_delay_s)  # the first draw of the trial's stream
    assert np.all(fwd == 0.0)
    assert np.all(yaw[t < delay] == 0.0)
    full = 2.0 * r.spin_wheel_speed_mm_s / r.wheel_base_mm
    assert yaw[-1] == pytest.approx(sign * full)


def test_turning_anticlockwise_the_whisker_trails_clockwise_it_leads():
    r = Roomba()
    t = np.array([0.0, 1.0])
    ccw = floor_slide(r, 200.0, t, np.zeros(2), np.array([0.5, 0.5]))
    cw = floor_slide(r, 200.0, t, np.zeros(2), np.array([-0.5, -0.5]))
    assert ccw[0][0] == pytest.approx(0.5 * r.mount_radius_mm) and ccw[0][0] > 0
    assert cw[0][0] == pytest.approx(-ccw[0][0])
    reach = 200.0 * math.cos(math.radians(r.tilt_deg))
    assert ccw[1][0] == pytest.approx(0.5 * reach) and cw[1][0] == pytest.approx(-0.5 * reach)
    # driving straight ahead the floor runs from base to tip, with no lateral slide
    along, across = floor_slide(r, 200.0, t, np.full(2, 100.0), np.zeros(2))
    assert along[0] == 100.0 and across[0] == 0.0


def test_spot_is_an_outward_spiral_that_varies_from_run_to_run():
    r = Roomba()
    t, fwd, yaw = base_motion(r, "spot", 16.0, _rng(1))
    moving = fwd == fwd.max()
    assert np.all(np.diff(np.abs(yaw[moving])) <= 1e-12)  # curvature falls: radius grows
    t2, fwd2, yaw2 = base_motion(r, "spot", 16.0, _rng(2))
    assert not np.allclose(yaw, yaw2)
    np.testing.assert_array_equal(yaw, base_motion(r, "spot", 16.0, _rng(1))[2])


def test_the_tip_circles_the_turning_centre_when_spinning():
    r = Roomba()
    t, fwd, yaw = base_motion(r, "clockwise", 8.0, _rng())
    x, y = tip_path(r, 200.0, t, fwd, yaw)
    reach = 200.0 * math.cos(math.radians(r.tilt_deg))
    np.testing.assert_allclose(np.hypot(x, y), math.hypot(reach, r.mount_radius_mm))


def test_unknown_condition_and_bad_mounting_are_refused():
    with pytest.raises(ValueError, match="unknown condition 'zigzag'"):
        base_motion(Roomba(), "zigzag", 1.0, _rng())
    with pytest.raises(ValueError, match="tilt_deg"):
        Roomba(tilt_deg=95.0)
    with pytest.raises(ValueError, match="start_delay_s"):
        Roomba(start_delay_s=(2.0, 1.0))
    assert CONDITIONS == ("clockwise", "anticlockwise", "spot")


def test_a_short_trial_is_quiet_until_the_robot_moves():
    g = preset("scratchbot")
    model = RodModel(g, 16)
    sensor = HallSettings(sample_rate_hz=2000.0, calibration_mm=(150.0, 30.0)).calibrate(g, 16)
    r = Roomba(start_delay_s=(0.5, 0.5))
    res = run_floor_trial(
        r,
        model,
        sensor,
        make_floor("tarmac", 0, 40.0, 40.0),
        FLOORS["tarmac"],
        "anticlockwise",
        1.5,
        _rng(3),
    )
    assert res.signal_v.shape == (2, 3000)
    assert res.contact_fraction > 0.9  # pressed on the floor throughout
    keep = active_packets(res.signal_v)
    still = int(0.5 * 2000) // PACKET_SAMPLES
    assert not keep[:still].any()  # at rest on the floor: only sensor noise
    assert keep[still + 2 :].mean() > 0.8  # dragged over tarmac
    assert res.moving_fraction == pytest.approx(1.0 / 1.5, abs=0.01)


@settings(max_examples=40, deadline=None)
@given(
    yaw_deg=st.floats(-90.0, 90.0),
    tilt_deg=st.floats(5.0, 80.0),
    omega=st.floats(-2.0, 2.0),
    forward=st.floats(0.0, 300.0),
)
def test_the_floor_slide_is_the_tip_s_motion_over_the_floor_reversed(
    yaw_deg, tilt_deg, omega, forward
):
    """Whatever the mount, the slide is minus the nominal tip's velocity in the whisker frame."""
    r = Roomba(mount_yaw_deg=yaw_deg, tilt_deg=tilt_deg)
    t = np.array([0.0, 1e-4])
    fwd, yaw = np.full(2, forward), np.full(2, omega)
    x, y = tip_path(r, 200.0, t, fwd, yaw)
    v_tip = np.array([x[1] - x[0], y[1] - y[0]]) / 1e-4  # robot heading 0 at t = 0
    psi = math.radians(yaw_deg)
    d = np.array([-math.cos(psi), -math.sin(psi)])  # from the base toward the tip
    e = np.array([-math.sin(psi), math.cos(psi)])  # the whisker's y, seen from above
    along, across = floor_slide(r, 200.0, t, fwd, yaw)
    assert along[0] == pytest.approx(-v_tip @ d, abs=0.05 + 1e-3 * abs(v_tip).max())
    assert across[0] == pytest.approx(-v_tip @ e, abs=0.05 + 1e-3 * abs(v_tip).max())


def test_pointing_outward_both_turns_slide_the_floor_across_as_mirror_images():
    r = Roomba(mount_yaw_deg=90.0)
    t = np.array([0.0, 1.0])
    ccw = floor_slide(r, 200.0, t, np.zeros(2), np.array([0.5, 0.5]))
    cw = floor_slide(r, 200.0, t, np.zeros(2), np.array([-0.5, -0.5]))
    assert ccw[0][0] == pytest.approx(0.0, abs=1e-9) and cw[0][0] == pytest.approx(0.0, abs=1e-9)
    assert cw[1][0] == pytest.approx(-ccw[1][0]) and ccw[1][0] > 0
    with pytest.raises(ValueError, match="mount_yaw_deg"):
        Roomba(mount_yaw_deg=120.0)


def test_stick_runs_are_counted_in_samples():
    mask = np.array([0, 1, 1, 0, 1, 0, 0, 1, 1, 1], dtype=bool)
    np.testing.assert_array_equal(_runs(mask), [2, 1, 3])
    assert _runs(np.zeros(4, dtype=bool)).size == 0


def _short_trial(floor: str, condition: str, seconds: float = 1.2):
    g = preset("scratchbot")
    sensor = HallSettings(sample_rate_hz=2000.0, calibration_mm=(150.0, 30.0)).calibrate(g, 16)
    return run_floor_trial(
        Roomba(start_delay_s=(0.0, 0.0)),
        RodModel(g, 16),
        sensor,
        make_floor(floor, 0, 40.0, 40.0),
        FLOORS[floor],
        condition,
        seconds,
        _rng(5),
    )


def test_the_leading_tip_catches_in_rough_carpet_loops_and_not_on_vinyl():
    carpet = _short_trial("rough-carpet", "clockwise")
    assert carpet.catches >= 1 and carpet.catch_fraction >= CATCH_MIN_S / 1.2
    assert carpet.rail_fraction > 0.0  # the caught whisker drives the sensor to a rail
    vinyl = _short_trial("vinyl", "clockwise")
    assert vinyl.catches == 0 and vinyl.catch_fraction == 0.0 and vinyl.rail_fraction == 0.0
    assert carpet.contact_force_n > 2.0 * vinyl.contact_force_n > 0.0  # jammed into a loop
