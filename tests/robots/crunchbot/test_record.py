"""The run record's shape checks."""

import numpy as np
import pytest

from vibrissa.robots.crunchbot import PRESETS, RunRecord, synthetic_log


def _record(**changes):
    log = synthetic_log(PRESETS["slam"], seconds=3.0, seed=1)
    t = log.n_steps
    n = 200 * t
    kw = dict(
        arena=PRESETS["slam"],
        seed=1,
        log=log,
        sample_rate_hz=2000.0,
        time_s=np.arange(n) / 2000.0,
        hall_v=np.zeros((n, 6, 2), np.float32),
        pose=np.zeros((n, 3)),
        step_start=np.arange(t + 1) * 200,
        contact_true_m=np.full((t, 4), np.nan),
        floor_texture_true=np.full((t, 2), ""),
        floor_texture_pred=np.full((t, 2), ""),
        latency_s={"floor_texture": np.array([1e-4])},
        wall_seconds=0.5,
    )
    kw.update(changes)
    return RunRecord(**kw)


def test_a_consistent_record_reports_its_time_and_speed():
    rec = _record()
    assert rec.seconds == pytest.approx(rec.log.n_steps * 0.1)
    assert rec.real_time_factor == pytest.approx(rec.seconds / 0.5)


@pytest.mark.parametrize(
    "name, value, match",
    [
        ("hall_v", np.zeros((5, 6, 2)), "hall_v"),
        ("step_start", np.zeros(3, int), "step_start"),
        ("sample_rate_hz", 0.0, "sample_rate_hz"),
        ("latency_s", {"fft": np.zeros(1)}, "unknown classifier"),
    ],
)
def test_inconsistent_records_are_refused_naming_the_field(name, value, match):
    with pytest.raises(ValueError, match=match):
        _record(**{name: value})
