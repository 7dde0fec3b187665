"""Earlier runs as baselines in the reports (thesis / before / this run)."""

import json

import pytest

from vibrissa.evaluate.baseline import compact_results, load_baseline
from vibrissa.thesis.angle_texture.report import markdown_chapter5
from vibrissa.thesis.radial_distance.report import markdown_report

CH4 = {
    "meta": {"n_trials": 8},
    "classifiers": {
        "template": {
            "radius_mm": {"mean": 0.5, "std": 7.7, "n": 4},
            "speed_mm_s": {"mean": -1.0, "std": 13.1, "n": 4},
            "predictions": [1, 2],
        },
    },
    "training_fractions": {},
}
CH5 = {
    "meta": {},
    "classifiers": {"template_raw": {"kappa": {"angle": 0.4, "speed": 0.7, "texture": 0.15}}},
}


def test_compact_keeps_the_summary_only():
    c = compact_results(CH4, "old")
    assert c["meta"]["label"] == "old"
    assert c["classifiers"]["template"] == {
        "radius_mm": {"mean": 0.5, "std": 7.7},
        "speed_mm_s": {"mean": -1.0, "std": 13.1},
    }
    assert compact_results(CH5, "x")["classifiers"]["template_raw"]["kappa"]["angle"] == 0.4


def test_load_baseline_labels_by_file_and_refuses_other_json(tmp_path):
    p = tmp_path / "r.json"
    p.write_text(json.dumps(CH4))
    assert load_baseline(p)["meta"]["label"] == str(p)
    bad = tmp_path / "bad.json"
    bad.write_text("[1, 2]")
    with pytest.raises(ValueError, match="no 'classifiers'"):
        load_baseline(bad)
    with pytest.raises(ValueError, match="no such file"):
        load_baseline(tmp_path / "missing.json")
    junk = tmp_path / "junk.json"
    junk.write_text("{not json")
    with pytest.raises(ValueError, match="not a results JSON"):
        load_baseline(junk)


def test_chapter4_report_shows_before_beside_ours_and_the_thesis():
    before = compact_results(
        {
            "classifiers": {
                "template": {
                    "radius_mm": {"mean": 0.1, "std": 3.68},
                    "speed_mm_s": {"mean": 0.2, "std": 9.0},
                }
            }
        },
        "main before",
    )
    text = markdown_report(CH4, baseline=before)
    table = text[text.index("## Table 4.7") :]
    assert "*before*: main before." in table
    table = table[: table.index("\n\n", table.index("| template"))]
    lines = [ln for ln in table.splitlines() if ln.startswith("| template")]
    assert [ln.split("|")[2].strip() for ln in lines] == ["ours", "before", "thesis 4.7"]
    assert "3.68" in lines[1] and "7.70" in lines[0]
    assert "before" not in markdown_report(CH4)


def test_chapter5_report_has_a_thesis_before_after_kappa_table():
    before = {
        "meta": {"label": "old run"},
        "classifiers": {"template_raw": {"kappa": {"angle": 0.3, "speed": 0.6, "texture": 0.1}}},
    }
    text = markdown_chapter5(CH5, baseline=before)
    assert "thesis / before / this run" in text and "old run" in text
    row = next(ln for ln in text.splitlines() if ln.startswith("| `template_raw`") and "0.30" in ln)
    assert "0.30 / 0.40" in row


def test_baselines_that_would_crash_block_or_hang_are_one_line(tmp_path):
    import os

    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)  # RecursionError before
    odd_meta = tmp_path / "meta.json"
    odd_meta.write_text(json.dumps({"classifiers": {}, "meta": 5}))  # AttributeError before
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)  # read_text blocked forever before
    for path, message in (
        (deep, "nested too deep"),
        (odd_meta, "'meta' that is not an object"),
        (fifo, "not a regular file"),
        (tmp_path, "not a regular file"),
    ):
        with pytest.raises(ValueError, match=message) as err:
            load_baseline(path)
        assert str(err.value).startswith("--baseline:") and "\n" not in str(err.value)
