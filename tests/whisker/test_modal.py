"""Exact linear free flight (vibrissa.whisker.modal) and its hand-over to the nonlinear rod.

The hybrid integration must give the nonlinear rod's answer: the modes are the rod's own,
the hand-over keeps the state (energy and base signal continuous), no contact is
missed, and stop events fire at the same step.
"""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.whisker import preset
from vibrissa.whisker.benchmark import standard_trajectory
from vibrissa.whisker.hall import HallSettings
from vibrissa.whisker.modal import ENERGY_TOL, LINEARITY_TOL, linear_modes
from vibrissa.whisker.rod import MASS_KINDS, RodModel
from vibrissa.whisker.simulate import (
    BaseMotion,
    PoleContact,
    SurfaceContact,
    Trajectory,
    free_vibration,
    simulate,
)
from vibrissa.whisker.surfaces import make_surface


@pytest.fixture(scope="module")
def model():
    return RodModel(preset("xy-robot"))


@pytest.fixture(scope="module")
def standard_pair(model):
    """The standard pole contact, hybrid and nonlinear-only (fixed steps both)."""
    c = PoleContact(radius_mm=0.5, friction=0.3)
    tr = standard_trajectory(model)
    hyb = simulate(model, c, tr, 1.5, max_stride=1)
    ref = simulate(model, c, tr, 1.5, max_stride=1, linear_free_flight=False)
    return hyb, ref


def test_modes_are_the_rods_natural_frequencies(model):
    lm = linear_modes(model)
    f = lm.omega / (2 * np.pi)
    # the x and y planes bend alike: every frequency twice
    np.testing.assert_allclose(f[0:6:2], model.natural_frequencies_hz[:3], rtol=1e-6)
    np.testing.assert_allclose(f[1:6:2], model.natural_frequencies_hz[:3], rtol=1e-6)
    assert f.max() < lm.cutoff_hz
    # the damped first mode has the whisker's damping ratio
    lam = lm.eigenvalues[: lm.n_pairs]
    first = lam[np.argmin(np.abs(lam.imag))]
    assert -first.real / abs(first) == pytest.approx(model.geometry.damping_ratio, rel=0.02)


def test_amplitudes_round_trip_a_state_of_the_kept_modes(model):
    lm = linear_modes(model)
    rng = np.random.default_rng(0)
    q, qd = rng.normal(size=lm.n_modes) * 1e-8, rng.normal(size=lm.n_modes) * 1e-6
    x, v = model.x_rest.copy(), np.zeros_like(model.x_rest)
    x.reshape(-1)[lm.dofs] += lm.shapes @ q
    v.reshape(-1)[lm.dofs] = lm.shapes @ qd
    z, lost = lm.amplitudes(x, v)
    assert lost < 1e-12
    x2, v2 = lm.state(lm.expanded(lm.reduced(z)))
    # equal up to the second-order correction of LinearModes.state (edges keep their
    # lengths plus the linear extension)
    scale_x = np.abs(x - model.x_rest).max()
    np.testing.assert_allclose(x2[:, :2], x[:, :2], rtol=0, atol=1e-4 * scale_x)
    np.testing.assert_allclose(v2[:, :2], v[:, :2], rtol=0, atol=1e-4 * np.abs(v).max())
    np.testing.assert_allclose(x2[:, 2], x[:, 2], rtol=0, atol=2e-2 * scale_x)


def _numpy_amplitudes(lm, x, v):
    """LinearModes.amplitudes written out in NumPy, as the documentation states it."""

    def transverse(u):
        uu = u.reshape(-1, 3)
        return (uu - np.sum(uu * lm.tangents, axis=1)[:, None] * lm.tangents).reshape(-1)

    u = (x - lm.x_rest).reshape(-1)[lm.dofs]
    w = v.reshape(-1)[lm.dofs]
    q, qd = lm.shapes.T @ (lm.mass @ u), lm.shapes.T @ (lm.mass @ w)
    ut, wt = transverse(u), transverse(w)
    ru, rw = transverse(u - lm.shapes @ q), transverse(w - lm.shapes @ qd)
    total = ut @ lm.stiffness @ ut + wt @ (lm.mass @ wt)
    lost = ru @ lm.stiffness @ ru + rw @ (lm.mass @ rw)
    return lm.inverse @ np.concatenate([q, qd]), max(lost, 0.0) / total


def _numpy_state(lm, z):
    """LinearModes.state written out in NumPy."""
    qq = (lm.vectors @ z).real
    m = lm.n_modes
    x, v = lm.x_rest.copy(), np.zeros_like(lm.x_rest)
    x.reshape(-1)[lm.dofs] += lm.shapes @ qq[:m]
    v.reshape(-1)[lm.dofs] = lm.shapes @ qq[m:]
    e = np.diff(x, axis=0)
    t = e / np.linalg.norm(e, axis=1)[:, None]
    dv = np.diff(v, axis=0)
    dv -= t * np.sum(t * dv, axis=1)[:, None]
    x[1:] = x[0] + np.cumsum(lm.edge_lengths[:, None] * t, axis=0)
    v[1:] = v[0] + np.cumsum(dv, axis=0)
    return x, v


@pytest.mark.parametrize("mass", MASS_KINDS)
def test_the_compiled_mode_projections_agree_with_their_formulas(mass):
    """amplitudes, state and nonlinearity (numba kernels) against NumPy transcriptions,
    on bent, moving states with energy outside the modes too, for either mass matrix."""
    model = RodModel(preset("xy-robot"), mass=mass)
    lm = linear_modes(model)
    # the modes are mass-normalised with the model's own mass matrix
    np.testing.assert_allclose(lm.shapes.T @ lm.mass @ lm.shapes, np.eye(lm.n_modes), atol=1e-9)
    rng = np.random.default_rng(4)
    for scale in (1e-7, 1e-4, 3e-3):
        x = model.x_rest + rng.normal(size=model.x_rest.shape) * scale
        x[0] = model.x_rest[0]
        v = rng.normal(size=x.shape) * scale * 100.0
        v[0] = 0.0
        z, lost = lm.amplitudes(x, v)
        z_ref, lost_ref = _numpy_amplitudes(lm, x, v)
        np.testing.assert_allclose(z, z_ref, rtol=1e-10, atol=1e-12 * np.abs(z_ref).max())
        assert lost == pytest.approx(lost_ref, rel=1e-9)
        assert lost > 1e-6  # random states put energy outside the kept modes
        xs, vs = lm.state(z)
        xs_ref, vs_ref = _numpy_state(lm, z)
        np.testing.assert_allclose(xs, xs_ref, rtol=0, atol=1e-15)
        np.testing.assert_allclose(vs, vs_ref, rtol=0, atol=1e-12 * np.abs(vs_ref).max())
        e = np.diff(x, axis=0)
        e /= np.linalg.norm(e, axis=1)[:, None]
        rot = np.arccos(np.clip(np.sum(e * lm.tangents, axis=1), -1.0, 1.0))
        assert lm.nonlinearity(x) == pytest.approx(np.max(rot) ** 2, rel=1e-12)


def test_the_mode_projections_refuse_states_of_the_wrong_shape(model):
    lm = linear_modes(model)
    x = model.x_rest
    with pytest.raises(ValueError, match="x must have shape"):
        lm.amplitudes(x[:-1], np.zeros_like(x))
    with pytest.raises(ValueError, match="v must have shape"):
        lm.amplitudes(x, np.zeros((x.shape[0], 2)))
    with pytest.raises(ValueError, match="x must have shape"):
        lm.nonlinearity(x.T)
    with pytest.raises(ValueError, match="z must have shape"):
        lm.state(np.zeros(3, dtype=complex))


def test_hand_over_keeps_energy_and_base_signal(model):
    """Nonlinear ring-down states that pass the hand-over's gates, mapped into the modes
    and back, keep their energy to the order of the linearisation (the squared edge
    rotation, plus the energy outside the kept modes) and the magnet's tilt."""
    lm = linear_modes(model)
    tested = 0
    for force_n in (2e-3, 5e-3):
        ring = simulate(
            model,
            None,
            None,
            0.3,
            linear_free_flight=False,
            initial_positions_m=model.static_force(force_n, 185).positions_m,
            record_every=40,
        )
        peak = np.abs(ring.tan_xy[:, 0]).max()
        for x, v in zip(ring.states_m[1:], ring.velocities_m_s[1:], strict=True):
            z, lost = lm.amplitudes(x, v)
            nonlin = lm.nonlinearity(x)
            if lost > ENERGY_TOL or nonlin > LINEARITY_TOL:
                continue
            tested += 1
            x2, v2 = lm.state(z)
            e1 = model.elastic_energy(x) + model.kinetic_energy(v)
            e2 = model.elastic_energy(x2) + model.kinetic_energy(v2)
            assert abs(e2 - e1) <= 2 * (nonlin + lost) * e1
            tan1 = (x[1, 0] - x[0, 0]) / (x[1, 2] - x[0, 2])
            tan2 = (x2[1, 0] - x2[0, 0]) / (x2[1, 2] - x2[0, 2])
            assert abs(tan2 - tan1) <= 1e-3 * peak
    assert tested >= 10


def test_standard_contact_matches_the_nonlinear_rod(standard_pair):
    hyb, ref = standard_pair
    peak = np.abs(ref.tan_xy).max()
    linear = hyb.newton_iterations == 0
    assert linear.mean() > 0.5  # most of the 1.5 s is free flight
    assert np.abs(hyb.tan_xy - ref.tan_xy).max() <= 5e-4 * peak
    np.testing.assert_array_equal(hyb.contact_force_n > 0, ref.contact_force_n > 0)
    assert np.abs(hyb.follicle_moment_nm).max() == pytest.approx(
        np.abs(ref.follicle_moment_nm).max(), rel=1e-6
    )


def test_signal_is_continuous_at_every_hand_over(model, standard_pair):
    """Across each switch the magnet's tilt changes as the nonlinear rod's does, to well
    within one step of the Hall sensor's converter (an error the sensor cannot show)."""
    hyb, ref = standard_pair
    linear = hyb.newton_iterations == 0
    switches = np.flatnonzero(np.diff(linear.astype(int)) != 0) + 1
    assert switches.size >= 2  # into free flight and back
    sensor = HallSettings().calibrate(model.geometry, model.n_elements)
    lsb_tan = sensor.supply_v / 2**sensor.adc_bits / sensor.gain_v
    for i in switches:
        jump = hyb.tan_xy[i] - hyb.tan_xy[i - 1]
        ref_jump = ref.tan_xy[i] - ref.tan_xy[i - 1]
        assert np.abs(jump - ref_jump).max() <= 0.25 * lsb_tan, i


def test_ring_down_matches_the_nonlinear_rod(model):
    hyb = free_vibration(model, 5.0, 1.0)  # default long steps too
    assert hyb.tan_xy[0, 0] > 0.0
    ref = simulate(
        model,
        None,
        None,
        1.0,
        linear_free_flight=False,
        max_stride=1,
        initial_positions_m=model.static_force(*_tip_force(model, 5.0)).positions_m,
    )
    assert (hyb.newton_iterations == 0).mean() > 0.8
    peak = np.abs(ref.tan_xy).max()
    assert np.abs(hyb.tan_xy - ref.tan_xy).max() <= 1e-3 * peak


def _tip_force(model, deflection_mm):
    """The tip force (N) and position (mm) that free_vibration uses."""
    L = model.geometry.length_mm
    force = 1e-4 * deflection_mm / model.static_force(1e-4, L).deflection_mm
    for _ in range(3):
        force *= deflection_mm / model.static_force(force, L).deflection_mm
    return force, L


def test_a_late_contact_is_not_missed(model):
    """The pole starts 20 mm away: the approach is linear free flight, and contact
    starts on the same step as with the nonlinear rod throughout."""
    c = PoleContact(radius_mm=0.5, friction=0.3)
    tr = Trajectory.linear((-21.0, 140.0), (100.0, 0.0), 0.4)
    hyb = simulate(model, c, tr, 0.4)
    ref = simulate(model, c, tr, 0.4, linear_free_flight=False, max_stride=1)
    assert (hyb.newton_iterations[:500] == 0).mean() > 0.9
    on_h = np.argmax(hyb.contact_force_n > 0)
    on_r = np.argmax(ref.contact_force_n > 0)
    assert on_h == on_r > 0


def test_a_ringing_whisker_that_swings_back_into_the_pole_is_caught(model):
    """Released 30 mm deflected next to a pole 8 mm behind its rest position: the
    ringing whisker hits the pole, in both integrations at the same step."""
    c = PoleContact(radius_mm=0.5, friction=0.0)
    tr = Trajectory.linear((-9.0, 140.0), (0.0, 0.0), 0.5)
    x0 = model.static_force(*_tip_force(model, 30.0)).positions_m
    hyb = simulate(model, c, tr, 0.5, initial_positions_m=x0)
    ref = simulate(
        model, c, tr, 0.5, initial_positions_m=x0, linear_free_flight=False, max_stride=1
    )
    hits_r = np.flatnonzero(ref.contact_force_n > 0)
    assert hits_r.size > 0
    assert np.argmax(hyb.contact_force_n > 0) == hits_r[0]


def test_surface_contact_after_free_flight_matches(model):
    surf = make_surface("p80", 3)
    c = SurfaceContact(surf, angle_deg=45.0)
    n, _, _ = c.frame()
    g = model.geometry
    origin = np.array([0, 0, g.length_m]) - n * (8e-3 + g.tip_radius_mm * 1e-3) * n[0]
    tr = Trajectory.linear((origin[0] * 1e3, origin[2] * 1e3), (60.0, 0.0), 0.4)
    hyb = simulate(model, c, tr, 0.4, max_stride=1)
    ref = simulate(model, c, tr, 0.4, linear_free_flight=False, max_stride=1)
    assert (hyb.newton_iterations[:200] == 0).mean() > 0.9
    assert np.argmax(hyb.contact_force_n > 0) == np.argmax(ref.contact_force_n > 0) > 0
    peak = np.abs(ref.tan_xy).max()
    # Sliding over P80 grains amplifies any perturbation: the nonlinear rod alone
    # moves by several 1e-3 of the peak when its Newton tolerance is tightened. The
    # hybrid must agree with it to 1e-3 of the peak, or to that spread if larger.
    tight = simulate(model, c, tr, 0.4, linear_free_flight=False, max_stride=1, tol_m=1e-10)
    spread = np.abs(tight.tan_xy - ref.tan_xy).max()
    assert np.abs(hyb.tan_xy - ref.tan_xy).max() <= max(1e-3 * peak, spread)


def test_stop_event_fires_on_the_same_step_in_free_flight(model):
    x0 = model.static_force(*_tip_force(model, 3.0)).positions_m
    ref = simulate(
        model, None, None, 0.5, initial_positions_m=x0, linear_free_flight=False, max_stride=1
    )
    # a level the decaying ring-down crosses late, in free flight
    level = 0.3 * np.abs(ref.tan_xy[:, 0]).max()
    late = np.flatnonzero(np.abs(ref.tan_xy[400:, 0]) >= level)[0] + 400
    a = simulate(model, None, None, 0.5, initial_positions_m=x0, stop_when_tan_x_exceeds=level)
    b = simulate(
        model,
        None,
        None,
        0.5,
        initial_positions_m=x0,
        linear_free_flight=False,
        max_stride=1,
        stop_when_tan_x_exceeds=level,
    )
    assert a.stopped_early and b.stopped_early
    assert a.time_s.size == b.time_s.size
    assert late > 0


def test_long_steps_keep_the_standard_contact_accurate(model):
    """Issue 14: the peak base moment stays within 0.5 % of a fine reference (half the
    step, twice the elements) with every speed-up on."""
    c = PoleContact(radius_mm=0.5, friction=0.3)
    fine = RodModel(preset("xy-robot"), 2 * model.n_elements)
    tr = standard_trajectory(model)
    ref = simulate(fine, c, tr, 1.5, 1.25e-4, linear_free_flight=False, max_stride=1)
    res = simulate(model, c, tr, 1.5)
    peak_ref = np.abs(ref.follicle_moment_nm[:, 0]).max()
    peak = np.abs(res.follicle_moment_nm[:, 0]).max()
    assert abs(peak / peak_ref - 1) <= 5e-3


def test_adaptive_long_steps_grow_in_a_steady_slide_and_keep_the_signal(model):
    """Issue 14: while the whisker slides steadily along the pole the long steps grow
    past two steps of dt (up to ``max_stride``), and the Hall signal stays within 1e-3
    of its peak of the same run at fixed steps."""
    c = PoleContact(radius_mm=0.5, friction=0.3)
    tr = standard_trajectory(model)
    res = simulate(model, c, tr, 1.5)
    fixed = simulate(model, c, tr, 1.5, max_stride=1)
    touching = res.contact_force_n > 0
    interpolated = (res.newton_iterations == 0) & touching
    # rows inside one long step carry no iterations of their own: runs of 3+ such rows
    # mean steps of 4 dt or more
    runs = np.diff(np.flatnonzero(np.diff(np.r_[0, interpolated.astype(int), 0])))[::2]
    assert runs.max() >= 3
    assert runs.max() <= 7  # max_stride = 8: at most 7 rows between solved ones
    peak = np.abs(fixed.tan_xy).max()
    assert np.abs(res.tan_xy - fixed.tan_xy).max() <= 1e-3 * peak


# --------------------------------------------------------------- a turning housing
def _whisk(freq_hz: float, amplitude_deg: float = 12.0, end_s: float = 1.6) -> BaseMotion:
    """A raised-cosine whisk, sampled finely so that angle and rate agree."""
    t = np.arange(0.0, end_s, 6.25e-5)
    amp = np.deg2rad(amplitude_deg)
    w = 2 * np.pi * freq_hz
    return BaseMotion(t, 0.5 * amp * (1 - np.cos(w * t)), 0.5 * amp * w * np.sin(w * t))


@pytest.fixture(scope="module")
def scratchbot():
    return RodModel(preset("scratchbot"))


def test_whisking_in_air_is_linear_free_flight_seen_from_the_housing(scratchbot):
    """Seen from the turning housing the free whisker is the fixed-base linear
    system driven by the housing's angular acceleration: the hybrid agrees with
    the nonlinear rod throughout to 1e-3 of the peak, with nearly every step modal."""
    bm = _whisk(2.0)
    hyb = simulate(scratchbot, None, None, 1.5, base_motion=bm)
    ref = simulate(
        scratchbot, None, None, 1.5, base_motion=bm, linear_free_flight=False, max_stride=1
    )
    assert (hyb.newton_iterations == 0).mean() > 0.95
    peak = np.abs(ref.tan_xy[:, 0]).max()
    assert peak > 1e-3  # the whisking itself bends the whisker
    assert np.abs(hyb.tan_xy - ref.tan_xy).max() <= 1e-3 * peak


@pytest.mark.parametrize("mass", MASS_KINDS)
def test_the_housing_load_is_the_euler_load(mass):
    """A housing turning at constant angular acceleration from rest loads the
    whisker, seen from the housing, with the steady Euler load -m (y x r) theta''
    (the centrifugal load, of order theta'^2 / omega_1^2, is below 1e-4 here): the
    ringing decays and the magnet settles at the linear static deflection under
    that load, K^-1 f, from the rod's own tangent stiffness."""
    model = RodModel(preset("xy-robot"), mass=mass)
    assert model.damping[0] == 0.0  # no mass-proportional drag adds to the load
    acc = 2.0  # rad/s^2: 0.36 rad after 0.6 s
    t = np.arange(0.0, 0.7, 6.25e-5)
    res = simulate(model, None, None, 0.6, base_motion=BaseMotion(t, 0.5 * acc * t**2, acc * t))
    assert (res.newton_iterations == 0).mean() > 0.95
    r = model.x_rest - model.x_rest[0]
    f = -(model.node_mass_matrix() @ np.column_stack([r[:, 2], 0 * r[:, 0], -r[:, 0]])) * acc
    dofs = np.flatnonzero(np.repeat(model.free, 3))
    K = model.stiffness_matrix()[np.ix_(dofs, dofs)]
    u = np.zeros(model.x_rest.size)
    u[dofs] = np.linalg.solve(K, f.reshape(-1)[dofs])
    x = model.x_rest + u.reshape(-1, 3)
    tan = (x[1, 0] - x[0, 0]) / (x[1, 2] - x[0, 2])
    assert abs(tan) > 1e-5
    settled = res.tan_xy[res.time_s > 0.5, 0]
    assert settled.mean() == pytest.approx(tan, rel=0.02)
    assert np.ptp(settled) < 0.25 * abs(tan)  # what is left of the start-up ringing


def test_a_whisk_into_a_pole_touches_on_the_same_step(scratchbot):
    """The pole, seen from the housing, turns the other way: free flight ends
    before it could touch, and every contact onset matches the nonlinear rod's
    until the whisker bounces off."""
    from vibrissa.robots.whisking import pole_whisker

    bm = _whisk(2.0)
    ws = pole_whisker(scratchbot, 130.0, 6.0)
    hyb = simulate(scratchbot, ws.contact, ws.trajectory, 1.0, base_motion=bm)
    ref = simulate(
        scratchbot,
        ws.contact,
        ws.trajectory,
        1.0,
        base_motion=bm,
        linear_free_flight=False,
        max_stride=1,
    )
    assert (hyb.newton_iterations == 0).mean() > 0.3
    on_h = np.flatnonzero(np.diff((hyb.contact_force_n > 0).astype(int)) == 1)
    on_r = np.flatnonzero(np.diff((ref.contact_force_n > 0).astype(int)) == 1)
    assert on_h.size and on_h[0] == on_r[0]
    peak = np.abs(ref.tan_xy[:, 0]).max()
    assert np.abs(hyb.tan_xy - ref.tan_xy).max() <= 2e-3 * peak


def test_a_fast_whisk_stays_with_the_rod(scratchbot):
    """Where the housing turns so fast that the centrifugal load it leaves out
    exceeds the linearity bound, the nonlinear rod integrates."""
    from vibrissa.whisker.modal import LINEARITY_TOL, linear_modes

    bm = _whisk(6.0)
    # fixed steps, so that every step of the rod reports its Newton iterations
    res = simulate(scratchbot, None, None, 0.5, base_motion=bm, max_stride=1)
    rate = bm.sample(res.time_s)[1]
    fast = rate**2 > LINEARITY_TOL * linear_modes(scratchbot).omega[0] ** 2
    assert fast.any()
    assert np.all(res.newton_iterations[1:][fast[1:]] > 0)
