"""Watching a CrunchBot run: the filter's frames, the GIF and the interactive page (the
page also in headless Chromium: it loads without errors and the slider moves the frame)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from vibrissa.robots.crunchbot import PRESETS, synthetic_log
from vibrissa.slam import (
    MODES,
    SensorLog,
    SlamSettings,
    WhiskerLayout,
    map_error,
    run_slam,
    smooth_ground_truth,
)
from vibrissa.thesis.crunchbot_slam.viewer import slam_frames, write_animation, write_viewer_html

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: the browser harness
from browser import chromium_or_skip, launch_chromium

BOXES = [[0.6, 0.6, 1.85, 1.85], [1.1, 1.1, 1.35, 1.35]]


@pytest.fixture(scope="module")
def run():
    log = synthetic_log(PRESETS["slam"], 15.0, seed=5)
    return log, slam_frames(log, SlamSettings(n_particles=15), seed=2)


def test_frames_are_the_filter_of_run_slam(run):
    log, fr = run
    n = log.n_steps + 1
    assert fr.particles.shape == (n, 15, 3) and fr.maps.shape == (n, 50, 50)
    ref = run_slam(log, SlamSettings(n_particles=15), seed=2)
    assert np.allclose(fr.estimate, ref.pose_estimate)
    assert np.allclose(fr.best_map, ref.best_map())
    assert np.all(fr.maps[0] == 128)  # nothing seen before the first step


@pytest.mark.parametrize("mode", MODES)
def test_the_viewer_scores_the_map_run_slam_scores(run, mode):
    log, _ = run
    settings = SlamSettings(n_particles=15, mode=mode)
    fr = slam_frames(log, settings, seed=2)
    ref = run_slam(log, settings, seed=2)
    truth = smooth_ground_truth(PRESETS["slam"].occupancy_grid())
    np.testing.assert_array_equal(fr.best_map, ref.best_map())
    assert map_error(fr.best_map, truth) == map_error(ref.best_map(), truth)
    np.testing.assert_array_equal(fr.estimate, ref.pose_estimate)


def test_the_last_frame_includes_an_episode_open_at_the_logs_end():
    """The log ends one step into a contact episode: run_slam closes it (a blob at the
    first contact), and so do the viewer's final map and its last frame."""
    layout = WhiskerLayout(
        base_m=np.array([[0.15, 0.05], [0.15, -0.05]]),
        angle_rad=np.zeros(2),
        length_m=np.full(2, 0.14),
    )
    log = SensorLog(
        layout=layout,
        state=np.array(["FWD_1", "HIT_1"]),
        odometry=np.zeros((2, 3)),
        contact=np.array([[True, False]] * 2),
        radial_distance_m=np.array([[0.1, np.nan]] * 2),
        surface_angle_rad=np.full(2, np.nan),
        start_pose=np.array([1.0, 1.0, 0.0]),
    )
    settings = SlamSettings(n_particles=2, odometry_error=0.0, mode="geometric")
    ticks = []
    fr = slam_frames(log, settings, seed=0, progress=lambda d, n: ticks.append((d, n)))
    ref = run_slam(log, settings, seed=0)
    wall = np.zeros((50, 50))
    wall[25, 15:35] = 1.0
    truth = smooth_ground_truth(wall)
    np.testing.assert_array_equal(fr.best_map, ref.best_map())
    assert map_error(fr.best_map, truth) == map_error(ref.best_map(), truth)
    hit = (int(1.25 / 0.05), int(1.05 / 0.05))
    assert fr.best_map[hit] == pytest.approx(0.75, abs=0.02)
    assert fr.maps.shape[0] == 3 and fr.maps[1][hit] == 128 and fr.maps[2][hit] > 180
    assert ticks == [(1, 3), (2, 3), (3, 3)]


def test_animation_is_a_gif_of_at_most_max_frames(run, tmp_path):
    log, fr = run
    path = write_animation(tmp_path / "a.gif", log, fr, BOXES, max_frames=7)
    with Image.open(path) as im:
        assert im.format == "GIF" and im.n_frames == 7
    assert not list(tmp_path.glob(".*.tmp"))


def _page(run, tmp_path) -> Path:
    log, fr = run
    t = np.arange(log.n_steps + 1) * 0.5
    return write_viewer_html(
        tmp_path / "v.html",
        log,
        fr,
        BOXES,
        step_time_s=t,
        # a floor whisker in window mode: NaN outside its windows
        traces={
            "w1": np.abs(np.sin(t)),
            "w2": np.zeros_like(t),
            "floor": np.where(np.arange(t.size) % 4 == 3, 0.2, np.nan),
        },
        trace_time_s=t,
        tiles=[(0.6, 0.6, 1.1, 1.1, "vinyl")],
        title="a <b>run</b> &",
        summary="s",
    )


def test_page_is_one_self_contained_file(run, tmp_path):
    html = _page(run, tmp_path).read_text()
    assert "<script src" not in html and "http://" not in html and "https://" not in html
    assert html.count("</script>") == 2  # the data cannot close its script early
    assert "a &lt;b&gt;run&lt;/b&gt; &amp;" in html


def test_page_in_chromium_loads_and_the_slider_moves_the_frame(run, tmp_path):
    chromium_or_skip()
    from playwright.sync_api import sync_playwright

    log, _ = run
    page_path = _page(run, tmp_path)
    errors: list[str] = []
    with sync_playwright() as p:
        browser = launch_chromium(p)
        try:
            context = browser.new_context(offline=True)
            page = context.new_page()
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(page_path.as_uri(), wait_until="load")
            assert page.evaluate("document.body.dataset.frame") == "0"
            last = log.n_steps
            page.evaluate(
                f"s = document.getElementById('slider'); s.value = {last}; "
                "s.dispatchEvent(new Event('input'))"
            )
            assert page.evaluate("document.body.dataset.frame") == str(last)
            assert f"step {last} / {last}" in page.inner_text("#label")
            page.evaluate("s.value = 0; s.dispatchEvent(new Event('input'))")
            page.click("#play")
            page.wait_for_function("+document.body.dataset.frame > 1", timeout=5000)
            page.click("#play")
        finally:
            browser.close()
    assert errors == []


@pytest.mark.parametrize("mode", ["blob", "template"])
def test_the_viewer_and_the_reproduction_score_a_run_alike(tmp_path, mode):
    """``vibrissa run crunchbot`` (watch_run) and ``vibrissa reproduce crunchbot-slam``
    (slam_job, per run and mode) map the same run with the same filter seed to the same
    map error and trajectory error: one SLAM loop, closed the same way."""
    from vibrissa.robots.crunchbot import PRESETS, synthetic_record
    from vibrissa.slam import smooth_ground_truth
    from vibrissa.thesis.crunchbot_slam.evaluation import slam_job
    from vibrissa.thesis.crunchbot_slam.viewer import watch_run

    arena = PRESETS["slam"]
    seen = watch_run(
        tmp_path / "w",
        arena,
        12.0,
        seed=3,
        particles=15,
        mode=mode,
        simulate_run=synthetic_record,
        train=None,
    )
    log = synthetic_record(arena, 12.0, 3).log
    scored = slam_job(
        {"ground_truth": smooth_ground_truth(arena.occupancy_grid())}, log, mode, 15, 3
    )
    assert seen["map_error"] == scored["map_error"]
    assert seen["trajectory_error_mm"] == scored["trajectory_error_mm"]
