"""Protocol grids, trial lists and their validation."""

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from vibrissa.experiments.protocols import get_protocol, parse_grid
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSettings


def test_thesis_grids():
    p4 = get_protocol("radial-distance")
    assert len(p4.radial_distances_mm) == 101 and len(p4.speeds_mm_s) == 26
    assert p4.radial_distances_mm[0] == 80 and p4.radial_distances_mm[-1] == 180
    assert p4.speeds_mm_s[0] == 36 and p4.speeds_mm_s[-1] == 216
    assert p4.n_trials == 10504
    assert p4.sensor.sample_rate_hz == 1000 and p4.window_s == (0.6, 0.7)
    p5 = get_protocol("angle-texture")
    assert p5.angles_deg == (10, 20, 30, 40, 50, 60, 70, 80)
    assert len(p5.speeds_mm_s) == 11 and p5.speeds_mm_s[0] == 6 and p5.speeds_mm_s[-1] == 106
    assert p5.textures == ("aluminium", "p600", "p180", "p80")
    assert p5.n_trials == 8 * 11 * 4 * 4 and p5.sensor.sample_rate_hz == 4000


def test_trials_cover_the_grid_in_four_sets_with_interleaved_order():
    p = get_protocol("radial-distance", quick=True)
    trials = p.trials()
    assert len(trials) == p.n_trials == 80
    assert sorted({t.set for t in trials}) == [1, 2, 3, 4]
    per_set = [[tuple(t.labels.values()) for t in trials if t.set == s] for s in (1, 2, 3, 4)]
    assert all(ps == per_set[0] for ps in per_set)  # every set is a complete grid
    orders = [t.order for t in trials]
    assert sorted(orders) == list(range(80))  # each session slot used once
    assert orders != sorted(orders)  # randomly interleaved
    assert {t.direction for t in trials if t.set in (1, 3)} == {1}


def test_parse_grid():
    assert parse_grid("80:180:20") == (80, 100, 120, 140, 160, 180)
    assert parse_grid("36:216:#26")[1] == pytest.approx(43.2)
    assert parse_grid("1, 2,3") == (1, 2, 3)
    for bad in ["", "1:2", "a,b", "5:1:1", "0:1:0", "1:2:#0"]:
        with pytest.raises(ValueError, match="grid|parse|empty"):
            parse_grid(bad)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"radial_distances_mm": (80.0, 190.0)}, "radial_distance_mm"),
        ({"speeds_mm_s": (36.0, 800.0)}, "speed_mm_s"),
        ({"speeds_mm_s": ()}, "speed"),
        ({"runs": 0}, "runs"),
        ({"directions": (2,)}, "directions"),
    ],
)
def test_bad_radial_distance_protocols(kwargs, match):
    with pytest.raises(ValueError, match=match):
        get_protocol("radial-distance", **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"angles_deg": (10.0, 95.0)}, "angle_deg"),
        ({"angles_deg": (0.0,)}, "point contacts"),
        ({"textures": ("p120",)}, "texture"),
    ],
)
def test_bad_angle_texture_protocols(kwargs, match):
    with pytest.raises(ValueError, match=match):
        get_protocol("angle-texture", **kwargs)


def test_unknown_protocol():
    with pytest.raises(ValueError, match="radial-distance"):
        get_protocol("texture-only")


def test_fingerprint_tracks_every_parameter():
    a = get_protocol("radial-distance", quick=True)
    assert a.fingerprint() == get_protocol("radial-distance", quick=True).fingerprint()
    assert a.fingerprint() != get_protocol("radial-distance", quick=True, seed=2).fingerprint()
    assert a.fingerprint() != a.with_sensor(noise_v=0.01).fingerprint()
    assert a.fingerprint() != a.with_sensor(calibration_mm=(90.0, 60.0)).fingerprint()


def test_sensor_settings_are_nested():
    p4 = get_protocol("radial-distance")
    assert p4.sensor == HallSettings(calibration_mm=(80.0, 60.0))
    assert p4.to_dict()["sensor"]["calibration_mm"] == (80.0, 60.0)
    p5 = get_protocol("angle-texture")
    assert p5.sensor.calibration_mm is None  # the thesis' point: 60 mm at r = 150 mm
    assert p5.sensor.calibration_point(preset(p5.whisker)) == (150.0, 60.0)
    q = p4.with_sensor(noise_v=0.0, sample_rate_hz=2000.0)
    assert q.sensor.noise_v == 0.0 and q.sensor.sample_rate_hz == 2000.0
    assert q.sensor.calibration_mm == (80.0, 60.0)
    assert q.radial_distances_mm == p4.radial_distances_mm
    assert get_protocol("radial-distance", sensor=HallSettings(noise_v=0.0)).sensor.noise_v == 0.0


@pytest.mark.parametrize(
    ("sensor", "match"),
    [
        ({"sample_rate_hz": 3000.0}, "dt_s"),  # 0.25 ms does not divide 1/3000 s
        ({"sample_rate_hz": -1.0}, "sample_rate_hz"),
        ({"noise_v": -0.1}, "noise_v"),
        ({"calibration_mm": (190.0, 60.0)}, "calibration radius"),
    ],
)
def test_bad_sensor_settings(sensor, match):
    with pytest.raises(ValueError, match=match):
        get_protocol("radial-distance", quick=True).with_sensor(**sensor)


def test_sensor_must_be_hall_settings():
    with pytest.raises(TypeError, match="HallSettings"):
        get_protocol("radial-distance", quick=True, sensor={"noise_v": 0.0})


# --- properties of parse_grid ----------------------------------------------------------

_QUARTERS = st.integers(-4000, 4000).map(lambda k: k / 4)  # exact binary fractions


@settings(max_examples=50, deadline=None)
@given(start=_QUARTERS, step=st.integers(1, 400).map(lambda k: k / 4), count=st.integers(1, 200))
def test_parse_grid_step_ranges(start, step, count):
    stop = start + step * (count - 1)
    vals = parse_grid(f"{start!r}:{stop!r}:{step!r}")
    assert len(vals) == count
    assert list(vals) == sorted(vals) and all(math.isfinite(v) for v in vals)
    assert vals[0] == start and vals[-1] == pytest.approx(stop)


@settings(max_examples=50, deadline=None)
@given(a=_QUARTERS, b=_QUARTERS, num=st.integers(1, 200))
def test_parse_grid_counted_ranges(a, b, num):
    start, stop = min(a, b), max(a, b)
    if start == stop and num > 1:  # the same value num times: refused, each value once
        with pytest.raises(ValueError, match="repeats"):
            parse_grid(f"{start!r}:{stop!r}:#{num}")
        return
    vals = parse_grid(f"{start!r}:{stop!r}:#{num}")
    assert len(vals) == num
    assert list(vals) == sorted(vals) and all(math.isfinite(v) for v in vals)
    assert vals[0] == start and (num == 1 or vals[-1] == stop)


@settings(max_examples=50, deadline=None)
@given(
    values=st.lists(
        st.floats(-1e6, 1e6), min_size=1, max_size=20, unique_by=lambda v: float(np.round(v, 9))
    )
)
def test_parse_grid_lists(values):
    vals = parse_grid(",".join(repr(v) for v in values))
    assert sorted(vals) == sorted(float(np.round(v, 9)) for v in values)


_TOKENS = st.sampled_from(
    [
        ":",
        ",",
        "#",
        " ",
        "-",
        ".",
        "e",
        "1",
        "0",
        "5",
        "nan",
        "inf",
        "1e308",
        "1e-300",
        "1e400",
        "#0",
        "#-1",
        "_",
        "x",
        "١",
    ]
)
_HOSTILE = st.text(max_size=12) | st.lists(
    _TOKENS | st.floats().map(repr) | st.integers().map(str), max_size=7
).map("".join)


@settings(max_examples=50, deadline=None)
@example("1:1e308:1e-300")  # was an OverflowError (issue 13, finding 3)
@example("0:1e300:#3")  # was (0.0, inf, inf)
@example("0:10:1e-12")  # was a 73 TiB allocation
@example("1:2:#100000000")  # was a hang growing memory
@example("100,100,100")  # silently tripled every trial (finding 8)
@given(text=_HOSTILE)
def test_parse_grid_hostile_text_is_a_value_error_or_a_finite_grid(text):
    try:
        vals = parse_grid(text)
    except ValueError as exc:
        assert "grid" in str(exc)
    else:
        assert vals and all(math.isfinite(v) for v in vals)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1:2:#100000000", "more than 10000 values"),
        ("50:100:0.0000001", "more than 10000 values"),
        ("100,100,100", "repeats the value"),
        ("", "empty grid"),
        ("inf:5:1", "non-finite"),
    ],
)
def test_parse_grid_bounds_name_the_limit(text, message):
    with pytest.raises(ValueError, match=message):
        parse_grid(text, "--speeds")
