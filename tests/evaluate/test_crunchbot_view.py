"""Watching a CrunchBot run: the filter's frames, the GIF and the interactive page (the
page also in headless Chromium: it loads without errors and the slider moves the frame)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from vibrissa.evaluate.crunchbot_view import slam_frames, write_animation, write_viewer_html
from vibrissa.robots.crunchbot import PRESETS, synthetic_log
from vibrissa.slam import SlamSettings, run_slam

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: the browser harness
from browser import chromium_or_skip, launch_chromium  # noqa: E402

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


def test_animation_is_a_gif_of_at_most_max_frames(run, tmp_path):
    log, fr = run
    path = write_animation(tmp_path / "a.gif", log, fr, BOXES, max_frames=7)
    with Image.open(path) as im:
        assert im.format == "GIF" and im.n_frames == 7
    assert not list(tmp_path.glob(".*.tmp"))


def _page(run, tmp_path) -> Path:
    log, fr = run
    t = np.arange(log.n_steps + 1) * 0.5
    return write_viewer_html(tmp_path / "v.html", log, fr, BOXES, step_time_s=t,
                             # a floor whisker in window mode: NaN outside its windows
                             traces={"w1": np.abs(np.sin(t)), "w2": np.zeros_like(t),
                                     "floor": np.where(np.arange(t.size) % 4 == 3, 0.2,
                                                       np.nan)},
                             trace_time_s=t, tiles=[(0.6, 0.6, 1.1, 1.1, "vinyl")],
                             title="a <b>run</b> &", summary="s")


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
            page.evaluate(f"s = document.getElementById('slider'); s.value = {last}; "
                          "s.dispatchEvent(new Event('input'))")
            assert page.evaluate("document.body.dataset.frame") == str(last)
            assert f"step {last} / {last}" in page.inner_text("#label")
            page.evaluate("s.value = 0; s.dispatchEvent(new Event('input'))")
            page.click("#play")
            page.wait_for_function("+document.body.dataset.frame > 1", timeout=5000)
            page.click("#play")
        finally:
            browser.close()
    assert errors == []
