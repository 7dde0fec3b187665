"""A trial's physical variability as run_trial applies it (robots.xy_variability)."""

import numpy as np
import pytest

from vibrissa.robots import PoleStimulus, XYStage, run_trial
from vibrissa.robots.xy_variability import TrialPerturbation
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


def perturbation(**kw):
    d = dict(
        sensor_offset_v=np.zeros(2),
        sensor_gain=1.0,
        rest_angle_rad=np.zeros(2),
        position_offset_mm=np.zeros(2),
        modulus_factor=1.0,
    )
    d.update(kw)
    return TrialPerturbation(**d)


def trial(model, sensor, p, direction=1):
    return run_trial(
        XYStage(),
        model,
        sensor,
        PoleStimulus(130.0),
        100.0,
        direction,
        (0.325, 0.325),
        np.random.default_rng(3),
        perturbation=p,
    )


def test_no_perturbation_is_the_same_trial_as_a_zero_one(model, sensor):
    a = trial(model, sensor, perturbation())
    b = trial(model, sensor, perturbation())
    np.testing.assert_array_equal(a.signal_v, b.signal_v)


def test_the_hall_offset_moves_the_resting_output(model, sensor):
    a = trial(model, sensor, perturbation())
    b = trial(model, sensor, perturbation(sensor_offset_v=np.array([0.02, -0.03])))
    # before the contact the whisker rests: the output moves by the offset (ADC, noise)
    rest = slice(0, 20)
    d = b.signal_v[:, rest].mean(axis=1) - a.signal_v[:, rest].mean(axis=1)
    np.testing.assert_allclose(d, [0.02, -0.03], atol=2e-3)


def test_a_gain_change_scales_the_peak(model, sensor):
    a = trial(model, sensor, perturbation())
    b = trial(model, sensor, perturbation(sensor_gain=1.05))
    assert b.peak_deflection_v / a.peak_deflection_v == pytest.approx(1.05, rel=0.02)


def test_the_object_placed_higher_is_a_contact_further_out(model, sensor):
    a = trial(model, sensor, perturbation(position_offset_mm=np.array([0.0, 2.0])))
    b = run_trial(
        XYStage(),
        model,
        sensor,
        PoleStimulus(132.0),
        100.0,
        1,
        (0.325, 0.325),
        np.random.default_rng(3),
        perturbation=perturbation(),
    )
    c = trial(model, sensor, perturbation())
    assert a.peak_deflection_v == pytest.approx(b.peak_deflection_v, rel=0.01)
    assert abs(a.peak_deflection_v - c.peak_deflection_v) > 0.01 * c.peak_deflection_v
