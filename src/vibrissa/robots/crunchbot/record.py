"""What one CrunchBot run leaves behind: the sensor log, the raw whisker signals, the truth.

A :class:`RunRecord` is the interface between the simulated robot
(:mod:`vibrissa.robots.crunchbot`), the evaluation of 6.5.6 (``vibrissa reproduce
crunchbot-slam``) and the viewer (``vibrissa run crunchbot``). The filter reads only
``log`` (without its ``true_pose``); everything else is there to score and to watch a run.

Frames: ``pose`` and ``log.true_pose`` are ``(x_m, y_m, heading_rad)``; ``pose`` is in the
arena's frame (its corner at the origin), ``log`` in the map frame (the arena centred in
the SLAM map, :meth:`~vibrissa.robots.crunchbot.arena.Arena.map_offset_m`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vibrissa.robots.crunchbot.arena import Arena
from vibrissa.slam.log import SensorLog

#: The six whiskers in the order of every per-whisker axis: the four forward obstacle
#: whiskers from right to left (the order of ``CRUNCHBOT_LAYOUT``), then the two outer
#: floor whiskers in the order of ``FLOOR_WHISKERS_M`` (left, then right).
WHISKER_NAMES = ("w1", "w2", "w3", "w4", "floor_left", "floor_right")
#: How many of :data:`WHISKER_NAMES` are obstacle whiskers (the first ones).
N_OBSTACLE_WHISKERS = 4
#: Real-time classifiers timed in the control loop (keys of ``RunRecord.latency_s``).
CLASSIFIERS = ("floor_texture", "radial_distance", "surface_angle")


@dataclass(frozen=True)
class RunRecord:
    """One run of the robot.

    Attributes
    ----------
    arena
        Where it ran.
    seed
        The run's seed (same seed, same record).
    log
        Per FSM step what the robot reported (:class:`~vibrissa.slam.log.SensorLog`,
        map frame, with ``true_pose``).
    sample_rate_hz
        The whiskers' sample rate (2 kHz, thesis 3.5.2).
    time_s
        ``(n_samples,)`` robot time of each whisker sample.
    hall_v
        ``(n_samples, 6, 2)`` float32 Hall outputs (x, y) of the six whiskers in
        :data:`WHISKER_NAMES` order (V).
    pose
        ``(n_samples, 3)`` true arena-frame pose at each sample.
    step_start
        ``(n_steps + 1,)`` index into the samples where each FSM step starts, and the
        end; the zero-length HIT and ABORT rows start and end on the same sample.
    contact_true_m
        ``(n_steps, 4)`` true radial distance from each obstacle whisker's base of the
        first point it touched in the step (NaN: no contact), from the physics.
    floor_texture_true, floor_texture_pred
        ``(n_steps, 2)`` tile texture under each floor whisker's tip at the step's end,
        and the real-time classifier's choice there (``""``: none).
    latency_s
        Per classifier of :data:`CLASSIFIERS`, the wall time of each call in the control
        loop (s).
    wall_seconds
        Wall time of the whole run, physics and classifiers.
    """

    arena: Arena
    seed: int
    log: SensorLog
    sample_rate_hz: float
    time_s: np.ndarray
    hall_v: np.ndarray
    pose: np.ndarray
    step_start: np.ndarray
    contact_true_m: np.ndarray
    floor_texture_true: np.ndarray
    floor_texture_pred: np.ndarray
    latency_s: dict[str, np.ndarray] = field(default_factory=dict)
    wall_seconds: float = float("nan")

    def __post_init__(self) -> None:
        n = np.shape(self.time_s)[0] if np.ndim(self.time_s) == 1 else -1
        t = self.log.n_steps
        shapes = {
            "hall_v": (n, len(WHISKER_NAMES), 2),
            "pose": (n, 3),
            "step_start": (t + 1,),
            "contact_true_m": (t, N_OBSTACLE_WHISKERS),
            "floor_texture_true": (t, 2),
            "floor_texture_pred": (t, 2),
        }
        if n < 0:
            raise ValueError(f"run record: time_s must be 1-D, got shape {np.shape(self.time_s)}")
        for name, shape in shapes.items():
            got = np.shape(getattr(self, name))
            if got != shape:
                raise ValueError(f"run record: {name} must have shape {shape}, got {got}")
        starts = np.asarray(self.step_start)
        if t and (np.any(np.diff(starts) < 0) or starts[0] < 0 or starts[-1] > n):
            raise ValueError("run record: step_start must be non-decreasing sample indices")
        if not self.sample_rate_hz > 0:
            raise ValueError(
                f"run record: sample_rate_hz must be positive, got {self.sample_rate_hz!r}"
            )
        unknown = set(self.latency_s) - set(CLASSIFIERS)
        if unknown:
            raise ValueError(
                f"run record: unknown classifier(s) {sorted(unknown)} in "
                f"latency_s; known: {', '.join(CLASSIFIERS)}"
            )

    @property
    def seconds(self) -> float:
        """Simulated robot time (s)."""
        return float(len(self.time_s) / self.sample_rate_hz)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall second (NaN if the wall time is unknown)."""
        return self.seconds / self.wall_seconds if self.wall_seconds > 0 else float("nan")
