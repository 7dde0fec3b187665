"""The stage's point-to-point retract move against its analytic motion."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.robots.stage_motion import mi_axis_motion, trapezoid_breakpoints

DT = 1e-4


def _move(v=100.0, t_rev=0.05, vr=720.0, a=10_000.0, j=math.inf, x0=-1.0, x_end=-60.0, t_end=0.5):
    t = np.arange(0.0, t_end, DT)
    x, vel = mi_axis_motion(t, v, t_rev, vr, a, j, x0, x_end)
    return t, x, vel


def test_trapezoid_reaches_the_limit_and_stops_at_the_target():
    t, x, v = _move()
    # advance at 100 mm/s for 50 ms, brake at 10 m/s^2 (10 ms, 0.5 mm), reverse
    x_turn = -1.0 + 100.0 * 0.05 + 100.0**2 / (2 * 10_000.0)
    assert x.max() == pytest.approx(x_turn, abs=1e-3)
    assert v.min() == pytest.approx(-720.0, abs=1e-6)
    assert x[-1] == pytest.approx(-60.0, abs=2e-3)
    assert v[-1] == 0.0
    acc = np.diff(v) / DT
    assert np.abs(acc).max() <= 10_000.0 * (1 + 1e-6)
    # analytic duration: brake 10 ms + up 72 ms + cruise + down 72 ms
    back = x_turn + 60.0
    t_cruise = (back - 720.0**2 / 10_000.0) / 720.0
    t_stop = 0.05 + 0.01 + 2 * 0.072 + t_cruise
    moving = np.flatnonzero(v != 0.0)
    assert t[moving[-1]] == pytest.approx(t_stop, abs=2 * DT)


def test_a_short_move_is_a_triangle():
    tb, vb = trapezoid_breakpoints(0.0, 1.0, 720.0, 10_000.0)
    peak = math.sqrt(1.0 * 10_000.0)  # v = a t, distance a t^2 = 1 mm
    assert -vb.min() == pytest.approx(peak)
    assert tb[-1] == pytest.approx(2 * peak / 10_000.0)
    # the area under the velocity is the distance
    assert np.trapezoid(vb, tb) == pytest.approx(-1.0)


def test_finite_jerk_bounds_the_jerk_and_keeps_the_end_point():
    a, j = 10_000.0, 500_000.0  # T_j = 20 ms
    # a long move: its acceleration changes lie further apart than T_j
    t, x, v = _move(j=j, x_end=-150.0, t_end=0.8)
    t0, x0, v0 = _move(x_end=-150.0, t_end=0.8)
    acc = np.diff(v) / DT
    jerk = np.diff(acc) / DT
    assert np.abs(acc).max() <= a * (1 + 1e-6)
    assert np.abs(jerk).max() <= j * 1.01
    assert x[-1] == pytest.approx(x0[-1], abs=2e-3)
    # the S-curve ends T_j = a / j after its unsmoothed trapezoid, which cruises
    # v T_j / 2 further back (at 720 mm/s) to make up for the delayed braking
    end, end0 = t[np.flatnonzero(v)[-1]], t0[np.flatnonzero(v0)[-1]]
    assert end - end0 == pytest.approx(a / j + 100.0 * (a / j) / 2 / 720.0, abs=2 * DT)


@settings(max_examples=40, deadline=None)
@given(
    v=st.floats(1.0, 720.0),
    t_rev=st.floats(0.0, 0.2),
    a=st.floats(1_000.0, 50_000.0),
    back=st.floats(0.0, 50.0),
)
def test_any_move_ends_at_rest_at_its_target_within_its_limits(v, t_rev, a, back):
    total = back + v * t_rev + v * v / (2 * a)  # from the turning point to the target
    t = np.arange(0.0, t_rev + v / a + 2 * math.sqrt(total / a) + total / 720.0 + 0.01, 1e-4)
    x, vel = mi_axis_motion(t, v, t_rev, 720.0, a, math.inf, 0.0, -back)
    assert vel[-1] == 0.0
    assert x[-1] == pytest.approx(-back, abs=5e-3)
    assert vel.min() >= -720.0 - 1e-9 and vel.max() <= v + 1e-9


@pytest.mark.parametrize(
    ("kw", "name"),
    [
        ({"approach_mm_s": 0.0}, "approach_mm_s"),
        ({"acc_mm_s2": -1.0}, "acc_mm_s2"),
        ({"jerk_mm_s3": 0.0}, "jerk_mm_s3"),
    ],
)
def test_bad_parameters_are_refused_by_name(kw, name):
    args = dict(
        approach_mm_s=100.0,
        t_retract_s=0.0,
        retract_mm_s=720.0,
        acc_mm_s2=1e4,
        jerk_mm_s3=math.inf,
        x_start_mm=0.0,
        x_end_mm=-1.0,
    )
    args.update(kw)
    with pytest.raises(ValueError, match=name):
        mi_axis_motion(np.arange(0.0, 0.1, 1e-3), **args)
