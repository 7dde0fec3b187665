"""The observables' specifications (vibrissa.experiments.identify.SPECS, Tolerance).

Each tolerance's ``holds`` is checked against its printed text, read back by an
independent parser, on values at, just inside and just outside its bounds.
"""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vibrissa.experiments.identify import SPECS, ObservableSpec, Tolerance

# The strings printed by `vibrissa identify` and stored in docs/runs/identify.json.
TEXTS = {
    "resonance_hz": "median between 25 Hz and 35 Hz",
    "mi_latency_ms": "median within 300 +/- 30 ms",
    "duration_grows_with_speed": "at least 0.9",
    "ringing_chapter4": "median at most 0.1",
    "ringing_chapter5": "between 0.1 and 0.9",
    "contact_duration_chapter5_ms": "median within 300 +/- 60 ms",
    "closest_usable_contact_mm": "80 +/- 10 mm",
    "tip_zone_mm": "at most 10 mm at every speed up to 216 mm/s",
    "above_216_mm_s": "at least 0.75",
}

_NUM = r"(-?\d+(?:\.\d+)?)"
_UNIT = r"(?: [a-zA-Z/%]+)?"


def interval_of(spec: ObservableSpec) -> tuple[float, float]:
    """The closed interval a tolerance's text states (a ``%`` is of the thesis value)."""
    text = spec.tolerance.text()
    body = re.sub(r"^median ", "", text).replace(spec.tolerance.scope, "").strip()
    if m := re.fullmatch(rf"within {_NUM} %", body):
        assert spec.thesis_value is not None
        half = abs(spec.thesis_value) * float(m[1]) / 100
        return spec.thesis_value - half, spec.thesis_value + half
    if m := re.fullmatch(rf"(?:within )?{_NUM} \+/- {_NUM}{_UNIT}", body):
        return float(m[1]) - float(m[2]), float(m[1]) + float(m[2])
    if m := re.fullmatch(rf"at least {_NUM}{_UNIT}", body):
        return float(m[1]), math.inf
    if m := re.fullmatch(rf"at most {_NUM}{_UNIT}", body):
        return -math.inf, float(m[1])
    if m := re.fullmatch(rf"between {_NUM}{_UNIT} and {_NUM}{_UNIT}", body):
        return float(m[1]), float(m[2])
    raise AssertionError(f"cannot read tolerance text {text!r}")


def test_specs_names_are_unique_and_in_the_documented_order():
    names = [s.name for s in SPECS]
    assert len(set(names)) == len(names) == 9
    assert names == list(TEXTS)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_tolerance_text_is_byte_identical_to_the_stored_one(spec):
    assert spec.tolerance.text() == TEXTS[spec.name]


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.name)
def test_holds_at_the_bounds_and_not_one_ulp_outside(spec):
    lo, hi = interval_of(spec)
    tol = spec.tolerance
    for bound, outward in ((lo, -math.inf), (hi, math.inf)):
        if math.isfinite(bound):
            assert tol.holds(bound)
            assert not tol.holds(math.nextafter(bound, outward))
    assert not tol.holds(math.nan)


@given(
    spec=st.sampled_from(SPECS),
    frac=st.floats(min_value=1e-9, max_value=1.0),
    upper=st.booleans(),
)
def test_holds_agrees_with_the_text_just_inside_and_just_outside(spec, frac, upper):
    lo, hi = interval_of(spec)
    bound = hi if upper else lo
    if not math.isfinite(bound):
        bound, upper = (lo, False) if upper else (hi, True)
    span = hi - lo if math.isfinite(hi - lo) else max(abs(bound), 1.0)
    step = frac * span / 2
    inside = bound - step if upper else bound + step
    outside = bound + step if upper else bound - step
    assert spec.tolerance.holds(inside)
    assert not spec.tolerance.holds(outside)


@given(spec=st.sampled_from(SPECS), x=st.floats(allow_nan=False, min_value=-1e6, max_value=1e6))
def test_holds_is_membership_of_the_stated_interval(spec, x):
    lo, hi = interval_of(spec)
    assert spec.tolerance.holds(x) == (lo <= x <= hi)


def test_a_tolerance_without_its_bounds_is_refused():
    with pytest.raises(ValueError, match="needs"):
        Tolerance("between", low=0.1)
    with pytest.raises(ValueError, match="unknown"):
        Tolerance("around", target=1.0)  # type: ignore[arg-type]


def test_the_thesis_statement_ends_with_its_section():
    for spec in SPECS:
        assert spec.thesis.endswith(f" ({spec.section})")
        assert spec.thesis_value is None or math.isfinite(spec.thesis_value)
