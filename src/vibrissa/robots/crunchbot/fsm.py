"""CrunchBot's finite state machine for tactile SLAM (thesis 6.5.3) as a pure function.

FWD_1 drives forward in 0.5 s steps at 0.05 m/s until a whisker touches (HIT_1); FWD_2
then creeps forward at 0.02 m/s until a second whisker touches (HIT_2) or a whisker's
strain passes the safety threshold (ABORT); the robot then reverses in 0.5 s steps at
0.05 m/s (BACK) and turns on the spot at 0.3 rad/s (TURN) by an angle drawn from a
mixture of two Gaussians, then goes forward again.

What the thesis leaves open is a setting, identified on the simulated robot from what
the thesis reports (ABORT ends FWD_2 only "in some cases"; the angle training's drives
into a wall; ``scripts/identify_crunchbot_fsm.py``,
``docs/runs/identify_crunchbot_fsm.json``): the strain threshold (``strain_limit``); what
"until a second whisker makes contact" counts (``two_in_contact``: two whiskers touching
in a FWD_2 step is a second contact even if both touched at HIT_1, as when a wall meets
two whiskers at once; off: only a whisker that did not touch at HIT_1 counts); whether
BACK repeats its step while a whisker still touches ("then BACK to escape";
``back_until_clear``, at most ``max_back_steps`` steps); and whether the strain is
watched during TURN (``monitor_turn``: an over-strain stops the turn and the FSM goes to
ABORT, then BACK). TURN is unwatched by default, as the thesis reads: "each FWD_1, FWD_2
and BACK step ... lasts for 0.5 s ... within each 0.5 s FSM step, the whisker strains
are monitored", and TURN is no 0.5 s step; watched, a whisker left pressed on an
obstacle after BACK stops every turn at once, and the robot can stay stuck there.

:func:`transition` maps ``(state, observation) -> (next state, motor command)``: the
observation is what the robot sensed while it carried out ``state``'s command, and the
command is the one to carry out in the next state. The robot (not this module) watches
the strain during a step and stops early when it passes the threshold; it reports that
as :attr:`Observation.strain`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from vibrissa import _validate as v
from vibrissa.slam.log import FSM_STATES
from vibrissa.slam.log import fsm_outcome_counts as outcome_counts

FWD_1, HIT_1, FWD_2, HIT_2, ABORT, BACK, TURN = (
    "FWD_1",
    "HIT_1",
    "FWD_2",
    "HIT_2",
    "ABORT",
    "BACK",
    "TURN",
)
#: Every state, in the thesis' order (the sensor log's vocabulary, :mod:`vibrissa.slam.log`).
STATES = FSM_STATES
__all__ = [
    "ABORT",
    "BACK",
    "FWD_1",
    "FWD_2",
    "HIT_1",
    "HIT_2",
    "STATES",
    "TURN",
    "FsmSettings",
    "FsmState",
    "MotorCommand",
    "Observation",
    "command_for",
    "draw_turn",
    "outcome_counts",
    "transition",
]


@dataclass(frozen=True)
class FsmSettings:
    """The FSM's numbers (thesis 6.5.3 unless noted).

    ``turn_components`` are ``(weight, mean_rad, variance_rad2)``: a narrow one
    (0.14 pi, variance 0) for wall following and a wide one (0.3 pi, variance 0.25 pi)
    for exploring; the thesis gives no weights, so they are equal (ours). Positive angles
    turn anticlockwise, which makes the robot circle the arena anticlockwise as the
    thesis reports. ``strain_limit`` is in the units the robot reports strain in: the
    obstacle whiskers' Hall deflection as a fraction of the sensor's full scale
    (:mod:`~vibrissa.robots.crunchbot.obstacle_whiskers`). The thesis gives no number;
    0.7 is identified from its angle-training drives (the lowest threshold at which more
    of them end in HIT_2 than in ABORT; ``scripts/identify_crunchbot_fsm.py``).
    ``back_until_clear``, ``max_back_steps``, ``monitor_turn`` and ``two_in_contact``: the
    module's note.
    """

    step_s: float = 0.5
    fwd1_speed_m_s: float = 0.05
    fwd2_speed_m_s: float = 0.02
    back_speed_m_s: float = 0.05
    turn_rate_rad_s: float = 0.3
    strain_limit: float = 0.7
    back_until_clear: bool = True
    max_back_steps: int = 4
    monitor_turn: bool = False
    two_in_contact: bool = True
    turn_components: tuple[tuple[float, float, float], ...] = (
        (0.5, 0.14 * math.pi, 0.0),
        (0.5, 0.3 * math.pi, 0.25 * math.pi),
    )

    def __post_init__(self) -> None:
        for name in (
            "step_s",
            "fwd1_speed_m_s",
            "fwd2_speed_m_s",
            "back_speed_m_s",
            "turn_rate_rad_s",
            "strain_limit",
        ):
            v.positive(name, getattr(self, name))
        if isinstance(self.max_back_steps, bool) or not isinstance(self.max_back_steps, int):
            raise TypeError(f"max_back_steps must be an integer, got {self.max_back_steps!r}")
        if self.max_back_steps < 1:
            raise ValueError(f"max_back_steps must be at least 1, got {self.max_back_steps}")
        if not self.turn_components:
            raise ValueError("turn_components must hold at least one (weight, mean, variance)")
        for i, (w, m, var) in enumerate(self.turn_components):
            v.positive(f"turn_components[{i}] weight", w)
            v.finite(f"turn_components[{i}] mean", m)
            v.non_negative(f"turn_components[{i}] variance", var)


@dataclass(frozen=True)
class FsmState:
    """A state and what it remembers.

    The whiskers that made the first contact, and how many BACK steps in a row it took.
    """

    name: str = FWD_1
    first_contact: frozenset[int] = field(default_factory=frozenset)
    back_steps: int = 0

    def __post_init__(self) -> None:
        if self.name not in STATES:
            raise ValueError(f"unknown FSM state {self.name!r}; states are {', '.join(STATES)}")


@dataclass(frozen=True)
class Observation:
    """What the robot sensed during a step.

    Contact per whisker during the step, peak strain per whisker, whether the body bumped
    into something (the Create's bumper; the thesis does not say what happened then: ours,
    it aborts like an over-strain), and contact per whisker at the step's end (what BACK
    asks: is a whisker still touching? ``None``: as ``contact``).
    """

    contact: tuple[bool, ...]
    strain: tuple[float, ...] = ()
    bumped: bool = False
    contact_at_end: tuple[bool, ...] | None = None


@dataclass(frozen=True)
class MotorCommand:
    """Drive at ``linear_m_s`` forward and ``angular_rad_s`` anticlockwise for ``duration_s``."""

    linear_m_s: float
    angular_rad_s: float
    duration_s: float

    @property
    def displacement(self) -> tuple[float, float]:
        """``(distance_m, rotation_rad)`` the command asks for."""
        return self.linear_m_s * self.duration_s, self.angular_rad_s * self.duration_s


STOP = MotorCommand(0.0, 0.0, 0.0)


def draw_turn(settings: FsmSettings, rng: np.random.Generator) -> float:
    """A turn angle in radians (anticlockwise positive) from the two-Gaussian mixture."""
    comps = np.array(settings.turn_components, dtype=float)
    k = rng.choice(len(comps), p=comps[:, 0] / comps[:, 0].sum())
    return float(comps[k, 1] + math.sqrt(comps[k, 2]) * rng.standard_normal())


def command_for(name: str, settings: FsmSettings, rng: np.random.Generator) -> MotorCommand:
    """The motor command carried out in state ``name`` (a fresh turn angle for TURN)."""
    s = settings
    if name == FWD_1:
        return MotorCommand(s.fwd1_speed_m_s, 0.0, s.step_s)
    if name == FWD_2:
        return MotorCommand(s.fwd2_speed_m_s, 0.0, s.step_s)
    if name == BACK:
        return MotorCommand(-s.back_speed_m_s, 0.0, s.step_s)
    if name == TURN:
        angle = draw_turn(s, rng)
        return MotorCommand(
            0.0, math.copysign(s.turn_rate_rad_s, angle), abs(angle) / s.turn_rate_rad_s
        )
    return STOP


def transition(
    state: FsmState, obs: Observation, rng: np.random.Generator, settings: FsmSettings | None = None
) -> tuple[FsmState, MotorCommand]:
    """One step of the FSM: the next state and the command to carry out in it.

    Parameters
    ----------
    state
        The state whose command the robot just carried out.
    obs
        What it sensed meanwhile (contacts and peak strains, one entry per whisker).
    rng
        Draws TURN angles.
    settings
        The FSM's numbers; default :class:`FsmSettings`.
    """
    s = settings or FsmSettings()
    touching = frozenset(i for i, c in enumerate(obs.contact) if c)
    unsafe = obs.bumped or any(x > s.strain_limit for x in obs.strain)
    name = state.name
    first = state.first_contact
    if name == FWD_1:
        nxt = ABORT if unsafe else HIT_1 if touching else FWD_1
        first = touching
    elif name == HIT_1:
        nxt = FWD_2
    elif name == FWD_2:
        second = bool(touching - first) or (s.two_in_contact and len(touching) >= 2)
        nxt = ABORT if unsafe else HIT_2 if second else FWD_2
    elif name in (HIT_2, ABORT):
        nxt = BACK
    elif name == BACK:
        backs = state.back_steps + 1
        still = obs.contact if obs.contact_at_end is None else obs.contact_at_end
        again = s.back_until_clear and any(still) and backs < s.max_back_steps
        nxt = BACK if again else TURN
    else:  # TURN
        nxt = ABORT if s.monitor_turn and unsafe else FWD_1
    if nxt in (BACK, TURN, FWD_1):
        first = frozenset()
    back_steps = state.back_steps + 1 if name == BACK and nxt == BACK else 0
    return FsmState(nxt, first, back_steps), command_for(nxt, s, rng)
