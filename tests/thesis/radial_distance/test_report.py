"""Tests of chapter 4's report and figures, and the dataset figures (files in tmp_path)."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest
import xarray as xr
from matplotlib.figure import Figure

from vibrissa.evaluate import figures, report_common
from vibrissa.thesis.radial_distance import evaluation as protocol
from vibrissa.thesis.radial_distance import figures as ch4_figures
from vibrissa.thesis.radial_distance import report

from .test_evaluation import Centroid, Constant, RadiusOnly, make_grid_dataset

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def ds() -> xr.Dataset:
    return make_grid_dataset(noise=0.02)


@pytest.fixture(scope="module")
def results(ds) -> dict:
    clf = {"template": Centroid(), "frequency": Constant(), "static_beam_measured": RadiusOnly()}
    return protocol.run_chapter4(ds, clf, fractions=(0.8, 0.5), n_seeds=2, seed=3)


def _is_png(path) -> bool:
    return path.exists() and path.stat().st_size > 1000 and path.read_bytes()[:8] == PNG_MAGIC


def test_thesis_values_transcribed() -> None:
    t = report.THESIS_CHAPTER4
    assert t["table_4_1"]["fitted"] == {
        "youngs_modulus_gpa": 1.5,
        "base_radius_mm": 1.2,
        "length_mm": 230.0,
        "scale_factor": 0.002,
    }
    assert t["table_4_2"]["speed_mm_s"]["mean"]["1.0"] == -89.98
    assert t["table_4_3"]["radius_mm"]["std"]["0.05"] == 5.79
    assert t["table_4_4"]["speed_mm_s"]["mean"]["0.4"] == -0.002
    assert t["table_4_5"]["radius_mm"]["mean"]["0.05"] == 0.636
    assert t["table_4_6"]["naive_bayes"] == 22 * 60 + 24
    # table 4.7 repeats the 100 % columns of tables 4.2-4.5
    for col, tab in (
        ("frequency", "table_4_2"),
        ("template", "table_4_3"),
        ("feature", "table_4_4"),
        ("naive_bayes", "table_4_5"),
    ):
        for par in ("speed_mm_s", "radius_mm"):
            for stat in ("mean", "std"):
                assert t["table_4_7"][col][par][stat] == t[tab][par][stat]["1.0"]
    assert t["table_4_7"]["static_beam"]["speed_mm_s"] is None
    assert t["table_4_7"]["static_beam"]["radius_mm"] == {"mean": 0.25, "std": 8.8}
    json.dumps(t)


def test_results_figures_return_axes(results) -> None:
    ax = ch4_figures.error_histogram([0.0, 1.0, -2.0], parameter="speed_mm_s")
    assert isinstance(ax.figure, Figure)
    assert ch4_figures.training_size_plot(results, "template", "radius_mm").get_xscale() == "log"
    assert ch4_figures.static_beam_speed_plot(results, "static_beam_measured", errorbar="sem")
    assert ch4_figures.comparison_plot(results, "speed_mm_s")
    ax = Figure().add_subplot()
    assert ch4_figures.prediction_scatter([80, 90], [80, 100], ax=ax) is ax
    fig = ch4_figures.classifier_figure(results, "template")
    assert len(fig.axes) == 6
    assert len(ch4_figures.classifier_figure(results, "static_beam_measured").axes) == 3
    with pytest.raises(ValueError, match="parameter"):
        ch4_figures.error_histogram([1.0], parameter="angle")
    with pytest.raises(ValueError, match="no results"):
        ch4_figures.training_size_plot(results, "nope")
    with pytest.raises(ValueError, match="errorbar"):
        ch4_figures.static_beam_speed_plot(results, "static_beam_measured", errorbar="ci")


def test_dataset_figures(ds, tmp_path) -> None:
    ax = figures.deflection_traces(ds, radial_distances_mm=[80, 101], speeds_mm_s=[70])
    assert len(ax.lines) == 2  # snapped to 80/100 mm at 72 mm/s
    assert len(figures.deflection_traces(ds, channel="y", set_value=1).lines) == 3
    g = figures.feature_grid(ds)
    assert g["peak_v"].shape == (4, 3) and np.all(np.isfinite(g["duration_ms"]))
    # peak deflection falls with radial distance, duration with speed (figure 4.1)
    assert np.all(np.diff(g["peak_v"], axis=0) < 0)
    assert np.all(np.diff(g["duration_ms"], axis=1) <= 0)
    axes = figures.feature_contours(ds)
    p = figures.save_figure(axes[0].figure, tmp_path / "sub" / "contours.png")
    assert _is_png(p)
    assert _is_png(figures.save_figure(figures.typical_traces_figure(ds), tmp_path / "t.png"))
    with pytest.raises(ValueError, match="speed_mm_s"):
        figures.deflection_traces(ds.drop_vars("speed_mm_s"))
    with pytest.raises(ValueError, match="channel"):
        figures.deflection_traces(ds, channel="z")
    with pytest.raises(ValueError, match="angle_deg"):
        figures.angle_texture_traces(ds)


def test_angle_texture_traces(tmp_path) -> None:
    t = np.arange(30) / 4000.0
    rows = [(a, tx, s) for a in (10.0, 20.0) for tx in ("P80", "aluminium") for s in (6.0, 56.0)]
    sig = np.stack([np.stack([2.5 + 0.01 * a * np.sin(s * t * 50)] * 2) for a, _, s in rows])
    d = xr.Dataset(
        {"signal": (("trial", "channel", "time"), sig)},
        coords={
            "time": t,
            "channel": ["x", "y"],
            "angle_deg": ("trial", [r[0] for r in rows]),
            "texture": ("trial", [r[1] for r in rows]),
            "speed_mm_s": ("trial", [r[2] for r in rows]),
        },
        attrs={"sample_rate_hz": 4000.0},
    )
    axs = figures.angle_texture_traces(d)
    assert axs.shape == (2, 2) and len(axs[0, 0].lines) == 2
    assert _is_png(figures.save_figure(axs[0, 0].figure, tmp_path / "f52.png"))


def test_csv_figures_and_report_written(results, ds, tmp_path) -> None:
    out = tmp_path / "out"
    figs = report.write_outputs(results, out, dataset=ds)
    loaded = report_common.load_results(report_common.write_json(results, out / "results.json"))
    assert loaded["classifiers"]["template"]["radius_mm"]["mean"] == 0
    assert set(loaded["training_fractions"]) == {"0.8", "0.5"}
    assert set(loaded["parameters"]) == {"radius_mm", "speed_mm_s"}
    rows = list(csv.DictReader(io.StringIO((out / "results.csv").read_text())))
    assert set(rows[0]) == set(report.CSV_COLUMNS)
    full = [r for r in rows if r["fraction"] == "1.0" and r["classifier"] == "template"]
    assert {r["parameter"] for r in full} == {"radius_mm", "speed_mm_s", "joint"}
    sb = [r for r in rows if r["classifier"] == "static_beam_measured"]
    assert {r["parameter"] for r in sb} == {"radius_mm"}
    assert any(r["seed"] == "3/1" for r in rows) and any(r["seed"] == "mean" for r in rows)
    by_speed = (out / "radius_error_by_speed.csv").read_text().splitlines()
    assert by_speed[0].startswith("classifier,speed_mm_s") and len(by_speed) == 1 + 3 * 3
    rel = {k: p.relative_to(out) for k, p in figs.items()}
    md = report.markdown_report(results, figures=rel)
    for needle in (
        "Table 4.1",
        "Table 4.2",
        "Table 4.3",
        "Table 4.6",
        "Table 4.7",
        "thesis 4.7",
        "-89.98",
        "## Discussion",
        "(figures/comparison.png)",
        "(figures/contours.png)",
    ):
        assert needle in md, needle
    assert len(figs) == 3 * 2 + 1 + 2
    for p in figs.values():
        assert _is_png(p), p
        assert f"]({p.relative_to(out).as_posix()})" in md
    # written again: replaced atomically, no temporary files left
    report.write_outputs(results, out, figures=False)
    assert not [p for p in out.rglob("*.tmp")]


def test_figures_drawn_by_workers_are_the_same_files(results, tmp_path) -> None:
    one = ch4_figures.chapter4_figures(results, tmp_path / "one", workers=1)
    two = ch4_figures.chapter4_figures(results, tmp_path / "two", workers=2)
    assert list(one) == list(two) and len(one) == 3 * 2 + 1
    for key in one:
        assert one[key].name == two[key].name and _is_png(two[key])
        assert one[key].read_bytes() == two[key].read_bytes(), key


def test_discussion_numbers_come_from_the_results(results) -> None:
    """The frequency row's explanation is computed from the run's speeds and test set."""
    text = report.discussion(results)
    truth = np.asarray(results["predictions"]["speed_mm_s_true"])
    slow = min(results["meta"]["speeds_mm_s"]) - truth
    assert f"{slow.mean():.2f} mm/s with std {slow.std(ddof=1):.2f}" in text
    changed = json.loads(json.dumps(results))
    changed["meta"]["speeds_mm_s"] = [v + 1.0 for v in changed["meta"]["speeds_mm_s"]]
    assert report.discussion(changed) != text
    assert "goes here" not in text


def test_markdown_without_figures(results) -> None:
    md = report.markdown_report(results)
    assert "goes here" not in md and "docs/methods.md" in md
    assert "![" not in md


def test_write_json_refuses_nan(tmp_path) -> None:
    with pytest.raises(ValueError, match="NaN"):
        report_common.write_json({"x": float("nan")}, tmp_path / "r.json")
    assert not (tmp_path / "r.json").exists()
