"""Watch one CrunchBot run: the filter step by step, an animation and an interactive page.

:func:`check_watch` checks every option of ``vibrissa run crunchbot`` before any work;
:func:`watch_run` runs the robot once, then :func:`slam_frames` runs the particle filter
over its sensor log (:func:`vibrissa.slam.run_slam` with a :class:`~vibrissa.slam.Frames`
collector, the same loop the reproduction scores) keeping,
at every FSM step, the particles and the best particle's map;
:func:`write_animation` draws them as an animated GIF (matplotlib's ``PillowWriter``);
:func:`write_viewer_html` writes ONE self-contained HTML page (inline script, style and
data; no network) with a time slider and a play button showing the arena, the true robot
and its whiskers, the particles and the current map, with the whisker traces under it.
"""

from __future__ import annotations

import base64
import html
import json
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from vibrissa._atomic import atomic_path, atomic_write_text
from vibrissa.robots.crunchbot.arena import Arena, get_arena
from vibrissa.robots.crunchbot.fsm import FsmSettings
from vibrissa.robots.crunchbot.record import WHISKER_NAMES, RunRecord
from vibrissa.slam import Frames, FrameStack, Progress, SensorLog, SlamSettings, run_slam
from vibrissa.thesis.crunchbot_slam.protocol import default_robot, robot_kind

__all__ = [
    "MAX_PARTICLES",
    "MAX_WATCH_SECONDS",
    "SlamFrames",
    "check_watch",
    "slam_frames",
    "watch_run",
    "write_animation",
    "write_viewer_html",
]


@dataclass(frozen=True)
class SlamFrames:
    """The filter before each step and after the last (``n_steps + 1`` frames).

    ``particles`` ``(n_frames, n_particles, 3)`` map-frame poses; ``maps``
    ``(n_frames, n, n)`` uint8 occupancy (0-255, ``[ix, iy]``) of the most probable
    particle, 128 where it has seen nothing; ``estimate`` ``(n_frames, 3)``;
    ``best_map`` the final most probable map as :meth:`vibrissa.slam.SlamRun.best_map`
    (occupancy, 0.3 where unexplored). The last frame is the filter's final state, a
    contact episode still open at the log's end closed as :func:`vibrissa.slam.run_slam`
    closes it.
    """

    particles: np.ndarray
    maps: np.ndarray
    estimate: np.ndarray
    cell_m: float
    best_map: np.ndarray


def slam_frames(
    log: SensorLog,
    settings: SlamSettings,
    seed: int = 0,
    progress: Callable[[int, int], None] | None = None,
) -> SlamFrames:
    """Run the filter over ``log`` keeping each frame.

    :func:`vibrissa.slam.run_slam` with a :class:`~vibrissa.slam.Frames` collector, so the
    final map is the one it scores.

    Parameters
    ----------
    log
        The run's observations.
    settings
        The filter's settings.
    seed
        Seeds the filter's random stream (as :func:`~vibrissa.slam.run_slam`'s).
    progress
        Called as ``progress(frames_done, n_steps + 1)`` after each frame.
    """
    frames = Frames()
    collect = [frames] if progress is None else [frames, Progress(progress)]
    run = run_slam(log, settings, seed, collect=collect)
    rec: FrameStack = run.collected[frames.name]
    return SlamFrames(rec.particles, rec.maps, rec.estimate, settings.cell_m, run.best_map())


def _whisker_lines(pose: np.ndarray, layout: Any) -> np.ndarray:
    """``(n_whiskers, 2, 2)`` base and tip of each obstacle whisker at a pose."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    rot = np.array([[c, -s], [s, c]])
    base = np.asarray(layout.base_m) @ rot.T + pose[:2]
    tip = np.asarray(layout.points(np.asarray(layout.length_m))) @ rot.T + pose[:2]
    return np.stack([base, tip], axis=1)


def write_animation(
    path: str | os.PathLike[str],
    log: SensorLog,
    frames: SlamFrames,
    boxes: Sequence[Sequence[float]],
    max_frames: int = 120,
    fps: int = 8,
) -> Path:
    """An animated GIF of the run (at most ``max_frames`` frames), written atomically.

    ``boxes`` are the walls and obstacles as map-frame ``(x0, y0, x1, y1)``, the first the
    arena's border. matplotlib (Agg) draws each frame and Pillow writes the GIF (as
    matplotlib's ``PillowWriter`` does; it picks the format from the file name, which an
    atomic temporary file does not end in).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle
    from PIL import Image

    n = frames.maps.shape[0]
    pick = np.unique(np.linspace(0, n - 1, min(max_frames, n)).round().astype(int))
    size = frames.maps.shape[1] * frames.cell_m
    fig = Figure(figsize=(5, 5), dpi=80, layout="constrained")
    ax = fig.add_subplot()
    im = ax.imshow(
        frames.maps[0].T, origin="lower", cmap="gray_r", vmin=0, vmax=255, extent=(0, size, 0, size)
    )
    for i, b in enumerate(boxes):
        ax.add_patch(
            Rectangle(
                (b[0], b[1]),
                b[2] - b[0],
                b[3] - b[1],
                fill=False,
                ec="tab:blue",
                lw=1.5 if i == 0 else 1,
            )
        )
    (pts,) = ax.plot([], [], ".", ms=2, color="tab:orange")
    (path_line,) = ax.plot([], [], ":", lw=0.8, color="k", label="true path")
    (est_line,) = ax.plot([], [], "-", lw=0.8, color="tab:green", label="filter estimate")
    (body,) = ax.plot([], [], "-", color="k")
    whiskers = [ax.plot([], [], "-", lw=1.2)[0] for _ in range(log.layout.n_whiskers)]
    title = ax.set_title("")
    ax.set_xlim(0, size)
    ax.set_ylim(0, size)
    ax.set_aspect("equal")
    ax.legend(loc="lower left", fontsize=7)
    ring = np.linspace(0, 2 * np.pi, 40)
    true = np.asarray(log.true_pose)
    canvas = FigureCanvasAgg(fig)
    images = []
    for t in pick:
        im.set_data(frames.maps[t].T)
        pts.set_data(frames.particles[t, :, 0], frames.particles[t, :, 1])
        path_line.set_data(true[: t + 1, 0], true[: t + 1, 1])
        est_line.set_data(frames.estimate[: t + 1, 0], frames.estimate[: t + 1, 1])
        p = true[t]
        r = log.layout.body_radius_m
        body.set_data(p[0] + r * np.cos(ring), p[1] + r * np.sin(ring))
        touch = (
            np.asarray(log.contact[t], bool)
            if t < log.n_steps
            else np.zeros(log.layout.n_whiskers, bool)
        )
        for w, (ln, seg) in enumerate(zip(whiskers, _whisker_lines(p, log.layout), strict=True)):
            ln.set_data(seg[:, 0], seg[:, 1])
            ln.set_color("tab:red" if touch[w] else "0.4")
        state = str(log.state[t]) if t < log.n_steps else "end"
        title.set_text(f"step {t} / {n - 1}  {state}")
        canvas.draw()
        images.append(
            Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3]).convert(
                "P", palette=Image.Palette.ADAPTIVE
            )
        )
    with atomic_path(Path(path)) as tmp:
        images[0].save(
            tmp,
            format="GIF",
            save_all=True,
            append_images=images[1:],
            duration=int(1000 / fps),
            loop=0,
        )
    return Path(path)


#: Longest run ``vibrissa run crunchbot`` accepts (robot seconds): ten of the thesis'
#: 6-minute runs, about 8 minutes of wall time on one core.
MAX_WATCH_SECONDS = 3600.0
#: Most particles it accepts: each carries a 50 x 50 map (20 kB), so 10 000 hold 200 MB.
MAX_PARTICLES = 10_000

_PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>__TITLE__</title>
<style>
body{font-family:system-ui,sans-serif;margin:1em;max-width:980px}
#views{display:flex;flex-wrap:wrap;gap:12px}
canvas{border:1px solid #999;max-width:100%}
#controls{margin:8px 0;display:flex;gap:8px;align-items:center}
#slider{flex:1}
.legend span{margin-right:1em}
</style></head><body>
<h1>__TITLE__</h1>
<p id="summary"></p>
<div id="controls"><button id="play" type="button">Play</button>
<input id="slider" type="range" min="0" value="0" step="1" aria-label="time step">
<span id="label"></span></div>
<div id="views">
<canvas id="arena" width="460" height="460" aria-label="arena, robot and particles"></canvas>
<canvas id="map" width="460" height="460" aria-label="best particle's map"></canvas></div>
<p class="legend"><span>black: true robot</span>
<span style="color:#d62728">red: whisker in contact</span>
<span style="color:#ff7f0e">orange: particles</span>
<span style="color:#2ca02c">green: filter estimate</span></p>
<canvas id="traces" width="940" height="220" aria-label="whisker traces"></canvas>
<script id="data" type="application/json">__DATA__</script>
<script>
"use strict";
const D = JSON.parse(document.getElementById("data").textContent);
const N = D.poses.length, S = D.map_size_m, C = D.n_cells;
const mapBytes = Uint8Array.from(atob(D.maps), c => c.charCodeAt(0));
const slider = document.getElementById("slider"), label = document.getElementById("label");
const play = document.getElementById("play");
slider.max = N - 1;
document.getElementById("summary").textContent = D.summary;
function tx(ctx, x) { return x / S * ctx.canvas.width; }
function ty(ctx, y) { return ctx.canvas.height - y / S * ctx.canvas.height; }
function drawBoxes(ctx) {
  D.tiles.forEach(t => { ctx.fillStyle = t[4]; ctx.fillRect(tx(ctx, t[0]), ty(ctx, t[3]),
    tx(ctx, t[2]) - tx(ctx, t[0]), ty(ctx, t[1]) - ty(ctx, t[3])); });
  D.boxes.forEach((b, i) => { ctx.strokeStyle = "#1f77b4"; ctx.lineWidth = i ? 1 : 2;
    if (i) { ctx.fillStyle = "#9ecae1"; ctx.fillRect(tx(ctx, b[0]), ty(ctx, b[3]),
      tx(ctx, b[2]) - tx(ctx, b[0]), ty(ctx, b[1]) - ty(ctx, b[3])); }
    ctx.strokeRect(tx(ctx, b[0]), ty(ctx, b[3]), tx(ctx, b[2]) - tx(ctx, b[0]),
      ty(ctx, b[1]) - ty(ctx, b[3])); });
}
function drawRobot(ctx, t) {
  const p = D.poses[t], c = Math.cos(p[2]), s = Math.sin(p[2]);
  ctx.strokeStyle = "#000"; ctx.lineWidth = 2; ctx.beginPath();
  ctx.arc(tx(ctx, p[0]), ty(ctx, p[1]), tx(ctx, D.body_radius_m), 0, 2 * Math.PI); ctx.stroke();
  ctx.beginPath(); ctx.moveTo(tx(ctx, p[0]), ty(ctx, p[1]));
  ctx.lineTo(tx(ctx, p[0] + D.body_radius_m * c), ty(ctx, p[1] + D.body_radius_m * s));
  ctx.stroke();
  D.whiskers.forEach((w, i) => {
    const touch = t < D.contact.length && D.contact[t][i];
    ctx.strokeStyle = touch ? "#d62728" : "#777"; ctx.lineWidth = 1.5; ctx.beginPath();
    ctx.moveTo(tx(ctx, p[0] + c * w[0] - s * w[1]), ty(ctx, p[1] + s * w[0] + c * w[1]));
    ctx.lineTo(tx(ctx, p[0] + c * w[2] - s * w[3]), ty(ctx, p[1] + s * w[2] + c * w[3]));
    ctx.stroke(); });
}
function drawArena(t) {
  const ctx = document.getElementById("arena").getContext("2d");
  ctx.clearRect(0, 0, ctx.canvas.width, ctx.canvas.height); drawBoxes(ctx);
  ctx.strokeStyle = "#2ca02c"; ctx.lineWidth = 1; ctx.beginPath();
  for (let k = 0; k <= t; k++) { const e = D.estimate[k];
    if (k) ctx.lineTo(tx(ctx, e[0]), ty(ctx, e[1]));
    else ctx.moveTo(tx(ctx, e[0]), ty(ctx, e[1])); }
  ctx.stroke();
  ctx.fillStyle = "#ff7f0e";
  D.particles[t].forEach(q => ctx.fillRect(tx(ctx, q[0]) - 1, ty(ctx, q[1]) - 1, 2, 2));
  drawRobot(ctx, t);
}
function drawMap(t) {
  const ctx = document.getElementById("map").getContext("2d");
  const img = ctx.createImageData(C, C), off = t * C * C;
  for (let ix = 0; ix < C; ix++) for (let iy = 0; iy < C; iy++) {
    const v = 255 - mapBytes[off + ix * C + iy], k = 4 * ((C - 1 - iy) * C + ix);
    img.data[k] = img.data[k + 1] = img.data[k + 2] = v; img.data[k + 3] = 255; }
  const tmp = document.createElement("canvas"); tmp.width = C; tmp.height = C;
  tmp.getContext("2d").putImageData(img, 0, 0);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(tmp, 0, 0, ctx.canvas.width, ctx.canvas.height);
  drawBoxes({canvas: ctx.canvas, fillRect() {}, strokeRect: ctx.strokeRect.bind(ctx),
             set fillStyle(v) {}, set strokeStyle(v) { ctx.strokeStyle = v; },
             set lineWidth(v) { ctx.lineWidth = v; }});
  drawRobot(ctx, t);
}
function drawTraces(t) {
  const ctx = document.getElementById("traces").getContext("2d"), W = ctx.canvas.width,
        H = ctx.canvas.height, T = D.trace_time, colours = D.trace_colours;
  ctx.clearRect(0, 0, W, H);
  const tmax = T.length ? T[T.length - 1] : 1, vmax = D.trace_max || 1;
  D.traces.forEach((tr, i) => { ctx.strokeStyle = colours[i]; ctx.lineWidth = 1; ctx.beginPath();
    let pen = false;  // null: no sample there (e.g. a floor whisker outside its window)
    tr.forEach((v, k) => { if (v === null) { pen = false; return; }
      const x = T[k] / tmax * W, y = H - 12 - v / vmax * (H - 24);
      if (pen) ctx.lineTo(x, y); else ctx.moveTo(x, y); pen = true; }); ctx.stroke();
    ctx.fillStyle = colours[i]; ctx.fillText(D.trace_names[i], 4 + 80 * i, 10); });
  const x = D.times[t] / tmax * W;
  ctx.strokeStyle = "#000"; ctx.beginPath(); ctx.moveTo(x, 0); ctx.lineTo(x, H); ctx.stroke();
}
function show(t) {
  t = Math.max(0, Math.min(N - 1, t | 0)); slider.value = t;
  label.textContent = "step " + t + " / " + (N - 1) + ", t = " + D.times[t].toFixed(1) +
    " s, " + (D.states[t] || "end");
  drawArena(t); drawMap(t); drawTraces(t);
  document.body.dataset.frame = t;
}
let timer = null;
play.addEventListener("click", () => {
  if (timer) { clearInterval(timer); timer = null; play.textContent = "Play"; return; }
  play.textContent = "Pause";
  timer = setInterval(() => { const t = +slider.value + 1;
    if (t >= N) { clearInterval(timer); timer = null; play.textContent = "Play"; return; }
    show(t); }, 80);
});
slider.addEventListener("input", () => show(+slider.value));
show(0);
</script></body></html>
"""

_TILE_COLOURS = {"vinyl": "#f2f2f2", "smooth-carpet": "#e6dccb", "rough-carpet": "#d9c7a3"}
_TRACE_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b")


def _finite_or_null(a: np.ndarray) -> list:
    """``a`` as nested lists with ``None`` (JSON ``null``) where it is not finite.

    JSON has no NaN, and ``JSON.parse`` refuses the page's data otherwise.
    """
    arr = np.asarray(a, float)
    # numpy's stubs take no None for ``where``'s ``y``; it is an object scalar at run time
    return np.where(np.isfinite(arr), arr, None).tolist()  # type: ignore[call-overload]


def write_viewer_html(
    path: str | os.PathLike[str],
    log: SensorLog,
    frames: SlamFrames,
    boxes: Sequence[Sequence[float]],
    *,
    step_time_s: np.ndarray,
    traces: Mapping[str, np.ndarray],
    trace_time_s: np.ndarray,
    tiles: Sequence[tuple[float, float, float, float, str]] = (),
    title: str = "CrunchBot run",
    summary: str = "",
) -> Path:
    """Write the interactive page, atomically; one self-contained file.

    Parameters
    ----------
    log, frames
        The run's sensor log (with ``true_pose``) and :func:`slam_frames`.
    boxes
        Map-frame ``(x0, y0, x1, y1)``: the arena's border, then the obstacles.
    step_time_s
        ``(n_steps + 1,)`` robot time of each frame.
    traces, trace_time_s
        Whisker name -> signal to plot under the views (e.g. Hall magnitude, V), at
        ``trace_time_s``.
    tiles
        Map-frame ``(x0, y0, x1, y1, texture)`` floor tiles.
    """
    lay = log.layout
    base = np.asarray(lay.base_m)
    tip = np.asarray(lay.points(np.asarray(lay.length_m)))
    r4 = lambda a: np.round(np.asarray(a, float), 4).tolist()  # noqa: E731
    vmax = max(
        (
            float(np.max(np.asarray(v)[np.isfinite(v)]))
            for v in traces.values()
            if np.isfinite(v).any()
        ),
        default=1.0,
    )
    data = {
        "map_size_m": frames.maps.shape[1] * frames.cell_m,
        "n_cells": frames.maps.shape[1],
        "poses": r4(log.true_pose),
        "estimate": r4(frames.estimate),
        "particles": np.round(frames.particles, 3).tolist(),
        "maps": base64.b64encode(np.ascontiguousarray(frames.maps).tobytes()).decode(),
        "contact": np.asarray(log.contact, int).tolist(),
        "states": [str(s) for s in log.state],
        "times": r4(step_time_s),
        "whiskers": r4(np.c_[base, tip]),
        "body_radius_m": lay.body_radius_m,
        "boxes": r4(boxes),
        "tiles": [[*r4(t[:4]), _TILE_COLOURS.get(t[4], "#eee")] for t in tiles],
        "traces": [_finite_or_null(np.round(np.asarray(v, float), 3)) for v in traces.values()],
        "trace_names": list(traces),
        "trace_time": r4(trace_time_s),
        "trace_max": vmax,
        "trace_colours": list(_TRACE_COLOURS[: len(traces)]),
        "summary": summary,
    }
    text = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    page = _PAGE.replace("__TITLE__", html.escape(title)).replace("__DATA__", text)
    return atomic_write_text(Path(path), page)


# ------------------------------------------------------------------ one run, watched
def check_watch(arena: str, seconds: float, seed: int, particles: int, mode: str) -> Arena:
    """Check every option of :func:`watch_run` before any work; return the arena.

    Raises
    ------
    ValueError
        One line naming the option: an unknown arena or a bad arena file (unknown tile
        texture, overlapping obstacles, a robot starting inside one), ``seconds`` shorter
        than one FSM step or longer than :data:`MAX_WATCH_SECONDS`, ``particles`` outside
        1 .. :data:`MAX_PARTICLES`, a seed outside 0 .. 2**63 - 1, an unknown mode.
    """
    from vibrissa.slam import MODES

    step_s = FsmSettings().step_s
    if not (
        isinstance(seconds, int | float)
        and not isinstance(seconds, bool)
        and np.isfinite(seconds)
        and step_s <= seconds <= MAX_WATCH_SECONDS
    ):
        raise ValueError(
            f"--seconds must be between {step_s:g} (one FSM step) and {MAX_WATCH_SECONDS:g} "
            f"(an hour of robot time, ten of the thesis' runs), got {seconds!r}"
        )
    if (
        isinstance(particles, bool)
        or not isinstance(particles, int)
        or not 1 <= particles <= MAX_PARTICLES
    ):
        raise ValueError(
            f"--particles must be an integer from 1 to {MAX_PARTICLES} (each carries its own "
            f"map; the thesis used 100), got {particles!r}"
        )
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63:
        raise ValueError(f"--seed must be an integer from 0 to 2**63 - 1, got {seed!r}")
    if mode not in MODES:
        raise ValueError(f"--mode: unknown mapping mode {mode!r}; choose one of {', '.join(MODES)}")
    try:
        return get_arena(arena)
    except ValueError as exc:
        raise ValueError(f"--arena: {exc}") from None


def watch_run(
    out_dir: Path,
    arena: Arena,
    seconds: float = 360.0,
    seed: int = 0,
    particles: int = 100,
    mode: str = "blob",
    simulate_run: Callable[..., RunRecord] | None = None,
    train: Callable[..., Any] | None = None,
    progress: Callable[[str, float], None] | None = None,
) -> dict[str, Any]:
    """One run, then SLAM step by step, then the GIF and HTML viewer; returns a summary.

    The files are ``crunchbot.gif`` and ``crunchbot.html`` in ``out_dir`` (both written
    atomically).

    ``progress(stage, fraction)`` with stage ``"robot"``, ``"slam"`` or ``"draw"``.
    """
    from vibrissa.slam import SlamSettings, map_error, smooth_ground_truth
    from vibrissa.thesis.crunchbot_slam.evaluation import dead_reckoning, trajectory_error_mm

    if simulate_run is None:
        simulate_run, default_train = default_robot()
        train = train if train is not None else default_train
    kwargs: dict[str, Any] = {}
    if train is not None:
        kwargs["classifiers"] = train(seed, quick=True)
    if progress is not None and robot_kind(simulate_run) != "synthetic-oracle":
        kwargs["progress"] = lambda f: progress("robot", f)
    rec = simulate_run(arena, seconds, seed, **kwargs)
    if progress:
        progress("robot", 1.0)
    log = rec.log
    settings = SlamSettings(n_particles=particles, mode=mode)
    frames = slam_frames(
        log, settings, seed, progress=((lambda d, n: progress("slam", d / n)) if progress else None)
    )
    offset = arena.map_offset_m(settings.map_size_m, settings.cell_m)
    boxes = [
        [b[0] + offset, b[1] + offset, b[2] + offset, b[3] + offset]
        for b in [(0.0, 0.0, arena.size_m, arena.size_m)] + [o.bounds() for o in arena.obstacles]
    ]
    tiles = [
        (
            c * arena.tile_m + offset,
            r * arena.tile_m + offset,
            (c + 1) * arena.tile_m + offset,
            (r + 1) * arena.tile_m + offset,
            name,
        )
        for r, row in enumerate(arena.tiles)
        for c, name in enumerate(row)
    ]
    starts = np.asarray(rec.step_start)
    step_time = np.asarray(rec.time_s)[np.minimum(starts, len(rec.time_s) - 1)]
    every = max(1, int(round(rec.sample_rate_hz / 50)))  # 50 Hz traces in the page
    mag = np.hypot(rec.hall_v[::every, :, 0], rec.hall_v[::every, :, 1])
    traces = {name: mag[:, i] for i, name in enumerate(WHISKER_NAMES)}
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    grid = arena.occupancy_grid(settings.cell_m, settings.map_size_m)
    err = map_error(frames.best_map, smooth_ground_truth(grid))
    traj = trajectory_error_mm(frames.estimate, log.true_pose)
    summary = {
        "arena": arena.name,
        "seconds": rec.seconds,
        "seed": seed,
        "mode": mode,
        "particles": particles,
        "n_steps": log.n_steps,
        "robot": robot_kind(simulate_run),
        "map_error": err,
        "trajectory_error_mm": traj,
        "dead_reckoning_error_mm": trajectory_error_mm(dead_reckoning(log), log.true_pose),
        "real_time_factor": rec.real_time_factor,
    }
    if progress:
        progress("draw", 0.0)
    gif = write_animation(out_dir / "crunchbot.gif", log, frames, boxes)
    text = (
        f"{summary['robot']} robot, arena {arena.name}, {rec.seconds:.0f} s, seed {seed}, "
        f"{mode} mode, {particles} particles: map error {err:.3f} (eq. 6.3), trajectory "
        f"error {traj:.1f} mm. Hall traces: magnitude (V) of each whisker."
    )
    html = write_viewer_html(
        out_dir / "crunchbot.html",
        log,
        frames,
        boxes,
        step_time_s=step_time,
        traces=traces,
        trace_time_s=np.asarray(rec.time_s)[::every],
        tiles=tiles,
        title=f"CrunchBot in {arena.name}",
        summary=text,
    )
    if progress:
        progress("draw", 1.0)
    return {**summary, "animation": str(gif), "html": str(html)}
