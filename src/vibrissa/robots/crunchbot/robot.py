"""The simulated CrunchBot: body, whiskers, the FSM loop and its real-time reports (6.5).

:func:`run_crunchbot` drives the 6.5.3 finite state machine
(:func:`~vibrissa.robots.crunchbot.fsm.transition`) on the Create base
(:mod:`.body`) with the four obstacle whiskers on the rod model
(:mod:`.obstacle_whiskers`) and the two floor whiskers (``FloorWhiskers`` of
:mod:`.floor_whiskers`). After every FSM step the control loop calls the real-time
classifiers and times each call (``time.perf_counter``):

* radial distance, per whisker that touched in the step, from the peak deflection of
  the step's samples (Hall volts about the rest value);
* surface angle at ``HIT_2``, from the 8 channels (4 whiskers x (x, y), volts about
  rest) of the samples since ``HIT_1``;
* floor texture log-likelihoods from the latest 200 samples of each floor whisker (raw
  volts, as ``collect_floor_training`` gives them).

It writes the :class:`~vibrissa.slam.log.SensorLog` in the map frame with the row
semantics of :func:`~vibrissa.robots.crunchbot.synthetic.synthetic_log` (``HIT_1``,
``HIT_2`` and ``ABORT`` rows are zero-length and repeat the step before's contacts), and
the :class:`~vibrissa.robots.crunchbot.record.RunRecord`.

**Truth mode** (``classifiers=None``): the log's radial distances are the TRUE ones from
the physics and no surface angle is given; for tests and for collecting training data,
never for the reproduction's scores.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from vibrissa import _validate as v
from vibrissa.classify.realtime import (
    FloorTextureNB,
    RadialDistanceLinear,
    SurfaceAngleTemplates,
    peak_deflection,
)
from vibrissa.robots.crunchbot import fsm
from vibrissa.robots.crunchbot.arena import Arena
from vibrissa.robots.crunchbot.body import odometry, plan_motion
from vibrissa.robots.crunchbot.floor_whiskers import FloorWhiskers
from vibrissa.robots.crunchbot.obstacle_whiskers import ObstacleWhiskers
from vibrissa.robots.crunchbot.record import CLASSIFIERS, RunRecord
from vibrissa.robots.crunchbot.synthetic import CRUNCHBOT_LAYOUT, FLOOR_WHISKERS_M
from vibrissa.slam.filter import apply_motion
from vibrissa.slam.log import SensorLog, WhiskerLayout

__all__ = ["FLOOR_MODES", "FLOOR_WINDOW_S", "RealtimeClassifiers", "run_crunchbot"]

#: How the floor whiskers are simulated: the last 100 ms of each step, all of it, none.
FLOOR_MODES = ("window", "continuous", "off")
#: The floor classifier's window: the latest 100 ms (200 samples at 2 kHz, 6.5.2).
FLOOR_WINDOW_S = 0.1


@dataclass(frozen=True)
class RealtimeClassifiers:
    """What the control loop calls.

    Built by :func:`~vibrissa.robots.crunchbot.training.train_classifiers`.

    Attributes
    ----------
    floor
        Floor texture naive Bayes on the latest 100 ms of a floor whisker, or ``None``.
    radial
        One radial-distance fit per obstacle whisker.
    angle
        The multi-whisker surface-angle templates, or ``None``.
    """

    floor: FloorTextureNB | None
    radial: tuple[RadialDistanceLinear, ...]
    angle: SurfaceAngleTemplates | None


def deflection_volts(hall_v: np.ndarray, offset_v: float) -> np.ndarray:
    """Hall volts about the rest value (what the classifiers read)."""
    return np.asarray(hall_v, float) - offset_v


def _default_floor(arena: Arena, sample_rate_hz: float, seed: int) -> Any:
    return FloorWhiskers(arena, sample_rate_hz=sample_rate_hz, seed=seed)


class _Loop:
    """The bookkeeping of one run: rows of the log and the per-sample arrays."""

    def __init__(self) -> None:
        self.rows: dict[str, list] = {
            k: []
            for k in (
                "state",
                "odo",
                "contact",
                "dist",
                "angle",
                "floor",
                "pose",
                "true_m",
                "tex_true",
                "tex_pred",
            )
        }
        self.hall: list[np.ndarray] = []
        self.pose: list[np.ndarray] = []
        self.step_start = [0]
        self.n = 0
        self.latency: dict[str, list[float]] = {c: [] for c in CLASSIFIERS}

    def timed(self, name: str, fn: Callable[..., Any], *args: Any) -> Any:
        t = time.perf_counter()
        out = fn(*args)
        self.latency[name].append(time.perf_counter() - t)
        return out

    def recent(self, n: int, cols: slice, chunks: int | None = None) -> np.ndarray:
        """The latest ``n`` samples of the given whisker columns (fewer at the start).

        They are taken from the first ``chunks`` steps' samples (default all).
        """
        out, need = [], n
        for chunk in reversed(self.hall[:chunks]):
            if need <= 0:
                break
            out.append(chunk[-need:, cols])
            need -= len(out[-1])
        return np.concatenate(out[::-1]) if out else np.zeros((0, 2, 2))

    def since(self, index: int) -> np.ndarray:
        """Obstacle-whisker samples from sample ``index`` on, ``(m, 4, 2)``."""
        need = self.n - index
        if need <= 0:
            return np.zeros((0, 4, 2))
        return self.recent(need, slice(0, 4))


class _FloorInBackground:
    """The floor whiskers of one step, simulated on a thread of their own.

    The control loop goes on with the next step meanwhile; then they are read by the floor
    classifier.

    The floor whiskers carry their own state and noise streams and nothing the loop
    decides depends on them, so the record is the same as simulating them in line;
    one step's floor is finished before the next step's is started, in order.
    """

    def __init__(
        self,
        loop: _Loop,
        floor_sim: Any,
        clf: FloorTextureNB | None,
        n_obstacle: int,
        window_n: int,
        window_s: float | None,
    ) -> None:
        self.loop, self.sim, self.clf = loop, floor_sim, clf
        self.cols = slice(n_obstacle, n_obstacle + 2)
        self.window_n, self.window_s = window_n, window_s
        self.classes = tuple(clf.classes_) if clf is not None else ()
        self._pending: tuple[Future, np.ndarray, int, int] | None = None
        self._executor: ThreadPoolExecutor | None = None

    def submit(self, t_s: np.ndarray, poses: np.ndarray, hall: np.ndarray, row: int) -> None:
        """Start the floor of the step whose samples go to ``hall`` (log row ``row``)."""
        if self.sim is None:
            return
        self.wait()
        if self._executor is None:
            self._executor = ThreadPoolExecutor(1, thread_name_prefix="crunchbot-floor")
        future = self._executor.submit(self.sim.advance, t_s, poses, self.window_s)
        self._pending = (future, hall, row, len(self.loop.hall))

    def wait(self) -> None:
        """Finish the step started last (its floor columns and report) if there is one."""
        if self._pending is None:
            return
        future, hall, row, chunks = self._pending
        self._pending = None
        hall[:, self.cols] = future.result()
        if self.clf is None:
            return
        window = self.loop.recent(self.window_n, self.cols, chunks)
        if len(window) == self.window_n and np.all(np.isfinite(window)):
            loglik = np.stack(
                [
                    self.loop.timed("floor_texture", self.clf.loglik, window[:, k].astype(float))
                    for k in range(2)
                ]
            )
            self.loop.rows["floor"][row] = loglik
            self.loop.rows["tex_pred"][row] = tuple(self.classes[int(np.argmax(r))] for r in loglik)

    def close(self) -> None:
        """Let the thread go (a step still running is finished and dropped)."""
        self._pending = None
        if self._executor is not None:
            self._executor.shutdown(wait=True)
            self._executor = None

    def finish(self, loglik0: np.ndarray, pred0: tuple[str, str]) -> None:
        """Wait for the last step and give every row the latest report at its step.

        Rows before the first report get ``loglik0``, ``pred0``.
        """
        try:
            self.wait()
        finally:
            self.close()
        r = self.loop.rows
        loglik, pred = loglik0, pred0
        for j in range(len(r["floor"])):
            if r["floor"][j] is None:
                r["floor"][j], r["tex_pred"][j] = loglik.copy(), pred
            else:
                loglik, pred = r["floor"][j], r["tex_pred"][j]


def _one_blas_thread(fn: Callable[..., RunRecord]) -> Callable[..., RunRecord]:
    """Run ``fn`` with BLAS on one thread.

    The loop's own threads use the cores, and BLAS's workers, woken for a few small products
    and left spinning, took the cores from the timed classifier calls (a 1 ms angle call
    read 7-15 ms).
    """

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> RunRecord:
        with threadpool_limits(limits=1, user_api="blas"):
            return fn(*args, **kwargs)

    return wrapper


@_one_blas_thread
def run_crunchbot(
    arena: Arena,
    seconds: float = 360.0,
    seed: int = 0,
    classifiers: RealtimeClassifiers | None = None,
    *,
    floor: str = "window",
    progress: Callable[[float], None] | None = None,
    settings: fsm.FsmSettings | None = None,
    sample_rate_hz: float = 2000.0,
    odometry_error: float = 0.1,
    heading_drift_rad_m: float = 0.1,
    map_size_m: float = 2.5,
    cell_m: float = 0.05,
    floor_factory: Callable[[Arena, float, int], Any] | None = None,
    stats: dict | None = None,
    layout: WhiskerLayout = CRUNCHBOT_LAYOUT,
) -> RunRecord:
    """Run the simulated CrunchBot for ``seconds`` of robot time.

    Parameters
    ----------
    arena
        Where it runs (starts at ``arena.start``).
    seconds
        Robot time (s); the run ends after the step that passes it.
    seed
        Same seed, same record (FSM turns, odometry error, sensor noise, floors).
    classifiers
        The real-time classifiers; ``None``: truth mode (the module's note).
    floor
        ``"window"`` simulates each step's last 100 ms of the floor whiskers (what the
        classifier reads), ``"continuous"`` all of it, ``"off"`` none (their columns NaN,
        ``floor_loglik`` None).
    progress
        Called after each step with the fraction of ``seconds`` done.
    settings
        The FSM's numbers.
    sample_rate_hz
        The whiskers' rate (2 kHz).
    odometry_error, heading_drift_rad_m
        The odometry's error (:func:`~vibrissa.slam.filter.noisy_increment`).
    map_size_m, cell_m
        The SLAM map the log's frame centres the arena in.
    floor_factory
        ``(arena, sample_rate_hz, seed) -> FloorWhiskers``-like object (default the real
        one); for tests.
    stats
        If given, filled with counts: ``steps``, ``physics_steps`` (any whisker ran the
        physics), ``physics_whisker_steps``, ``touch_steps``, ``failures`` (steps where
        a whisker's physics gave up and it met nothing).
    layout
        Where the obstacle whiskers sit (default the identified
        :data:`~vibrissa.robots.crunchbot.synthetic.CRUNCHBOT_LAYOUT`).

    Raises
    ------
    ValueError
        One line: ``seconds`` not positive, an unknown ``floor`` mode.
    """
    v.positive("seconds", seconds)
    if floor not in FLOOR_MODES:
        raise ValueError(f"unknown floor mode {floor!r}; choose one of {', '.join(FLOOR_MODES)}")
    v.non_negative("odometry_error", odometry_error)
    wall0 = time.perf_counter()
    s = settings or fsm.FsmSettings()
    rng_fsm, rng_odo, rng_noise, rng_floor = (
        np.random.default_rng(q) for q in np.random.SeedSequence(seed).spawn(4)
    )
    whiskers = ObstacleWhiskers(arena, sample_rate_hz, layout)
    offset = whiskers.sensor.offset_v
    floor_sim = None
    if floor != "off":
        floor_sim = (floor_factory or _default_floor)(
            arena, sample_rate_hz, int(rng_floor.integers(2**31))
        )
    floor_clf = classifiers.floor if classifiers is not None and floor != "off" else None
    textures = tuple(floor_clf.classes_) if floor_clf is not None else ()
    window_n = int(round(FLOOR_WINDOW_S * sample_rate_hz))
    W = layout.n_whiskers
    loop = _Loop()
    floor_bg = _FloorInBackground(
        loop, floor_sim, floor_clf, W, window_n, FLOOR_WINDOW_S if floor == "window" else None
    )
    pose = arena.start.as_array()
    state = fsm.FsmState(fsm.FWD_1)
    command = fsm.command_for(fsm.FWD_1, s, rng_fsm)
    touching = np.zeros(W, bool)
    dist = np.full(W, np.nan)
    strain = np.zeros(W)
    angle_clf = classifiers.angle if classifiers is not None else None
    hit1_sample = 0
    touch_steps = 0
    elapsed = 0.0
    try:
        while elapsed < seconds:
            start = pose.copy()
            planned, bumped = plan_motion(arena, pose, command, sample_rate_hz)
            forward = command.linear_m_s > 0
            watched = forward or (state.name == fsm.TURN and s.monitor_turn)
            sig, m = whiskers.advance(
                start,
                planned,
                rng_noise,
                s.strain_limit if watched else None,
                stop_on_contact=state.name == fsm.FWD_1,
            )
            bumped = bumped and m == len(planned)
            # the last step's floor whiskers ran beside this step's obstacle whiskers;
            # they are finished before the classifiers run, so no simulation thread
            # competes with the timed calls
            floor_bg.wait()
            poses = planned[:m]
            angle = math.nan
            true_m = np.full(W, np.nan)
            if m:
                pose = poses[-1].copy()
                t_s = (loop.n + 1 + np.arange(m)) / sample_rate_hz
                hall = np.full((m, 6, 2), np.nan)
                hall[:, :W] = sig.hall_v
                loop.hall.append(hall)
                loop.pose.append(poses)
                loop.n += m
                touching = sig.contact.any(axis=0)
                strain = sig.strain.max(axis=0)
                true_m = sig.first_contact_m.copy()
                dist = _radial(loop, classifiers, sig, touching, true_m, offset, whiskers.length_m)
                touch_steps += int(touching.any())
            if state.name == fsm.HIT_2 and angle_clf is not None:
                rec = deflection_volts(loop.since(hit1_sample), offset).reshape(-1, 2 * W)
                if len(rec) >= 2:
                    angle = math.remainder(
                        float(loop.timed("surface_angle", angle_clf.predict, rec)), math.pi
                    )
            if state.name == fsm.HIT_1:
                hit1_sample = loop.n
            fl = apply_motion(pose, np.c_[FLOOR_WHISKERS_M, np.zeros(2)])
            r = loop.rows
            r["state"].append(state.name)
            r["odo"].append(odometry(start, pose, rng_odo, odometry_error, heading_drift_rad_m))
            r["contact"].append(touching.copy())
            r["dist"].append(np.where(touching, dist, np.nan))
            r["angle"].append(angle)
            r["pose"].append(start)
            r["true_m"].append(true_m)
            r["floor"].append(None)  # filled by floor_bg: the latest report at this step
            r["tex_true"].append(tuple(str(t) for t in arena.texture_at(fl[:, 0], fl[:, 1])))
            r["tex_pred"].append(None)
            loop.step_start.append(loop.n)
            if m:
                # this step's floor whiskers run beside the next step's obstacle
                # whiskers (the FSM never reads them); their columns and the floor
                # report of this step's row are filled in when they finish
                floor_bg.submit(t_s, poses, hall, len(r["state"]) - 1)
            elapsed += max(m, 1) / sample_rate_hz if command.duration_s > 0 else 0.0
            at_end = sig.contact[-1] if m else np.zeros(W, bool)
            obs = fsm.Observation(
                tuple(bool(x) for x in touching),
                tuple(float(x) for x in strain),
                bumped,
                tuple(bool(x) for x in at_end),
            )
            state, command = fsm.transition(state, obs, rng_fsm, s)
            if progress is not None:
                progress(min(elapsed / seconds, 1.0))
    except BaseException:
        floor_bg.close()
        raise
    floor_bg.finish(np.zeros((2, len(textures))), ("", ""))
    if stats is not None:
        stats.update(
            steps=whiskers.steps,
            physics_steps=whiskers.physics_steps,
            physics_whisker_steps=whiskers.physics_whisker_steps,
            touch_steps=touch_steps,
            failures=whiskers.failures,
        )
    return _record(
        arena,
        seed,
        loop,
        pose,
        textures,
        sample_rate_hz,
        map_size_m,
        cell_m,
        floor_clf is not None,
        time.perf_counter() - wall0,
        layout,
    )


def _radial(
    loop: _Loop,
    classifiers: RealtimeClassifiers | None,
    sig: Any,
    touching: np.ndarray,
    true_m: np.ndarray,
    offset: float,
    length_m: float,
) -> np.ndarray:
    """Radial distance per touching whisker: the classifier's, or the truth."""
    out = np.full(len(touching), np.nan)
    for w in np.flatnonzero(touching):
        if classifiers is None:
            est = true_m[w] if np.isfinite(true_m[w]) else length_m
        else:
            clf = classifiers.radial[w]

            def call(h: np.ndarray, clf: Any = clf) -> float:
                return float(clf.predict(peak_deflection(h, offset)))

            est = loop.timed("radial_distance", call, sig.hall_v[:, w])
        out[w] = float(np.clip(est, 0.0, length_m)) if np.isfinite(est) else length_m
    return out


def _record(
    arena: Arena,
    seed: int,
    loop: _Loop,
    pose: np.ndarray,
    textures: tuple[str, ...],
    rate: float,
    map_size_m: float,
    cell_m: float,
    with_floor: bool,
    wall_s: float,
    layout: WhiskerLayout,
) -> RunRecord:
    r = loop.rows
    offset = arena.map_offset_m(map_size_m, cell_m)
    true_pose = np.vstack([*r["pose"], pose]) + np.array([offset, offset, 0.0])
    log = SensorLog(
        layout=layout,
        state=np.array(r["state"]),
        odometry=np.array(r["odo"]),
        contact=np.array(r["contact"]),
        radial_distance_m=np.array(r["dist"]),
        surface_angle_rad=np.array(r["angle"]),
        start_pose=true_pose[0].copy(),
        floor_loglik=np.array(r["floor"]) if with_floor else None,
        floor_whisker_m=FLOOR_WHISKERS_M if with_floor else None,
        textures=textures if with_floor else (),
        true_pose=true_pose,
    )
    n = loop.n
    hall = (
        np.concatenate(loop.hall).astype(np.float32)
        if loop.hall
        else np.zeros((0, 6, 2), np.float32)
    )
    return RunRecord(
        arena=arena,
        seed=seed,
        log=log,
        sample_rate_hz=rate,
        time_s=np.arange(1, n + 1) / rate,
        hall_v=hall,
        pose=np.concatenate(loop.pose) if loop.pose else np.zeros((0, 3)),
        step_start=np.array(loop.step_start),
        contact_true_m=np.array(r["true_m"]),
        floor_texture_true=np.array(r["tex_true"], dtype=str).reshape(-1, 2),
        floor_texture_pred=np.array(r["tex_pred"], dtype=str).reshape(-1, 2),
        latency_s={k: np.array(x) for k, x in loop.latency.items()},
        wall_seconds=wall_s,
    )
