"""Tests of the import mapping (vibrissa.data.importers.mapping)."""

from __future__ import annotations

import json

import pytest
from data_recordings import XY_MAPPING
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.data import ImportMapping, ImportMappingError, load_mapping
from vibrissa.data.importers import parse_axis_option, parse_range


def test_load_mapping_files_and_errors(tmp_path) -> None:
    pj = tmp_path / "m.json"
    pj.write_text(json.dumps(XY_MAPPING))
    m = load_mapping(pj)
    assert isinstance(m, ImportMapping) and m.signal == "data" and m.channels == ("x", "y")
    pt = tmp_path / "m.toml"
    pt.write_text(
        'signal = "data"\nsample_rate_hz = 1000\nchannels = ["x", "y"]\n'
        '[[cell_axes]]\nname = "set"\nvalues = [1, 2, 3, 4]\n'
        '[[cell_axes]]\nname = "speed_mm_s"\nstart = 36\nstop = 50.4\nnum = 3\n'
        '[[cell_axes]]\nname = "radial_distance_mm"\nstart = 80\nstep = 1\n'
    )
    assert len(load_mapping(pt).cell_axes) == 3
    bad = tmp_path / "bad.json"
    bad.write_text("{signal: data")
    with pytest.raises(ValueError, match="bad.json is not valid JSON"):
        load_mapping(bad)
    with pytest.raises(ValueError, match="does not exist"):
        load_mapping(tmp_path / "none.json")
    for raw, match in [
        ({"sigal": "data"}, r"unknown mapping key\(s\) \['sigal'\]"),
        ({"sample_rate_hz": -1}, "sample_rate_hz"),
        ({"cell_axes": [{"name": "a", "start": 1}]}, "'num'.*'step'"),
        ({"cell_axes": [{"name": "a", "values": [1], "start": 1, "num": 1}]}, "more than one"),
        ({"cell_axes": [{"values": [1]}]}, "needs a 'name'"),
        ({"cell_axes": [{"name": "a", "stepp": 1}]}, "unknown key"),
        ({"cell_axes": ["a", "a"]}, "repeats"),
        ({"time_axis": 2}, "time_axis"),
        ({"ragged": "pad"}, "ragged"),
        ({"channels": ["x", "x"]}, "repeated"),
        ({"constants": {"set": 1}, "labels": {"set": "s"}}, "more than once"),
        ({"format": "xls"}, "format"),
    ]:
        with pytest.raises(ValueError, match=match):
            load_mapping(raw)


def test_parse_range_and_axis_option() -> None:
    assert parse_range("36:7.2:216")[:3] == [36.0, 43.2, 50.4]
    assert len(parse_range("36:7.2:216")) == 26 and parse_range("36:7.2:216")[-1] == 216.0
    assert parse_range("80:180") == [float(v) for v in range(80, 181)]
    assert parse_range("1,2,4") == [1, 2, 4]
    assert parse_range("0.5, 1") == [0.5, 1]
    assert parse_range("P80,P180") == ["P80", "P180"]
    with pytest.raises(ValueError):
        parse_range("1:0:3")
    with pytest.raises(ValueError):
        parse_range("5:1")
    assert parse_axis_option("set=1:4") == {"name": "set", "values": [1, 2, 3, 4]}
    assert parse_axis_option("speed_mm_s=@speeds") == {"name": "speed_mm_s", "from": "speeds"}
    assert parse_axis_option("trial") == {"name": "trial"}
    with pytest.raises(ValueError, match="--axis"):
        parse_axis_option("=1,2")


# --- property: any dict is a valid mapping or an ImportMappingError, never a crash ---

_KEYS = sorted(
    {
        "format",
        "sample_rate_hz",
        "channels",
        "labels",
        "constants",
        "ragged",
        "empty",
        "t0_s",
        "units",
        "attrs",
        "signal",
        "cell_axes",
        "time_axis",
        "trial_axes",
        "layout",
        "trial_column",
        "time_column",
    }
)
_SCALARS = (
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats()
    | st.text(max_size=8)
    | st.sampled_from(
        [
            "mat",
            "csv",
            "npz",
            "long",
            "wide",
            "crop",
            "skip",
            "error",
            "first",
            "last",
            "x,y",
            "trial",
            "set",
            "1:4",
            "data",
        ]
    )
)
_VALUES = st.recursive(
    _SCALARS,
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.dictionaries(
            st.sampled_from(["name", "values", "start", "stop", "step", "num", "from", "x"])
            | st.text(max_size=5),
            inner,
            max_size=4,
        )
    ),
    max_leaves=10,
)


@settings(max_examples=50, deadline=None)
@given(raw=st.dictionaries(st.sampled_from(_KEYS) | st.text(max_size=6), _VALUES, max_size=6))
def test_load_mapping_property(raw) -> None:
    try:
        m = load_mapping(raw)
    except ImportMappingError as exc:  # an ImportMappingError is a ValueError
        assert str(exc)
    else:
        assert isinstance(m, ImportMapping)
        assert set(m.raw) <= set(_KEYS)


@settings(max_examples=50, deadline=None)
@given(raw=st.fixed_dictionaries({}, optional={k: _VALUES for k in _KEYS}))
def test_load_mapping_property_known_keys(raw) -> None:
    try:
        assert isinstance(load_mapping(raw), ImportMapping)
    except ImportMappingError as exc:
        assert str(exc)


def test_a_mapping_that_is_a_directory_or_binary_is_named(tmp_path) -> None:
    """Issue 13, finding 7: a directory was reported as missing, a binary file as a bare
    UnicodeDecodeError without its path."""
    (tmp_path / "d.json").mkdir()
    with pytest.raises(ImportMappingError, match=r"d.json is a directory, not a file"):
        load_mapping(tmp_path / "d.json")
    (tmp_path / "b.json").write_bytes(b"\xff\xfe\x00binary")
    with pytest.raises(ImportMappingError, match=r"b.json is not UTF-8 text"):
        load_mapping(tmp_path / "b.json")


@pytest.mark.parametrize(
    "key", ["sample_rate_hz", "source_sha256", "source_file", "cropped_from_samples", "vibrissa_x"]
)
def test_attrs_cannot_contradict_what_the_import_takes_from_the_file(key) -> None:
    """Issue 33: ``"attrs": {"sample_rate_hz": 5}`` labelled 1 kHz data as 5 Hz."""
    with pytest.raises(ImportMappingError, match=rf"'attrs' cannot set \['{key}'\]"):
        load_mapping({**XY_MAPPING, "attrs": {key: 5, "robot": "XY"}})
    assert load_mapping({**XY_MAPPING, "attrs": {"robot": "XY", "protocol": "p"}}).attrs == {
        "robot": "XY",
        "protocol": "p",
    }
