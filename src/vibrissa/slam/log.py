"""The sensor log a tactile SLAM run reads: one row per FSM step (thesis 6.5.3).

A robot (simulated or real) writes, for every FSM step: the FSM state, the odometry's
pose increment over the step, which whiskers touched and where along them (radial
distance from the whisker's base), a surface-angle estimate when the template classifier
gave one, and the floor-texture log-likelihoods of the floor whiskers. The filter never
sees the true pose; ``true_pose`` rides along only to score a run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

#: The FSM's states (6.5.3), the vocabulary of a log's ``state`` column.
FSM_STATES: tuple[str, ...] = ("FWD_1", "HIT_1", "FWD_2", "HIT_2", "ABORT", "BACK", "TURN")


@dataclass(frozen=True)
class WhiskerLayout:
    """Where the obstacle whiskers sit on the robot, in the robot's frame (x forward, y left).

    ``base_m`` is ``(n_whiskers, 2)``, ``angle_rad`` the direction of each whisker (its
    undeflected line, anticlockwise from forward), ``length_m`` its length outside the
    follicle. ``body_radius_m`` is the robot's body, free of objects by definition.
    """

    base_m: np.ndarray
    angle_rad: np.ndarray
    length_m: np.ndarray
    body_radius_m: float = 0.17

    def __post_init__(self) -> None:
        base = np.asarray(self.base_m, float)
        n = base.shape[0]
        if base.shape != (n, 2) or n == 0:
            raise ValueError(f"base_m must be (n_whiskers, 2), got shape {base.shape}")
        for name in ("angle_rad", "length_m"):
            arr = np.asarray(getattr(self, name), float)
            if arr.shape != (n,) or not np.all(np.isfinite(arr)):
                raise ValueError(f"{name} must hold {n} finite values, one per whisker")
        if np.any(np.asarray(self.length_m) <= 0) or not self.body_radius_m > 0:
            raise ValueError("whisker lengths and body_radius_m must be positive")

    @property
    def n_whiskers(self) -> int:
        """How many obstacle whiskers."""
        return int(np.asarray(self.base_m).shape[0])

    def points(self, distance_m: np.ndarray) -> np.ndarray:
        """Robot-frame points ``(..., n_whiskers, 2)`` at ``distance_m`` along each whisker."""
        d = np.asarray(distance_m, float)[..., None]
        direction = np.stack([np.cos(self.angle_rad), np.sin(self.angle_rad)], axis=-1)
        return np.asarray(self.base_m, float) + d * direction


@dataclass(frozen=True)
class SensorLog:
    """Per-step observations of one run (``n_steps`` rows).

    Attributes
    ----------
    state
        ``(n_steps,)`` FSM state names (:mod:`vibrissa.robots.crunchbot.fsm`), the state
        the robot was in during the step. Steps in ``BACK`` move the particles but add no
        evidence (6.5.3). ``HIT_1``, ``HIT_2`` and ``ABORT`` are events of no duration
        whose rows repeat what the step before sensed: the filter reads from them only
        the surface angle (on ``HIT_2``) and where a contact episode ends.
    odometry
        ``(n_steps, 3)`` measured increments ``(forward_m, left_m, rotation_rad)`` in the
        robot's frame at the step's start.
    contact
        ``(n_steps, n_whiskers)`` bool, whisker in contact during the step.
    radial_distance_m
        ``(n_steps, n_whiskers)`` estimated distance of the contact from the whisker's
        base (NaN where no contact).
    surface_angle_rad
        ``(n_steps,)`` the template classifier's surface angle in the robot's frame (NaN
        where none).
    floor_loglik
        ``(n_steps, n_floor_whiskers, n_textures)`` log-likelihoods, or ``None``.
    floor_whisker_m
        ``(n_floor_whiskers, 2)`` robot-frame points where the floor whiskers brush.
    textures
        Names of the texture classes of ``floor_loglik``'s last axis.
    start_pose
        ``(3,)`` the known start pose in the map frame.
    true_pose
        ``(n_steps + 1, 3)`` the true pose before each step and after the last, or ``None``.
    """

    layout: WhiskerLayout
    state: np.ndarray
    odometry: np.ndarray
    contact: np.ndarray
    radial_distance_m: np.ndarray
    surface_angle_rad: np.ndarray
    start_pose: np.ndarray
    floor_loglik: np.ndarray | None = None
    floor_whisker_m: np.ndarray | None = None
    textures: tuple[str, ...] = ()
    true_pose: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = len(self.state)
        w = self.layout.n_whiskers
        shapes = {
            "odometry": (t, 3),
            "contact": (t, w),
            "radial_distance_m": (t, w),
            "surface_angle_rad": (t,),
            "start_pose": (3,),
        }
        for name, shape in shapes.items():
            got = np.shape(getattr(self, name))
            if got != shape:
                raise ValueError(f"sensor log: {name} must have shape {shape}, got {got}")
        if not np.all(np.isfinite(self.odometry)):
            raise ValueError("sensor log: odometry holds NaN or infinite values")
        d = np.asarray(self.radial_distance_m)[np.asarray(self.contact, bool)]
        if not np.all(np.isfinite(d)):
            raise ValueError("sensor log: a contact without a finite radial_distance_m")
        if self.floor_loglik is not None:
            ll = np.asarray(self.floor_loglik)
            if (
                ll.ndim != 3
                or ll.shape[0] != t
                or ll.shape[2] != len(self.textures)
                or (
                    self.floor_whisker_m is None
                    or np.shape(self.floor_whisker_m) != (ll.shape[1], 2)
                )
            ):
                raise ValueError(
                    "sensor log: floor_loglik must be (n_steps, n_floor_whiskers, "
                    "n_textures) with floor_whisker_m and textures to match"
                )
        if self.true_pose is not None and np.shape(self.true_pose) != (t + 1, 3):
            raise ValueError(f"sensor log: true_pose must have shape {(t + 1, 3)}")

    @property
    def n_steps(self) -> int:
        """How many FSM steps."""
        return len(self.state)

    def head(self, n_steps: int) -> SensorLog:
        """The log's first ``n_steps`` steps.

        Raises
        ------
        ValueError
            ``n_steps`` not in ``1..self.n_steps``.
        """
        if (
            isinstance(n_steps, bool)
            or not isinstance(n_steps, int | np.integer)
            or not (1 <= n_steps <= self.n_steps)
        ):
            raise ValueError(f"n_steps must be an integer in 1..{self.n_steps}, got {n_steps!r}")
        n = int(n_steps)
        return replace(
            self,
            state=self.state[:n],
            odometry=self.odometry[:n],
            contact=self.contact[:n],
            radial_distance_m=self.radial_distance_m[:n],
            surface_angle_rad=self.surface_angle_rad[:n],
            floor_loglik=None if self.floor_loglik is None else self.floor_loglik[:n],
            true_pose=None if self.true_pose is None else self.true_pose[: n + 1],
        )


def fsm_outcome_counts(states: Sequence[str] | np.ndarray) -> dict[str, Any]:
    """How the FSM's episodes ended in a run's sequence of states (one per step).

    Parameters
    ----------
    states
        The state of each step, in order (a sensor log's ``state``).

    Returns
    -------
    dict
        ``hit_1``, ``hit_2``, ``abort``, ``turn``: how many steps were in each of those
        states; ``abort_after``: the aborts by the state the robot was in when the strain
        (or the bumper) stopped it (``FWD_1``, ``FWD_2``, ``TURN``); ``fwd2_ends``: of
        the FWD_2 runs, how many ended in HIT_2 and how many in ABORT; ``back_steps``: the
        BACK steps.
    """
    s = [str(x) for x in states]
    unknown = sorted(set(s) - set(FSM_STATES))
    if unknown:
        raise ValueError(
            f"unknown FSM state(s) {', '.join(unknown)}; states are {', '.join(FSM_STATES)}"
        )
    after: dict[str, int] = {"FWD_1": 0, "FWD_2": 0, "TURN": 0}
    for prev, cur in zip(s[:-1], s[1:], strict=False):
        if cur == "ABORT" and prev in after:
            after[prev] += 1
    return {
        "hit_1": s.count("HIT_1"),
        "hit_2": s.count("HIT_2"),
        "abort": s.count("ABORT"),
        "turn": s.count("TURN"),
        "abort_after": after,
        "fwd2_ends": {"hit_2": s.count("HIT_2"), "abort": after["FWD_2"]},
        "back_steps": s.count("BACK"),
    }
