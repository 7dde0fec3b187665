"""The XY stage's MI loop on the simulated whisker."""

import numpy as np
import pytest

from vibrissa.robots import LatencyModel, PoleStimulus, SurfaceStimulus, XYStage, run_trial
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor, calibrated_gain
from vibrissa.whisker.rod import RodModel

G = preset("xy-robot")


@pytest.fixture(scope="module")
def model():
    return RodModel(G)


@pytest.fixture(scope="module")
def sensor():
    return HallSensor(calibrated_gain(G, calibration_mm=(80.0, 60.0)), sample_rate_hz=1000)


def trial(model, sensor, r=130.0, v=100.0, direction=1, seed=0, stage=None):
    return run_trial(
        stage or XYStage(),
        model,
        sensor,
        PoleStimulus(r),
        v,
        direction,
        (0.325, 0.325),
        np.random.default_rng(seed),
    )


def test_trial_is_aligned_to_its_peak_and_has_the_window(model, sensor):
    res = trial(model, sensor)
    assert res.signal_v.shape == (2, 651)
    assert res.peak_index == 325
    dev = np.abs(res.signal_v[0] - 2.5)
    assert int(np.argmax(dev)) == 325
    assert res.signal_v[0, 325] > 2.5  # +x deflection raises the x output
    assert abs(res.signal_v[0, 0] - 2.5) < 0.1 * dev.max()  # contact just begun at -325 ms
    lat = XYStage().latency
    assert abs(res.latency_s - lat.latency_s) <= lat.duty_cycle_s / 2


def test_events_are_ordered_and_the_retraction_follows_the_threshold_by_the_latency(model, sensor):
    res = trial(model, sensor, r=120.0, v=72.0, seed=5)
    assert res.contact_onset_s < res.threshold_time_s < res.retract_start_s < 0.0
    assert 0.0 < res.contact_end_s  # the peak comes while the stage brakes and returns
    # the command takes effect exactly one drawn latency after the crossing
    assert res.retract_start_s - res.threshold_time_s == pytest.approx(res.latency_s, abs=1e-9)
    assert res.mi_latency_s == pytest.approx(res.retract_start_s - res.contact_onset_s)
    assert not res.slipped_off and not res.saturated
    # the recorded signal crosses the threshold where the event says (one sample)
    x = res.signal_v[0] - 2.5
    k = int(np.argmax(x >= XYStage().threshold_v))
    assert abs((k - res.peak_index) / 1000 - res.threshold_time_s) <= 1.5e-3


def test_contact_near_the_tip_at_speed_slips_off_before_the_retraction(model, sensor):
    res = trial(model, sensor, r=183.0, v=216.0, seed=1)
    assert res.slipped_off
    # the MI contact ended while the stage was still advancing
    stage = XYStage()
    assert res.contact_end_s < res.retract_start_s + 216.0 / stage.acceleration_mm_s2


def test_retraction_follows_the_threshold_after_the_latency(model, sensor):
    slow = trial(model, sensor, v=40.0)
    fast = trial(model, sensor, v=200.0)
    assert np.isfinite(slow.threshold_time_s) and np.isfinite(fast.threshold_time_s)
    # the threshold is reached sooner after first contact
    assert (fast.threshold_time_s - fast.contact_onset_s) < (
        slow.threshold_time_s - slow.contact_onset_s
    )
    # the object keeps advancing for the latency: faster means a deeper, longer contact
    assert fast.peak_deflection_v > slow.peak_deflection_v
    assert fast.contact_duration_s > slow.contact_duration_s


def test_mirrored_direction_records_an_equivalent_trial(model, sensor):
    a = trial(model, sensor, direction=1, seed=3)
    b = trial(model, sensor, direction=-1, seed=3)
    # same random draws, mirrored mechanics, converted back: same signal up to noise
    assert np.abs(a.signal_v - b.signal_v).max() < 0.02


def test_latency_jitter_is_uniform_over_the_duty_cycle():
    lat = LatencyModel(0.3, 0.04)
    draws = np.array([lat.sample(np.random.default_rng(i)) for i in range(2000)])
    assert draws.min() >= 0.28 and draws.max() <= 0.32
    assert draws.std() == pytest.approx(0.04 / np.sqrt(12), rel=0.1)


def test_surface_trial_records_at_4khz(model):
    s4 = HallSensor(calibrated_gain(G), sample_rate_hz=4000)
    res = run_trial(
        XYStage(),
        model,
        s4,
        SurfaceStimulus("p80", 45.0),
        56.0,
        1,
        (0.75, 0.75),
        np.random.default_rng(0),
        dt_s=1.25e-4,
    )
    assert res.signal_v.shape == (2, 6001)
    assert res.peak_deflection_v > 0.05


def test_bad_trial_input(model, sensor):
    with pytest.raises(ValueError, match="speed_mm_s"):
        trial(model, sensor, v=800.0)
    with pytest.raises(ValueError, match="radial_distance_mm"):
        trial(model, sensor, r=200.0)
    with pytest.raises(ValueError, match="direction"):
        trial(model, sensor, direction=0)
    with pytest.raises(ValueError, match="duty_cycle_s"):
        LatencyModel(0.01, 0.1)


def test_retraction_clears_the_whisker_even_after_a_deep_fast_contact(model, sensor):
    res = trial(model, sensor, r=130.0, v=216.0)
    tail = res.signal_v[0, -60:] - 2.5  # the last 60 ms of the window
    assert abs(tail.mean()) < 0.1 * res.peak_deflection_v  # back near rest (ringing allowed)


def test_mirrored_surface_trial_is_equivalent(model):
    s4 = HallSensor(calibrated_gain(G), sample_rate_hz=4000)
    peaks = []
    for d in (1, -1):
        res = run_trial(
            XYStage(),
            model,
            s4,
            SurfaceStimulus("aluminium", 50.0),
            56.0,
            d,
            (0.75, 0.75),
            np.random.default_rng(2),
            dt_s=1.25e-4,
        )
        peaks.append(res.peak_deflection_v)
    assert peaks[1] == pytest.approx(peaks[0], rel=0.1)
