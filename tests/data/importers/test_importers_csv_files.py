"""Tests of CSV files (vibrissa.data.importers.csv_files)."""

from __future__ import annotations

import numpy as np
import pytest
from importer_checks import write_long_csv

from vibrissa.data import import_recording


def test_csv_long_format(tmp_path) -> None:
    p = tmp_path / "long.csv"
    write_long_csv(p, shuffle=True)
    ds = import_recording(p, {"labels": ["speed_mm_s", "texture"]})
    assert ds.sizes == {"trial": 3, "channel": 2, "time": 8}
    assert ds.attrs["sample_rate_hz"] == pytest.approx(250.0)
    np.testing.assert_allclose(ds["time"].values, np.arange(8) / 250)
    assert list(ds["texture"].values) == ["P80", "P180", "P80"][::-1]  # order of appearance
    # trial 2 appeared first in the shuffled file; samples sorted by time
    np.testing.assert_array_equal(ds["signal"].values[0, 0], 200 + np.arange(8))
    np.testing.assert_array_equal(ds["signal"].values[0, 1], -200 - np.arange(8))
    assert ds["speed_mm_s"].values[0] == pytest.approx(50.4)
    ds2 = import_recording(p, {"channels": ["y"], "sample_rate_hz": 250, "time_column": None})
    assert list(ds2["channel"].values) == ["y"]
    np.testing.assert_array_equal(ds2["signal"].values[0, 0], -200 - np.arange(8)[::-1])


def test_csv_long_errors(tmp_path) -> None:
    p = tmp_path / "long.csv"
    write_long_csv(p, bad_label=True)
    with pytest.raises(ValueError, match="trial 2 .*'texture' is not constant"):
        import_recording(p, {"labels": ["texture"]})
    write_long_csv(p)
    text = p.read_text().splitlines()
    text[4] = text[4].replace(",3,", ",abc,", 1)
    p.write_text("\n".join(text))
    with pytest.raises(ValueError, match="column 'x' must hold numbers; line 5 has 'abc'"):
        import_recording(p, {"channels": ["x", "y"]})
    with pytest.raises(ValueError, match="no trial column 'run'"):
        import_recording(p, {"trial_column": "run"})
    with pytest.raises(ValueError, match=r"no channel column\(s\) \['z'\]"):
        import_recording(p, {"channels": ["z"]})
    with pytest.raises(ValueError, match="do not apply to csv"):
        import_recording(p, {"signal": "data"})
    write_long_csv(p)
    lines = p.read_text().splitlines()
    p.write_text("\n".join(lines[:-2]) + "\n")  # trial 2 loses two samples
    with pytest.raises(ValueError, match="trial 2 of long.csv has 6 samples"):
        import_recording(p, {})


def test_csv_wide_format_with_ragged_rows(tmp_path) -> None:
    p = tmp_path / "wide.csv"
    header = (
        "angle_deg,texture,"
        + ",".join(f"x_{k}" for k in range(5))
        + ","
        + ",".join(f"y_{k}" for k in range(5))
    )
    rows = ["10,P80,1,2,3,4,5,-1,-2,-3,-4,-5", "20,P180,6,7,8,,,-6,-7,-8,,"]
    p.write_text("\n".join([header, *rows]) + "\n")
    mapping = {"layout": "wide", "labels": ["angle_deg", "texture"], "sample_rate_hz": 4000}
    with pytest.raises(ValueError, match="row 3 of wide.csv has 3 samples"):
        import_recording(p, mapping)
    ds = import_recording(p, {**mapping, "ragged": "crop"})
    assert ds.sizes == {"trial": 2, "channel": 2, "time": 3}
    np.testing.assert_array_equal(ds["signal"].values[1], [[6, 7, 8], [-6, -7, -8]])
    assert list(ds["texture"].values) == ["P80", "P180"]
    assert list(ds["channel"].values) == ["x", "y"]


def _long_lines(tmp_path):
    p = tmp_path / "long.csv"
    write_long_csv(p)
    return p, p.read_text().splitlines()


def test_csv_long_non_numeric_cell_in_a_channel_is_an_error(tmp_path) -> None:
    p, lines = _long_lines(tmp_path)
    # line 5 (trial 0, sample 3): the x cell becomes text; before, column x was dropped silently
    lines[4] = lines[4].replace(",3,", ",abc,", 1)
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="column 'x' holds numbers but line 5 has 'abc'"):
        import_recording(p, {"labels": ["speed_mm_s", "texture"]})
    # a column of text only is still ignored (not a channel)
    p2 = tmp_path / "text.csv"
    _, lines = _long_lines(tmp_path)
    p2.write_text("\n".join([lines[0] + ",note"] + [ln + ",ok" for ln in lines[1:]]) + "\n")
    ds = import_recording(p2, {"labels": ["speed_mm_s", "texture"]})
    assert list(ds["channel"].values) == ["x", "y"]


@pytest.mark.parametrize(
    ("line", "cell", "match"),
    [
        (
            3,
            "0.0000",
            r"trial 0 of long.csv: time column 'time' repeats the time 0 s on "
            r"lines 2 and 3",
        ),
        (
            9,
            "1e308",
            r"trial 0 of long.csv: time column 'time' is not evenly spaced: it steps "
            r"from 0.024 s \(line 8\) to 1e\+308 s \(line 9\)",
        ),
        (9, "1e400", r"time column 'time' must hold finite times \(s\); line 9 has inf"),
        (9, "inf", r"time column 'time' must hold finite times \(s\); line 9 has inf"),
        (9, "nan", r"time column 'time' must hold finite times \(s\); line 9 has"),
        (9, "", r"time column 'time' must hold finite times \(s\); line 9 has an empty cell"),
        (9, "0.0400", r"not evenly spaced: it steps from 0.024 s \(line 8\) to 0.04 s \(line 9\)"),
    ],
)
def test_csv_long_bad_time_stamps_are_errors(tmp_path, line, cell, match) -> None:
    p, lines = _long_lines(tmp_path)
    fields = lines[line - 1].split(",")
    fields[1] = cell
    lines[line - 1] = ",".join(fields)
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=match):
        import_recording(p, {"labels": ["speed_mm_s", "texture"]})


def test_csv_long_sample_rate_from_the_time_column(tmp_path) -> None:
    p = tmp_path / "ms.csv"
    rows = ["trial,time,x"] + [f"0,{k * 0.001!r},{k}" for k in range(50)]
    p.write_text("\n".join(rows) + "\n")
    ds = import_recording(p, {})
    assert ds.attrs["sample_rate_hz"] == 1000.0  # not 999.9999999999991
    with pytest.raises(ValueError, match="sampled at 1000 Hz but 'sample_rate_hz' is 250 Hz"):
        import_recording(p, {"sample_rate_hz": 250})
    assert (
        import_recording(p, {"sample_rate_hz": 250, "time_column": None}).attrs["sample_rate_hz"]
        == 250.0
    )
    p2 = tmp_path / "two.csv"
    rows += [f"1,{k * 0.002!r},{k}" for k in range(50)]
    p2.write_text("\n".join(rows) + "\n")
    with pytest.raises(
        ValueError,
        match="trial 1 of two.csv: time column 'time' is sampled at "
        "500 Hz but trial 0 of two.csv at 1000 Hz",
    ):
        import_recording(p2, {})
