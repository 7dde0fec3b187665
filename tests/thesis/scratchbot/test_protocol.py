"""The SCRATCHbot pole protocol (thesis 6.3): grid, geometry, refusals, one condition."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.whisking import pole_position_mm
from vibrissa.thesis.scratchbot.protocol import WINDOW_S, ScratchbotProtocol, scratchbot_protocol


def test_the_thesis_grid():
    p = scratchbot_protocol()
    assert p.radial_distances_mm == (70.0, 100.0, 130.0)
    assert p.whisk_frequencies_hz == (2.0, 4.0, 6.0)
    assert p.n_trials == 9 * p.n_whisks
    assert scratchbot_protocol(quick=True).n_trials < p.n_trials
    assert p.fingerprint() != scratchbot_protocol(seed=1).fingerprint()
    assert p.fingerprint() == scratchbot_protocol().fingerprint()


@pytest.mark.parametrize("angle", [3.0, 6.0, 20.0])
def test_the_pole_touches_the_turned_whisker_at_the_radial_distance(angle):
    x, z = pole_position_mm(100.0, angle, 0.5, 1.0)
    a = math.radians(angle)
    # distance of the pole's axis from the turned shaft's centre line, and where along it
    along = x * math.sin(a) + z * math.cos(a)
    across = x * math.cos(a) - z * math.sin(a)
    assert along == pytest.approx(100.0) and across == pytest.approx(1.5)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"whisk_frequencies_hz": (2.0, 0.0)}, "whisk frequency must be > 0"),
        ({"whisk_frequencies_hz": (-4.0,)}, "whisk frequency must be > 0"),
        ({"sigma_z": -0.7}, "sigma_z"),
        ({"tau_z_periods": -0.25}, "tau_z_periods"),
        ({"contact_angle_deg": 0.0}, "inside the whisker's reach at rest"),
        ({"contact_angle_deg": -5.0}, "inside the whisker's reach at rest"),
        ({"contact_angle_deg": 12.0}, "never reaches the pole"),
        ({"radial_distances_mm": (250.0,)}, "radial_distance_mm"),
        ({"n_whisks": 1}, "n_whisks"),
        ({"whisker": "nope"}, "unknown whisker preset"),
        ({"rcp_settings": ((0.7, 0.25), (-2.0, 0.1))}, "sigma_z"),
        ({"rcp_settings": ()}, "rcp_settings"),
        ({"rcp_whisk_frequency_hz": 0.0}, "frequency_hz"),
        ({"rcp_radial_distance_mm": 0.2}, "radial_distance_mm"),
        ({"rcp_whisks": 0}, "rcp_whisks"),
        ({"n_seeds": 0}, "n_seeds"),
        ({"contact_signal_scale": 0.0}, "contact_signal_scale"),
    ],
)
def test_bad_input_is_refused_in_one_line_before_any_simulation(kwargs, match, monkeypatch):
    import vibrissa.thesis.scratchbot.protocol as mod

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("simulated")

    monkeypatch.setattr(mod, "run_whisking", boom)
    with pytest.raises(ValueError, match=match) as err:
        ScratchbotProtocol(**kwargs)
    assert "\n" not in str(err.value)


def test_one_condition_keeps_each_whisk_with_its_own_samples():
    p = ScratchbotProtocol(radial_distances_mm=(100.0,), whisk_frequencies_hz=(4.0,), n_whisks=2)
    res = p.simulate_condition(0)
    fs = p.sensor.sample_rate_hz
    assert res["signal"].shape == (1, 2, 2, int(WINDOW_S * fs))  # one session
    per = int(fs / 4.0)
    x = res["signal"][0, :, 0]
    # outside its whisk the window is at rest; inside it the pole deflects the whisker
    assert np.all(x[:, per:] == 2.5)
    assert np.all(np.abs(x[:, :per] - 2.5).max(axis=1) > 0.5)
    assert res["force_n"].max() > 0 and res["saturated"][0] == 0.0
    # the in-air reference is what was subtracted
    whisk1 = res["raw_v"][per : 2 * per] - res["air_v"][per : 2 * per] + 2.5
    np.testing.assert_allclose(x[0, :per], whisk1)


def test_sessions_differ_in_the_sensor_noise_only():
    kw = dict(radial_distances_mm=(100.0,), whisk_frequencies_hz=(4.0,), n_whisks=2)
    three = ScratchbotProtocol(seed=2, n_seeds=3, **kw)
    assert three.n_trials == 3 * 2
    res = three.simulate_condition(0)
    assert res["signal"].shape[0] == 3
    # a session is the single session of its seed
    alone = ScratchbotProtocol(seed=3, **kw).simulate_condition(0)
    np.testing.assert_array_equal(res["signal"][1], alone["signal"][0])
    first = ScratchbotProtocol(seed=2, **kw).simulate_condition(0)
    np.testing.assert_array_equal(res["raw_v"], first["raw_v"])
    diff = np.abs(res["signal"][0] - res["signal"][2])
    assert 0 < diff.max() < 0.1  # noise, not another whisk
    ds = three.build_dataset([res])
    assert list(ds["session_seed"].values) == [2, 2, 3, 3, 4, 4]
    assert list(ds["whisk"].values) == [1, 2] * 3
    with pytest.raises(ValueError, match="n_seeds must be a positive integer"):
        ScratchbotProtocol(n_seeds=0)
