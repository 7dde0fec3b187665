"""``ClosedLoopStepper``: simulate() a control period at a time, set up once.

The stepper must give the numbers of the chain of ``simulate`` calls it replaces in the
whisking loops (each period from the last one's ``final_state``, the housing's motion
as a ``BaseMotion``, no linear free flight), bit for bit: against a pole the whisker
whisks into, against a textured plane, and in free air.
"""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import (
    BaseMotion,
    ClosedLoopStepper,
    PoleContact,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import make_surface

DT = 2.5e-4
SPP = 4  # steps per control period: 1 kHz control


@pytest.fixture(scope="module")
def model() -> RodModel:
    return RodModel(preset("xy-robot"))


def _whisk(n_periods: int, amplitude_deg: float = 40.0) -> tuple[np.ndarray, ...]:
    t = np.arange(n_periods * SPP + 1) * DT
    angle = np.radians(amplitude_deg) * np.sin(2 * np.pi * 2.0 * t)
    return t, angle, np.gradient(angle, t)


def _by_simulate(model, contact, trajectory, n_periods):
    t, angle, rate = _whisk(n_periods)
    state, rows = None, []
    for k in range(n_periods):
        sl = slice(k * SPP, (k + 1) * SPP + 1)
        res = simulate(
            model,
            contact,
            trajectory,
            SPP * DT,
            DT,
            initial_state=state,
            base_motion=BaseMotion(t[sl], angle[sl], rate[sl]),
            linear_free_flight=False,
        )
        state = res.final_state
        rows.append(np.column_stack([res.time_s, res.tan_xy, res.contact_force_n]))
    return np.concatenate(rows), state


def _by_stepper(model, contact, trajectory, n_periods):
    t, angle, rate = _whisk(n_periods)
    stepper = ClosedLoopStepper(model, contact, trajectory, DT)
    assert stepper.state is None
    rows = []
    for k in range(n_periods):
        sl = slice(k * SPP, (k + 1) * SPP + 1)
        out = stepper.advance(SPP, t[sl], angle[sl], rate[sl])
        rows.append(np.column_stack([out.time_s, out.tan_xy, out.contact_force_n]))
    return np.concatenate(rows), stepper.state


def _pole():
    # a pole 120 mm out, 60 mm to the side of the rest axis: a 40 deg whisk reaches it
    return PoleContact(), Trajectory(np.array([0.0, 10.0]), np.array([[60.0, 120.0]] * 2))


def _moving_pole():
    # the same pole coming in at 100 mm/s while the whisker whisks (not a still object)
    return PoleContact(), Trajectory.linear((75.0, 120.0), (-100.0, 0.0), 0.2)


def _plane():
    # a textured plane at 45 deg facing -x, its base point 15 mm to the +x side of the
    # rest axis at r = 175 mm: the whisk's swing toward +x presses the shaft into it
    contact = SurfaceContact(make_surface("p80", seed=1), angle_deg=45.0, side=-1)
    return contact, Trajectory(np.array([0.0, 10.0]), np.array([[15.0, 175.0]] * 2))


@pytest.mark.parametrize(
    "setup",
    [_pole, _moving_pole, _plane, lambda: (None, None)],
    ids=["pole", "moving pole", "plane", "air"],
)
def test_the_stepper_is_simulate_period_by_period_bit_for_bit(model, setup):
    contact, trajectory = setup()
    a, state_a = _by_simulate(model, contact, trajectory, 120)
    b, state_b = _by_stepper(model, contact, trajectory, 120)
    np.testing.assert_array_equal(a, b)
    for name in ("positions_m", "velocities_m_s", "accelerations_m_s2", "pole_anchor"):
        np.testing.assert_array_equal(getattr(state_a, name), getattr(state_b, name))
    assert state_b.time_s == state_a.time_s


@pytest.mark.parametrize(
    "setup", [_pole, _moving_pole, _plane], ids=["pole", "moving pole", "plane"]
)
def test_the_object_is_touched(model, setup):
    # the comparison above means something only if the whisk reaches the object
    rows, _ = _by_stepper(model, *setup(), 120)
    assert rows[:, 3].max() > 1e-3  # N


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"n_steps": 0}, "n_steps"),
        ({"n_steps": True}, "n_steps"),
        ({"base_time_s": np.zeros(3)}, "one length"),
        ({"base_angle_rad": np.zeros((5, 1))}, "one length"),
    ],
)
def test_bad_periods_are_refused_by_name(model, kwargs, match):
    stepper = ClosedLoopStepper(model, None, None, DT)
    t, angle, rate = _whisk(1)
    args = {"n_steps": SPP, "base_time_s": t, "base_angle_rad": angle, "base_rate_rad_s": rate}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        stepper.advance(**args)
    assert stepper.state is None and stepper.time_s == 0.0


@pytest.mark.parametrize(
    "kwargs, match",
    [({"dt_s": 0.0}, "dt_s"), ({"dt_s": 2e-3}, "dt_s"), ({"max_iterations": 0}, "max_iterations")],
)
def test_bad_settings_are_refused_by_name(model, kwargs, match):
    with pytest.raises(ValueError, match=match):
        ClosedLoopStepper(model, None, None, **kwargs)


@pytest.mark.parametrize("setup", [_pole, lambda: (None, None)], ids=["pole", "air"])
def test_the_sampled_period_is_the_interpolated_one(model, setup):
    # advance_sampled (the housing's motion given at the steps) against advance (given at
    # times it interpolates at the stepper's own clock, which overshoots the period's
    # last sample by an ulp in most periods): the same numbers, to the rounding of that
    # interpolation, well within the Newton tolerance (before the fix, advance read a
    # zero rate at those overshoots); not on the textured plane, whose grains amplify a
    # difference at the tolerance into a different stick-slip history
    t, angle, rate = _whisk(120)
    a = ClosedLoopStepper(model, *setup(), DT)
    b = ClosedLoopStepper(model, *setup(), DT)
    for k in range(120):
        sl = slice(k * SPP, (k + 1) * SPP + 1)
        pa = a.advance(SPP, t[sl], angle[sl], rate[sl])
        pb = b.advance_sampled(angle[sl], rate[sl])
        np.testing.assert_allclose(pa.tan_xy, pb.tan_xy, rtol=1e-6, atol=1e-12)
        np.testing.assert_allclose(pa.contact_force_n, pb.contact_force_n, rtol=1e-6, atol=1e-9)
    assert a.time_s == b.time_s


def test_a_sampled_period_of_mismatched_arrays_is_refused(model):
    stepper = ClosedLoopStepper(model, None, None, DT)
    with pytest.raises(ValueError, match="one length"):
        stepper.advance_sampled(np.zeros(5), np.zeros(4))
    with pytest.raises(ValueError, match="a still object"):
        ClosedLoopStepper(model, *_moving_pole(), DT).kernel_inputs(0.0, 0.0)


def test_kernel_inputs_are_the_steppers_own_state(model):
    # a driver that integrates the stepper's whisker outside advance works on the same
    # arrays, at rest in the housing's angle, and moves the clock afterwards
    stepper = ClosedLoopStepper(model, *_pole(), DT)
    k = stepper.kernel_inputs(0.1, 0.0)
    assert stepper.state is not None
    np.testing.assert_array_equal(k.state.x, stepper.state.positions_m)
    assert k.object_row.shape == (6,) and k.object_row[0] == pytest.approx(0.06)
    k.state.x[-1, 0] += 1e-3
    assert stepper.state.positions_m[-1, 0] == k.state.x[-1, 0]
    stepper.advance_clock(8)
    assert stepper.time_s == pytest.approx(8 * DT)
