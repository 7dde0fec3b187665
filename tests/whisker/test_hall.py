"""Hall-effect sensor: calibration, linearity in tan, clamping, sampling, noise, ADC."""

import numpy as np
import pytest

from vibrissa.whisker.geometry import PRESETS
from vibrissa.whisker.hall import (
    HallSensor,
    HallSettings,
    calibrated_gain,
    calibration_point_mm,
    steps_per_sample,
)
from vibrissa.whisker.rod import RodModel

XY = PRESETS["xy-robot"]


def test_rest_is_half_supply_and_output_is_linear_in_tan():
    s = HallSensor(gain_v=10.0)
    t = np.array([[0.0, 0.0], [0.01, -0.02], [0.05, 0.1]])
    v = s.ideal_volts(t)
    assert v[0].tolist() == [2.5, 2.5]
    np.testing.assert_allclose(v[1], [2.6, 2.3])
    assert v[2].tolist() == [3.0, 3.5]


def test_calibration_maps_60mm_at_150mm_to_95_percent_of_supply():
    gain = calibrated_gain(XY)
    res = RodModel(XY).push(150, 60, friction=0.0)
    v = HallSensor(gain).ideal_volts(np.array([res.tan_x, res.tan_y]))
    assert v[0] == pytest.approx(0.95 * 5.0, abs=1e-6)
    assert v[1] == pytest.approx(2.5)
    # half the deflection stays inside the range
    half = RodModel(XY).push(150, 30, friction=0.0)
    vh = HallSensor(gain).ideal_volts(np.array([half.tan_x, 0.0]))[0]
    assert 2.5 < vh < 4.75


def test_output_clamps_at_the_calibrated_range():
    s = HallSensor(gain_v=10.0)
    v = s.ideal_volts(np.array([[1.0, -1.0]]))
    assert v.tolist() == [[4.75, 0.25]]


def test_short_whiskers_are_calibrated_at_a_proportional_point():
    r, d = calibration_point_mm(PRESETS["biotact-g1-80"])
    assert r == pytest.approx(80 * 150 / 185)
    assert d == pytest.approx(60 * r / 150)


def test_read_decimates_filters_quantises_and_adds_noise():
    s = HallSensor(gain_v=10.0, sample_rate_hz=1000, bandwidth_hz=None, noise_v=0.0, adc_bits=0)
    t = np.zeros((4000, 2))
    t[:, 0] = np.linspace(0, 0.1, 4000)
    v = s.read(t, internal_rate_hz=4000)
    assert v.shape == (1000, 2)
    np.testing.assert_allclose(v[:, 0], 2.5 + 10 * t[::4, 0])
    q = HallSensor(gain_v=10.0, sample_rate_hz=1000, bandwidth_hz=None, noise_v=0.0, adc_bits=12)
    vq = q.read(t, 4000)
    lsb = 5.0 / 4096
    np.testing.assert_allclose(vq / lsb, np.round(vq / lsb), atol=1e-9)
    assert np.abs(vq - v).max() <= lsb / 2 + 1e-12
    noisy = HallSensor(gain_v=10.0, sample_rate_hz=1000, noise_v=0.01, adc_bits=0)
    vn = noisy.read(np.zeros((40000, 2)), 4000, rng=np.random.default_rng(0))
    assert vn.std() == pytest.approx(0.01, rel=0.05)
    # a 2 kHz sensor bandwidth attenuates a 3 kHz component sampled internally at 20 kHz
    bw = HallSensor(gain_v=1.0, sample_rate_hz=20000, bandwidth_hz=2000, noise_v=0, adc_bits=0)
    tt = np.arange(20000) / 20000
    sine = np.column_stack([0.1 * np.sin(2 * np.pi * 3000 * tt), np.zeros_like(tt)])
    out = bw.read(sine, 20000)
    assert (out[2000:, 0] - 2.5).std() < 0.6 * (0.1 / np.sqrt(2))


def test_read_rejects_bad_input():
    s = HallSensor(gain_v=10.0)
    with pytest.raises(ValueError, match="integer multiple"):
        s.read(np.zeros((10, 2)), internal_rate_hz=1500)
    with pytest.raises(ValueError, match="shape"):
        s.read(np.zeros((10, 3)), internal_rate_hz=4000)
    with pytest.raises(ValueError, match="NaN"):
        s.read(np.full((10, 2), np.nan), internal_rate_hz=4000)
    with pytest.raises(ValueError, match="gain_v"):
        HallSensor(gain_v=0.0)
    with pytest.raises(ValueError, match="sample_rate_hz"):
        HallSensor(gain_v=1.0, sample_rate_hz=-1)
    with pytest.raises(ValueError, match="adc_bits"):
        HallSensor(gain_v=1.0, adc_bits=40)


def test_calibration_spans_the_sensors_own_supply_and_range():
    res = RodModel(XY).push(150, 60, friction=0.0)
    tan = np.array([res.tan_x, res.tan_y])
    s33 = HallSettings(supply_v=3.3, offset_v=1.65, range_fraction=0.8).calibrate(XY)
    assert s33.gain_v == pytest.approx(calibrated_gain(XY) * (0.8 * 3.3) / (0.9 * 5.0))
    assert s33.ideal_volts(tan)[0] == pytest.approx(1.65 + 0.4 * 3.3, abs=1e-6)
    assert s33.v_max == pytest.approx(1.65 + 0.4 * 3.3)
    assert calibrated_gain(XY, sensor=s33) == s33.gain_v


def test_settings_calibrate_into_a_sensor_with_the_same_fields():
    settings = HallSettings(sample_rate_hz=4000.0, noise_v=0.0, calibration_mm=(80.0, 60.0))
    sensor = settings.calibrate(XY, 28)
    assert sensor.gain_v == calibrated_gain(XY, 28, (80.0, 60.0))
    d = sensor.to_dict()
    assert d.pop("gain_v") == sensor.gain_v
    assert d == {k: v for k, v in vars(settings).items() if k != "calibration_mm"}
    # HallSensor's defaults are HallSettings' defaults
    assert HallSettings().calibrate(XY) == HallSensor(calibrated_gain(XY))
    assert HallSettings().calibration_point(XY) == calibration_point_mm(XY)
    with pytest.raises(ValueError, match="calibration radius"):
        HallSettings(calibration_mm=(200.0, 60.0)).calibration_point(XY)
    with pytest.raises(ValueError, match="calibration_mm"):
        HallSettings(calibration_mm=(80.0,))
    with pytest.raises(ValueError, match="noise_v"):
        HallSettings(noise_v=-1.0)


@pytest.mark.parametrize(
    ("dt_s", "rate", "steps"),
    [(2.5e-4, 1000.0, 4), (2.5e-4, 4000.0, 1), (1.25e-4, 4000.0, 2), (1e-3 / 3, 1000.0, 3)],
)
def test_steps_per_sample(dt_s, rate, steps):
    assert steps_per_sample(dt_s, rate) == steps


@pytest.mark.parametrize(("dt_s", "rate"), [(3e-4, 1000.0), (5e-4, 4000.0), (0.0, 1000.0)])
def test_steps_per_sample_rejects_a_step_that_does_not_divide_the_period(dt_s, rate):
    with pytest.raises(ValueError, match="dt_s"):
        steps_per_sample(dt_s, rate)


def test_a_shaft_too_compliant_to_tilt_the_follicle_cannot_be_calibrated():
    """Issue 13: the gain came out infinite and failed later, far from its cause."""
    g = XY.replace(
        youngs_modulus_gpa=0.01, base_radius_mm=0.001, tip_radius_mm=0.001, length_mm=2000
    )
    with pytest.raises(ValueError, match="does not tilt the follicle"):
        calibrated_gain(g)
