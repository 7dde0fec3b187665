"""The XY robot's physical trial-to-trial variability sources against their stated laws."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.stats
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.robots.xy_variability import (
    SOURCES,
    TrialPerturbation,
    TrialVariability,
    VariabilityState,
)

N = 20_000


def _draws(variability: TrialVariability, n: int = N, seed: int = 1) -> list[TrialPerturbation]:
    state = VariabilityState(variability)
    rng = np.random.default_rng(seed)
    return [
        state.draw(rng, previous_peak_tan=0.0, previous_direction=0, interval_s=4.0)
        for _ in range(n)
    ]


def _only(name: str, **kw: object) -> TrialVariability:
    return TrialVariability(
        **{s: s == name for s in ("hall_drift", "creep", "placement", "modulus")}, **kw
    )


def test_defaults_all_on_and_cited() -> None:
    v = TrialVariability()
    assert v.enabled() == ("hall_drift", "creep", "placement", "modulus")
    assert TrialVariability.off().enabled() == ()
    assert set(SOURCES) == set(v.enabled())
    d = v.to_dict()
    assert d["enabled"] == list(v.enabled())
    assert d["hall_offset_tc_v_per_k"] == pytest.approx(1.2e-4)
    assert d["creep_contact_s"] == pytest.approx(0.191, abs=1e-3)


def test_off_gives_exactly_none() -> None:
    state = VariabilityState(TrialVariability.off())
    rng = np.random.default_rng(3)
    for direction in (1, -1, 1, 0):
        p = state.draw(rng, previous_peak_tan=0.3, previous_direction=direction, interval_s=4.0)
        assert p == TrialPerturbation.none()
    assert state.residual_rest_angle_rad() == 0.0
    assert TrialPerturbation.none() != TrialPerturbation(
        np.ones(2), 1.0, np.zeros(2), np.zeros(2), 1.0
    )


def test_placement_is_gaussian_with_a_third_of_the_repeatability() -> None:
    pos = np.array([p.position_offset_mm for p in _draws(_only("placement"))])
    sd = 0.01 / 3
    for axis in range(2):
        x = pos[:, axis]
        assert abs(x.mean()) < 4 * sd / math.sqrt(N)
        assert x.std() == pytest.approx(sd, rel=4 / math.sqrt(2 * N))
        assert scipy.stats.kstest(x, "norm", args=(0.0, sd)).pvalue > 1e-3
    assert abs(np.corrcoef(pos.T)[0, 1]) < 4 / math.sqrt(N)


def test_hall_drift_is_linear_in_a_gaussian_room_temperature() -> None:
    v = _only("hall_drift")
    draws = _draws(v)
    temp = np.array([p.temperature_k for p in draws])
    off = np.array([p.sensor_offset_v for p in draws])
    gain = np.array([p.sensor_gain for p in draws])
    assert scipy.stats.kstest(temp, "norm", args=(0.0, 1.0)).pvalue > 1e-3
    np.testing.assert_allclose(off[:, 0], 1.2e-4 * temp)
    np.testing.assert_array_equal(off[:, 0], off[:, 1])
    np.testing.assert_allclose(gain, 1.0 + 4e-5 * temp)
    assert off[:, 0].std() == pytest.approx(1.2e-4, rel=4 / math.sqrt(2 * N))
    assert all(p.modulus_factor == 1.0 and not p.rest_angle_rad.any() for p in draws)


def test_magnet_coefficient_enters_only_a_non_ratiometric_sensor() -> None:
    ratio = _draws(_only("hall_drift"), n=50)
    linear = _draws(_only("hall_drift", hall_ratiometric=False), n=50)
    t = np.array([p.temperature_k for p in linear])
    np.testing.assert_allclose([p.temperature_k for p in ratio], t)
    np.testing.assert_allclose([p.sensor_gain for p in linear], 1.0 + (4e-5 - 0.0012) * t)


def test_modulus_factor_follows_the_same_temperature() -> None:
    draws = _draws(TrialVariability(creep=False, placement=False), n=2000)
    t = np.array([p.temperature_k for p in draws])
    np.testing.assert_allclose([p.modulus_factor for p in draws], 1.0 - 0.004 * t)
    assert np.std([p.modulus_factor for p in draws]) == pytest.approx(0.004, rel=0.1)


def test_switching_one_source_leaves_the_others_draws_unchanged() -> None:
    a = _draws(TrialVariability(), n=100, seed=9)
    b = _draws(TrialVariability(hall_drift=False, modulus=False), n=100, seed=9)
    for p, q in zip(a, b, strict=True):
        np.testing.assert_array_equal(p.position_offset_mm, q.position_offset_mm)


def test_creep_of_one_element_relaxes_exponentially() -> None:
    tau, a, tc = 2.5, 0.05, 0.2
    v = _only("creep", creep_times_s=(tau,), creep_per_decade=a, creep_contact_s=tc)
    rng = np.random.default_rng(0)
    peak = 0.2
    after = a * math.atan(peak) * (1 - math.exp(-tc / tau))
    for dt in (0.0, 0.5, 2.5, 4.0, 10.0):
        state = VariabilityState(v)
        p = state.draw(rng, previous_peak_tan=peak, previous_direction=-1, interval_s=dt)
        assert p.rest_angle_rad[0] == pytest.approx(-after * math.exp(-dt / tau), rel=1e-12)
        assert p.rest_angle_rad[1] == 0.0


def test_default_creep_is_the_analytic_prony_sum() -> None:
    v = _only("creep")
    state = VariabilityState(v)
    p = state.draw(
        np.random.default_rng(0), previous_peak_tan=0.25, previous_direction=1, interval_s=3.6
    )
    tau = np.array(v.creep_times_s)
    expect = np.sum(
        0.06 * math.atan(0.25) * -np.expm1(-v.creep_contact_s / tau) * np.exp(-3.6 / tau)
    )
    assert p.rest_angle_rad[0] == pytest.approx(expect, rel=1e-12)
    assert p.rest_angle_rad[0] > 0  # toward the previous deflection


def test_unilateral_repeats_accumulate_and_alternation_cancels() -> None:
    """The thesis alternated directions so the whisker would not bend over time (4.2)."""
    rng = np.random.default_rng(0)
    uni, alt = VariabilityState(_only("creep")), VariabilityState(_only("creep"))
    for k in range(500):
        u = uni.draw(rng, previous_peak_tan=0.2, previous_direction=1, interval_s=3.8)
        a = alt.draw(rng, previous_peak_tan=0.2, previous_direction=(-1) ** k, interval_s=3.8)
    single = VariabilityState(_only("creep")).draw(
        rng, previous_peak_tan=0.2, previous_direction=1, interval_s=3.8
    )
    assert u.rest_angle_rad[0] > 5 * single.rest_angle_rad[0]
    assert abs(a.rest_angle_rad[0]) < 2 * single.rest_angle_rad[0]


@pytest.mark.parametrize(
    ("kwargs", "error", "name"),
    [
        ({"room_temperature_sd_k": -1.0}, ValueError, "room_temperature_sd_k"),
        ({"creep_per_decade": 1.5}, ValueError, "creep_per_decade"),
        ({"creep_times_s": ()}, ValueError, "creep_times_s"),
        ({"creep_times_s": (1.0, 1.0)}, ValueError, "creep_times_s"),
        ({"creep_times_s": (1.0, -2.0)}, ValueError, "creep_times_s"),
        ({"creep_contact_s": 0.0}, ValueError, "creep_contact_s"),
        ({"repeatability_mm": float("nan")}, ValueError, "repeatability_mm"),
        ({"modulus_tc_per_k": 0.5}, ValueError, "modulus_tc_per_k"),
        ({"hall_offset_tc_v_per_k": float("inf")}, ValueError, "hall_offset_tc_v_per_k"),
        ({"creep": 1}, TypeError, "creep"),
    ],
)
def test_bad_parameters_are_refused(kwargs: dict, error: type, name: str) -> None:
    with pytest.raises(error, match=name):
        TrialVariability(**kwargs)


def test_bad_draw_arguments_are_refused() -> None:
    state = VariabilityState()
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="previous_direction"):
        state.draw(rng, previous_peak_tan=0.1, previous_direction=2, interval_s=1.0)
    with pytest.raises(ValueError, match="previous_peak_tan"):
        state.draw(rng, previous_peak_tan=-0.1, previous_direction=1, interval_s=1.0)
    with pytest.raises(ValueError, match="interval_s"):
        state.draw(rng, previous_peak_tan=0.1, previous_direction=1, interval_s=-1.0)
    with pytest.raises(TypeError, match="rng"):
        state.draw(0, previous_peak_tan=0.1, previous_direction=1, interval_s=1.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="variability"):
        VariabilityState("all")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="sensor_offset_v"):
        TrialPerturbation(np.zeros(3), 1.0, np.zeros(2), np.zeros(2), 1.0)
    with pytest.raises(ValueError, match="sensor_gain"):
        TrialPerturbation(np.zeros(2), 0.0, np.zeros(2), np.zeros(2), 1.0)


@settings(max_examples=60, deadline=None)
@given(
    peaks=st.lists(st.floats(0.0, 1.0), min_size=1, max_size=20),
    directions=st.lists(st.sampled_from([-1, 0, 1]), min_size=20, max_size=20),
    interval_s=st.floats(0.0, 100.0),
    seed=st.integers(0, 2**32 - 1),
)
def test_creep_is_bounded_and_draws_are_deterministic(
    peaks: list[float], directions: list[int], interval_s: float, seed: int
) -> None:
    """The residual never exceeds the fully crept angle, and a seed repeats a session."""
    v = TrialVariability()
    bound = v.creep_per_decade * len(v.creep_times_s) * math.atan(max(peaks))
    runs = []
    for _ in range(2):
        state, rng = VariabilityState(v), np.random.default_rng(seed)
        out = []
        for p, d in zip(peaks, directions, strict=False):
            q = state.draw(rng, previous_peak_tan=p, previous_direction=d, interval_s=interval_s)
            assert abs(q.rest_angle_rad[0]) <= bound + 1e-15
            assert q.sensor_gain > 0 and q.modulus_factor > 0
            out.append(q)
        runs.append(out)
    assert runs[0] == runs[1]
