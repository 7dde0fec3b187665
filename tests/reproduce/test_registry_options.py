"""An experiment's selection option (``choices``) and the protocol it shapes (``protocol_for``)."""

from __future__ import annotations

import pytest

from vibrissa.reproduce import get_experiment, run_experiment
from vibrissa.reproduce.registry import Option

FLOORS = ("rough-carpet", "vinyl", "smooth-carpet", "tarmac")


def _opt() -> Option:
    return Option(
        "floors", ",".join(FLOORS), "Floors.", minimum=2, choices=FLOORS, item="floor texture"
    )


def test_a_selection_is_parsed_from_text_or_taken_as_names():
    o = _opt()
    assert o.check("vinyl, tarmac") == ("vinyl", "tarmac")
    assert o.check(["tarmac", "vinyl"]) == ("tarmac", "vinyl")
    assert o.check(o.default) == FLOORS


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ("vinyl,shag", "--floors: unknown floor texture 'shag'; choose from rough-carpet"),
        ("vinyl", "--floors needs at least 2"),
        ("", "--floors needs at least 2"),
        ("vinyl,vinyl", "each name once"),
        (3, "comma-separated list"),
    ],
)
def test_a_bad_selection_names_the_flag(value, match):
    with pytest.raises(ValueError, match=match):
        _opt().check(value)


def test_integer_options_are_unchanged():
    o = Option("n_seeds", 5, "Repeats.")
    assert o.check(3) == 3
    with pytest.raises(ValueError, match="--n-seeds must be an integer >= 1"):
        o.check(0)


def test_protocol_for_shapes_the_floor_session_and_defaults_to_protocol():
    exp = get_experiment("floor-texture")
    p = exp.protocol_for(True, 0, {"floors": ("tarmac", "vinyl")})
    assert p.floors == ("vinyl", "tarmac")  # the thesis' order
    assert exp.protocol_for(True, 0, {}).floors == FLOORS
    ch5 = get_experiment("angle-texture")
    assert ch5.protocol_for(True, 0, {}).fingerprint() == ch5.protocol(True, 0).fingerprint()


def test_run_experiment_refuses_an_unknown_floor_before_any_work(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(ValueError, match="unknown floor texture 'shag'"):
        run_experiment("floor-texture", out, quick=True, floors="vinyl,shag")
    assert not out.exists()
