"""The thesis' observables measured on the simulated robot (vibrissa.experiments.identify)."""

import math

import numpy as np
import pytest

from vibrissa.experiments.identify import (
    SPECS,
    deflection_duration_s,
    identify,
    ring_ratio,
    spectral_peak_hz,
    trial_spectral_peaks_hz,
)
from vibrissa.robots.xy_stage import TrialResult
from vibrissa.whisker.geometry import WhiskerGeometry
from vibrissa.whisker.rod import RodModel


def test_tip_pinned_uniform_cantilever_matches_beam_theory():
    """Clamped-pinned Euler-Bernoulli beam: beta_n L = 3.9266, 7.0686 (independent of
    the rod code: closed-form roots of tan(bL) = tanh(bL))."""
    g = WhiskerGeometry(length_mm=150.0, base_radius_mm=1.0, tip_radius_mm=1.0)
    model = RodModel(g, 56, rigid_follicle=True)
    EI = g.bending_stiffness_base_nm2
    rho_a = g.density_kg_m3 * math.pi * 1e-6
    scale = math.sqrt(EI / (rho_a * g.length_m**4)) / (2 * math.pi)
    f = model.pinned_frequencies_hz(g.length_mm, 2)
    for got, bl in zip(f, (3.92660231, 7.06858275), strict=True):
        assert got == pytest.approx(bl**2 * scale, rel=0.015)


def test_pinning_raises_the_first_mode_and_a_softer_follicle_lowers_it():
    g = WhiskerGeometry(name="xy-robot")
    soft = RodModel(g.replace(follicle_stiffness_nm_per_rad=0.02), 28)
    stiff = RodModel(g.replace(follicle_stiffness_nm_per_rad=0.2), 28)
    assert soft.pinned_frequencies_hz(185.0)[0] > soft.natural_frequencies_hz[0]
    assert soft.pinned_frequencies_hz(185.0)[0] < stiff.pinned_frequencies_hz(185.0)[0]


def test_spectral_peak_finds_a_resonance_beside_a_large_slow_pulse():
    fs = 4000.0
    t = np.arange(6001) / fs
    rng = np.random.default_rng(0)
    pulse = 1.5 * np.exp(-(((t - 0.75) / 0.12) ** 2))
    ring = 0.05 * np.exp(-3 * t) * np.sin(2 * np.pi * 30.0 * t)
    x = pulse + ring + rng.normal(0, 0.002, (8, t.size))
    assert spectral_peak_hz(x, fs) == pytest.approx(30.0, abs=1.0)


def _result(x: np.ndarray, peak: int, end_s: float) -> TrialResult:
    return TrialResult(
        signal_v=np.vstack([2.5 + x, np.full_like(x, 2.5)]),
        peak_index=peak,
        contact_onset_s=-0.3,
        threshold_time_s=-0.28,
        retract_start_s=-0.01,
        contact_end_s=end_s,
        latency_s=0.27,
        contact_duration_s=0.4,
        slipped_off=False,
        saturated=False,
        peak_deflection_v=float(np.abs(x).max()),
    )


def test_trial_spectral_peaks_find_each_trials_tone():
    fs = 4000.0
    t = np.arange(6001) / fs
    x = np.stack([np.sin(2 * np.pi * f * t) for f in (16.0, 30.0, 120.0)])
    np.testing.assert_allclose(trial_spectral_peaks_hz(x, fs), [16.0, 30.0, 120.0], atol=0.7)
    # a slow pulse alone peaks at the band's lower edge
    pulse = np.exp(-(((t - 0.75) / 0.15) ** 2))
    assert trial_spectral_peaks_hz(pulse[None], fs)[0] == pytest.approx(10.0, abs=0.7)
    with pytest.raises(ValueError, match="band_hz"):
        trial_spectral_peaks_hz(x, fs, band_hz=(2500.0, 3000.0))


def test_deflection_duration_is_the_longest_stretch_above_threshold_bridging_dips():
    fs = 1000.0
    x = np.full(1000, 2.5)
    x[100:400] = 2.6  # 300 ms contact
    x[250:253] = 2.52  # a 3 ms dip (texture): bridged
    x[500:520] = 2.4  # a ringing half-cycle: a separate, shorter stretch
    x[50] = 2.56  # a noise spike before the contact
    assert deflection_duration_s(x, fs) == pytest.approx(0.300)
    assert deflection_duration_s(np.full(100, 2.5), fs) == 0.0


def test_ring_ratio_is_the_overshoot_after_release_over_the_peak():
    fs = 1000.0
    t = np.arange(-500, 501) / fs
    x = np.where(t < 0.1, np.cos(np.pi * t / 0.2), 0.0)  # 1 V peak, back to rest at 0.1 s
    after = t >= 0.1
    x[after] = -0.25 * np.sin(2 * np.pi * 16 * (t[after] - 0.1)) * np.exp(-5 * (t[after] - 0.1))
    assert ring_ratio(_result(x, 500, 0.1), fs) == pytest.approx(0.25, abs=0.03)
    quiet = np.where(t < 0.1, np.cos(np.pi * t / 0.2), 0.0)
    assert ring_ratio(_result(quiet, 500, 0.1), fs) == pytest.approx(0.0, abs=1e-6)


@pytest.fixture(scope="module")
def observables():
    return {o.key: o for o in identify(quick=True)}


def test_identify_reports_every_observable_of_the_issue(observables):
    assert set(observables) == {
        "resonance_hz",
        "mi_latency_ms",
        "duration_grows_with_speed",
        "ringing_chapter4",
        "ringing_chapter5",
        "contact_duration_chapter5_ms",
        "closest_usable_contact_mm",
        "tip_zone_mm",
        "above_216_mm_s",
    }
    for o in observables.values():
        assert math.isfinite(o.value)
        d = o.to_dict()
        assert d["key"] == o.key and isinstance(d["within"], bool)


def test_the_identified_whisker_resonates_at_30_hz_with_its_tip_held(observables):
    o = observables["resonance_hz"]
    assert o.detail["tip_pinned_first_mode_hz"] == pytest.approx(30.0, abs=3.0)
    # the value is what the recordings' spectra show, one peak per trial, in 10-200 Hz
    assert 10.0 <= o.value <= 200.0
    assert sum(o.detail["trial_peaks_by_band"].values()) == o.detail["n_chapter5_trials"]
    # the free whisker cannot: 30 Hz is not its free mode, with or without the follicle
    assert o.detail["free_first_mode_hz"] < 20.0
    assert o.detail["rigid_follicle_free_first_mode_hz"] < 25.0


def test_the_loop_latency_counted_from_first_contact_is_300_ms(observables):
    o = observables["mi_latency_ms"]
    assert o.within
    lo, _, hi = o.detail["contact_to_threshold_ms_5_50_95"]
    assert 0.0 <= lo <= hi < 300.0  # the threshold comes after first contact


def test_specs_name_the_observables_identify_returns_in_order(observables):
    names = [s.name for s in SPECS]
    assert len(set(names)) == len(names)
    assert list(observables) == names  # the fixture keeps identify's order
    for spec, o in zip(SPECS, observables.values(), strict=True):
        assert o.tolerance == spec.tolerance.text()
        assert o.within == spec.tolerance.holds(o.value)
        assert o.thesis == spec.thesis and o.unit == spec.unit
