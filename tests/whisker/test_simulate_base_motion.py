"""Whisking: the follicle housing turned by a motor (``simulate(..., base_motion=...)``).

Checked against analytics: zero rotation is the fixed follicle to the byte; a slow
constant-rate rotation is followed rigidly with the lag of the derivation below; a
quick step of the housing rings at the first damped natural frequency with the
configured damping ratio; a run cut into pieces resumes where it stopped.

Lag of a constant-rate rotation: turning at ``Omega`` about the pivot, the whisker
moves rigidly with the housing. The follicle damper acts on the rate *relative* to
the housing (zero), the shaft damping is objective (zero for a rigid rotation), so
the only torque to balance is the mass-proportional drag ``alpha m_i v_i`` with
``v_i = Omega r_i``: ``k_f sin(psi) = alpha Omega sum_i m_i r_i^2`` -- the magnet
trails the housing by ``psi = alpha I_p Omega / k_f`` (``I_p`` the moment of inertia
about the pivot), and by nothing when ``alpha = 0``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import MASS_KINDS, RodModel
from vibrissa.whisker.simulate import BaseMotion, PoleContact, Trajectory, simulate


@pytest.fixture(scope="module")
def model() -> RodModel:
    return RodModel(preset("scratchbot"))


def _ramp(t0: float, rise: float, angle: float, end: float = 5.0) -> BaseMotion:
    t = np.linspace(0.0, end, int(end / 2.5e-4) + 1)
    return BaseMotion(t, angle * np.clip((t - t0) / rise, 0.0, 1.0))


def test_zero_rotation_gives_the_fixed_follicle_bytes(model):
    traj = Trajectory.linear((-5.0, 120.0), (60.0, 0.0), 0.35)
    fixed = simulate(model, PoleContact(), traj, 0.35, linear_free_flight=False)
    still = simulate(
        model,
        PoleContact(),
        traj,
        0.35,
        linear_free_flight=False,
        base_motion=BaseMotion(np.array([0.0, 1.0]), np.zeros(2)),
    )
    assert fixed.contact_force_n.max() > 0.0
    assert fixed.tan_xy.tobytes() == still.tan_xy.tobytes()
    assert fixed.contact_force_n.tobytes() == still.contact_force_n.tobytes()
    assert np.all(still.base_angle_rad == 0.0) and fixed.base_angle_rad is None
    # a whisker at rest starts exactly at the model's rest positions (not turned by 0)
    for bm in (None, BaseMotion(np.array([0.0, 1.0]), np.zeros(2))):
        res = simulate(model, None, None, 0.001, record_every=1, base_motion=bm)
        assert res.states_m[0].tobytes() == model.x_rest.tobytes()


@pytest.mark.parametrize("mass", MASS_KINDS)
@pytest.mark.parametrize("alpha", [0.0, 3.0])
def test_constant_rate_rotation_is_followed_with_the_derived_lag(alpha, mass):
    m = RodModel(preset("scratchbot"), mass=mass)
    _, beta_s, beta_f = m.damping
    m.__dict__["damping"] = (alpha, beta_s, beta_f)  # add air drag to see a lag
    omega = 0.4
    t = np.array([0.0, 3.0])
    res = simulate(
        m,
        None,
        None,
        1.5,
        base_motion=BaseMotion(t, omega * t, np.full(2, omega)),
        record_every=200,
    )
    r = m.x_rest - m.x_rest[0]
    # moment of inertia about the pivot: sum_ij M_ij r_i . r_j over the moving nodes
    M = m.node_mass_matrix()[np.ix_(m.free, m.free)]
    inertia = float(np.sum(M * (r[m.free] @ r[m.free].T)))
    lag = alpha * inertia * omega / m.kf
    # the magnet, read in the housing's frame, trails by the lag (toward -x)
    assert res.tan_xy[-1, 0] == pytest.approx(-math.tan(lag), rel=0.02, abs=1e-9)
    # and the tip is where the housing points, turned by 0.6 rad
    tip = res.states_m[-1, -1]
    assert math.atan2(tip[0], tip[2] - m.x_rest[0, 2]) == pytest.approx(omega * 1.5 - lag, abs=2e-3)


def test_a_quick_step_rings_at_the_first_damped_frequency(model):
    res = simulate(model, None, None, 2.5, base_motion=_ramp(0.05, 0.002, 0.02))
    x = res.tan_xy[:, 0]
    keep = res.time_s > 0.3  # after the higher modes died out
    t, y = res.time_s[keep], x[keep]
    zeta, freq = model.modal_damping(*model.damping, 1)
    up = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    tc = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    assert 1.0 / np.mean(np.diff(tc)) == pytest.approx(freq[0], rel=0.01)
    peaks = [np.max(y[(t >= a) & (t < b)]) for a, b in zip(tc[:-1], tc[1:], strict=True)]
    delta = np.mean(np.log(np.array(peaks[:-1]) / np.array(peaks[1:])))
    assert delta / math.sqrt(4 * math.pi**2 + delta**2) == pytest.approx(zeta[0], rel=0.1)
    # it settles on the housing: the relative tilt decays toward zero
    assert abs(x[-1]) < 0.05 * np.abs(x).max()


def test_a_whisker_starting_mid_whisk_starts_turned_and_moving(model):
    t = np.linspace(0.0, 1.0, 101)
    bm = BaseMotion(t, 0.2 + 0.3 * t)
    res = simulate(model, None, None, 0.2, base_motion=bm, record_every=1)
    x0 = res.states_m[0]
    assert math.atan2(x0[-1, 0], x0[-1, 2] - x0[0, 2]) == pytest.approx(0.2, abs=1e-12)
    # moving rigidly with the housing from the first step: no jolt, no bending
    assert np.abs(res.tan_xy[:, 0]).max() < 1e-3


def test_resuming_in_pieces_follows_the_same_path(model):
    bm = _ramp(0.01, 0.05, 0.1, end=1.0)
    traj = Trajectory(np.array([0.0, 1.0]), np.array([[12.0, 100.0], [12.0, 100.0]]))
    # the nonlinear rod throughout: where linear free flight hands over depends on
    # where a run starts, so a resumed hybrid run agrees only to rounding, which a
    # contact onset can amplify
    opts = {"base_motion": bm, "linear_free_flight": False}
    whole = simulate(model, PoleContact(), traj, 0.2, **opts)
    first = simulate(model, PoleContact(), traj, 0.1, **opts)
    second = simulate(model, PoleContact(), traj, 0.1, initial_state=first.final_state, **opts)
    assert whole.contact_force_n.max() > 0
    joined = np.concatenate([first.tan_xy[:, 0], second.tan_xy[1:, 0]])
    np.testing.assert_allclose(joined, whole.tan_xy[:, 0], atol=2e-5)
    assert second.base_angle_rad[0] == pytest.approx(bm.sample(np.array([0.1]))[0][0])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"time_s": np.array([0.0, 0.0]), "angle_rad": np.zeros(2)}, "strictly increasing"),
        ({"time_s": np.array([0.0, 1.0]), "angle_rad": np.zeros(3)}, "angle_rad must have"),
        ({"time_s": np.array([0.0, 1.0]), "angle_rad": np.array([0.0, 2.0])}, "pi/2"),
        (
            {"time_s": np.array([0.0, 1.0]), "angle_rad": np.zeros(2), "rate_rad_s": np.zeros(1)},
            "rate_rad_s must have",
        ),
        ({"time_s": np.array([0.0, np.nan]), "angle_rad": np.zeros(2)}, "time_s"),
    ],
)
def test_bad_base_motion(kwargs, match):
    with pytest.raises(ValueError, match=match):
        BaseMotion(**kwargs)


def test_base_motion_must_be_a_base_motion(model):
    with pytest.raises(TypeError, match="BaseMotion"):
        simulate(model, None, None, 0.01, base_motion=(0.0, 0.0))  # type: ignore[arg-type]


def test_a_time_a_rounding_error_past_the_last_sample_reads_the_end_rate():
    # a closed loop's clock is a running sum of steps, which overshoots its periods'
    # sample times (k * dt) by a rounding error in most periods at 1 kHz and 0.25 ms
    # steps; the housing is still turning there (before the fix the rate read zero)
    dt, spp, clock, over = 2.5e-4, 4, 0.0, 0
    for k in range(500):
        clock = float((clock + np.arange(spp + 1) * dt)[-1])
        over += clock > (k + 1) * spp * dt
    assert over > 250
    t = np.arange(5) * 2.5e-4
    motion = BaseMotion(t, 0.1 * t, np.full(5, 0.1))
    ahead = t[-1] + math.ulp(t[-1]) * 4
    angle, rate = motion.sample(np.array([t[0] - 1e-15, ahead, t[-1] + 1e-6]))
    assert rate[0] == 0.1 and rate[1] == 0.1
    assert rate[2] == 0.0 and angle[2] == motion.angle_rad[-1]  # truly beyond: held, still
