"""The whisking pattern generator and rapid cessation of protraction (thesis 3.2.4, 3.4.2)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import butter, sosfilt

from vibrissa.robots.whisking import (
    ContactFilter,
    RCPControl,
    WhiskerSetup,
    WhiskPattern,
    count_contacts,
    motor_follow,
    obstacle_whisk,
    pole_whisker,
    rcp_gating,
    run_whisking,
)
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSettings
from vibrissa.whisker.rod import RodModel


# ------------------------------------------------------------------ eq. 3.3
def test_rcp_gating_follows_eq_3_3_sample_by_sample():
    # dt/tau = 0.25: z decays by 0.75 a step; sigma_z = 0.7
    contact = np.array([0.0, 0.5, 0.2, 0.0, 0.0, 2.0, 0.0, -1.0])
    z = rcp_gating(contact, dt_s=0.01, sigma_z=0.7, tau_z_s=0.04)
    by_hand = [0.0, 0.35, 0.2625, 0.196875, 0.14765625, 1.0, 0.75, 0.5625]
    np.testing.assert_allclose(z, by_hand, rtol=0, atol=1e-15)
    # z0 is the value before the first sample; 0.9 * 0.75 beats 0.7 * 0.5
    np.testing.assert_allclose(rcp_gating([0.5], 0.01, 0.7, 0.04, z0=0.9), [0.675])
    # no gain, no gating
    assert not rcp_gating(contact, 0.01, 0.0, 0.04).any()


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([0.1], 0.01, -0.7, 0.04), "sigma_z"),
        (([0.1], 0.01, 0.7, 0.0), "tau_z_s"),
        (([0.1], 0.05, 0.7, 0.04), "at least the step"),
        (([0.1], 0.0, 0.7, 0.04), "dt_s"),
        (([[0.1]], 0.01, 0.7, 0.04), "1-D"),
        (([np.nan], 0.01, 0.7, 0.04), "contact"),
    ],
)
def test_rcp_gating_refuses_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        rcp_gating(*args)
    with pytest.raises(ValueError, match="z0"):
        rcp_gating([0.1], 0.01, 0.7, 0.04, z0=1.5)


def test_contact_filter_is_the_causal_butterworth_maximised_over_the_side():
    rng = np.random.default_rng(1)
    x = rng.normal(size=(3, 400))
    filt = ContactFilter(3, 1000.0)
    got = np.array([filt.step(x[:, n]) for n in range(x.shape[1])])
    sos = butter(3, 50.0, fs=1000.0, output="sos")
    want = np.abs(sosfilt(sos, x, axis=1)).max(axis=0)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-14)
    with pytest.raises(ValueError, match="below half the control rate"):
        ContactFilter(1, 80.0)


# ------------------------------------------------------------------ the generator
def test_pattern_suppresses_protraction_without_touching_the_phase():
    p = WhiskPattern(4.0, 30.0, 10.0)
    t = np.linspace(0.0, 1.0, 1001)
    osc = p.oscillator_deg(t)
    assert osc.min() == pytest.approx(10.0) and osc.max() == pytest.approx(40.0)
    half = p.command_deg(t, 0.5)
    np.testing.assert_allclose(half - 10.0, 0.5 * (osc - 10.0))
    np.testing.assert_allclose(p.command_deg(t, 1.0), 10.0)
    # the phase is the oscillator's: the same instants of full protraction
    assert np.argmax(half[:250]) == np.argmax(osc[:250])


@pytest.mark.parametrize("f", [0.0, -2.0, float("nan")])
def test_whisk_frequency_must_be_positive(f):
    with pytest.raises(ValueError, match="frequency_hz"):
        WhiskPattern(f)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"sigma_z": -0.1}, "sigma_z"),
        ({"cia_gain": -1.0}, "cia_gain"),
        ({"tau_z_periods": 0.0}, "tau_z_periods"),
    ],
)
def test_negative_gains_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        RCPControl(**kwargs)


def test_motor_is_a_critically_damped_follower():
    ang, rate = motor_follow(np.full(4000, 10.0), 2.5e-4, 20.0)
    assert ang[0] == 0.0 and ang[-1] == pytest.approx(10.0, abs=1e-6)
    assert ang.max() <= 10.0 + 1e-9  # no overshoot
    # the critically damped step response 1 - (1 + w t) exp(-w t)
    w = 2 * math.pi * 20.0
    for k in (8, 32, 200):
        wt = w * k * 2.5e-4
        assert ang[k] == pytest.approx(10.0 * (1 - (1 + wt) * math.exp(-wt)), rel=1e-9)
    # held commands are followed exactly, whatever the step
    a2, _ = motor_follow(np.full(8, 10.0), 2.5e-3, 20.0)
    assert a2[2] == pytest.approx(ang[20], rel=1e-9)


# ------------------------------------------------------------------ figure 3.9
@pytest.mark.parametrize("frequency_hz", [6.0, 8.0, 10.0])
@pytest.mark.parametrize("scale_deg", [20.0, 25.0])
def test_biphasic_whisk_appears_only_with_strong_fast_rcp(frequency_hz, scale_deg):
    kw = {"frequency_hz": frequency_hz, "deflection_scale_deg": scale_deg, "n_whisks": 3}
    a = obstacle_whisk(0.7, 0.25, **kw)
    b = obstacle_whisk(2.0, 0.1, **kw)
    for r in (a, b):
        assert count_contacts(r.angle_deg[1] - r.obstacle_deg[1], 0.0, -2.0) == 0  # right
    # (a): one contact per whisk, protraction held near the obstruction, and z all but
    # recovered before the next whisk's contact (no inter-whisk modulation)
    assert count_contacts(a.angle_deg[0] - a.obstacle_deg[0], 0.0, -2.0) == 3
    assert (a.angle_deg[0] - a.obstacle_deg[0]).max() < 10.0
    touching = a.angle_deg[0] > a.obstacle_deg[0]
    onsets = np.flatnonzero(touching[1:] & ~touching[:-1]) + 1
    second = onsets[np.searchsorted(a.time_s[onsets], 1.0 / frequency_hz)]
    assert a.gating[0, second] < 0.1 * a.gating[0].max()
    # (b): the whisker detaches and protracts again within the whisk: two contacts each
    assert count_contacts(b.angle_deg[0] - b.obstacle_deg[0], 0.0, -2.0) == 6
    assert b.gating[0].max() > a.gating[0].max()


def test_count_contacts_hysteresis():
    s = np.array([0, 1, -0.5, 1, -3, 1, -3.0])
    assert count_contacts(s, 0.0) == 3
    assert count_contacts(s, 0.0, -2.0) == 2
    with pytest.raises(ValueError, match="release"):
        count_contacts(s, 0.0, 1.0)


# ------------------------------------------------------------------ physical whisking
@pytest.fixture(scope="module")
def model() -> RodModel:
    return RodModel(preset("scratchbot"))


def _pole(model: RodModel, r_mm: float = 100.0, angle_deg: float = 10.0) -> WhiskerSetup:
    return pole_whisker(model, r_mm, angle_deg)


def _episodes(force: np.ndarray, dt: float, gap_s: float = 0.05) -> int:
    idx = np.flatnonzero(force > 0)
    return 0 if idx.size == 0 else 1 + int(np.sum(np.diff(idx) * dt > gap_s))


def test_whisking_in_air_gives_no_detected_contacts(model):
    """The contact detector of the SCRATCHbot experiment: the Hall output minus the
    robot's prediction of its own whisk in air (a separate, shorter, noise-free run),
    over gamma = 0.05 V. At 6 Hz the inertial deflection alone exceeds it many times."""
    sensor = HallSettings().calibrate(model.geometry, model.n_elements)
    pattern = WhiskPattern(6.0, 12.0)
    ref = run_whisking([WhiskerSetup(model, hall_gain_v=sensor.gain_v)], pattern, None, 0.5)
    air = run_whisking([WhiskerSetup(model, hall_gain_v=sensor.gain_v)], pattern, None, 1.0)
    rate = 1.0 / air.dt_s

    def volts(res, rng=None):
        return sensor.read(np.column_stack([res.tan_x[0], 0 * res.tan_x[0]]), rate, rng)[:, 0]

    v = volts(air, np.random.default_rng(0))
    resid = v[:501] - volts(ref)
    assert np.abs(v - 2.5).max() > 10 * 0.05  # self-motion alone would be a "contact"
    assert count_contacts(np.abs(resid), 0.05) == 0
    assert not air.contact_force_n.any()
    # the same detector finds the pole on every whisk
    touch = run_whisking([_pole(model, 100.0, 6.0)], pattern, None, 0.5)
    resid = volts(touch, np.random.default_rng(0)) - volts(ref)
    assert count_contacts(-resid, 0.05, 0.02) == 3


def test_rcp_feedback_keeps_deflections_small_on_the_physical_whisker(model):
    """Minimal impingement (3.2.4, 3.3): with RCP the whisker presses less on the pole."""
    w = _pole(model)
    pattern = WhiskPattern(2.0, 20.0)
    peak = {}
    for key, ctrl in (("off", None), ("rcp7", RCPControl(0.7)), ("strong", RCPControl(2.0, 0.1))):
        res = run_whisking([w], pattern, ctrl, 1.0)
        peak[key] = np.abs(res.deflection[0]).max()
        assert _episodes(res.contact_force_n[0], res.dt_s) >= 2
        if ctrl is None:
            assert not res.gating.any()
        else:
            assert res.gating.max() > 0.1
            # the oscillator's phase is untouched: full retraction stays at the same times
            assert res.command_deg[0, 0] == pytest.approx(0.0)
    # both press less; the strong, fast setting (figure 3.9 b) may touch twice per whisk,
    # the second time with the resumed protraction's speed, so it need not press least
    assert max(peak["strong"], peak["rcp7"]) < 0.8 * peak["off"]


def test_a_side_is_several_whiskers_and_cia_protracts_the_other_side(model):
    short = RodModel(preset("biotact-g1-80"))
    ctrl, pattern = RCPControl(0.7, cia_gain=0.5), WhiskPattern(2.0, 20.0)
    others = [WhiskerSetup(short, side=0), WhiskerSetup(model, side=1)]
    res = run_whisking([_pole(model), *others], pattern, ctrl, 0.5)
    air = run_whisking([WhiskerSetup(model, side=0), *others], pattern, ctrl, 0.5)
    assert res.tan_x.shape[0] == 3 and res.gating.shape[0] == 2
    assert not res.contact_force_n[1:].any()
    # in air both sides gate alike on their own inertial deflection (no self-motion
    # cancellation); the side's contact signal is its largest whisker's, the touching one
    assert air.gating[0].max() == pytest.approx(air.gating[1].max(), rel=0.05)
    assert res.gating[0].max() > 2.0 * air.gating[0].max()
    # the other side, touching nothing, protracts further than in air (CIA)
    assert res.command_deg[1].max() > air.command_deg[1].max() + 1.0
    with pytest.raises(ValueError, match="side"):
        run_whisking([WhiskerSetup(model, side=2)], [WhiskPattern(2.0)] * 2, None, 0.1)
    with pytest.raises(ValueError, match="divide the control period"):
        run_whisking([WhiskerSetup(model)], WhiskPattern(2.0), None, 0.1, dt_s=3e-4)


def test_a_varying_pattern_changes_amplitude_at_full_retraction_only():
    from vibrissa.robots.whisking import VaryingWhiskPattern

    p = VaryingWhiskPattern(2.0, 30.0, 5.0, amplitudes_deg=(30.0, 20.0))
    t = np.arange(0, 1.5, 1e-3)
    osc = p.oscillator_deg(t)
    # whisk 1 peaks at 5 + 30, whisk 2 at 5 + 20, and the last amplitude repeats
    assert osc[(t > 0.2) & (t < 0.3)].max() == pytest.approx(35.0, abs=1e-3)
    assert osc[(t > 0.7) & (t < 0.8)].max() == pytest.approx(25.0, abs=1e-3)
    assert osc[(t > 1.2) & (t < 1.3)].max() == pytest.approx(25.0, abs=1e-3)
    # continuous: every whisk starts and ends at full retraction
    assert np.max(np.abs(np.diff(osc))) < 0.2
    with pytest.raises(ValueError, match="amplitudes_deg"):
        VaryingWhiskPattern(2.0, 30.0, amplitudes_deg=(30.0, -1.0))
