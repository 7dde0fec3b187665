"""CrunchBot (thesis 3.5, 6.5): its arenas, state machine and synthetic runs.

The arenas, the finite state machine of 6.5.3 and a synthetic run with exact whisker
contacts that feeds :mod:`vibrissa.slam`.
"""

from vibrissa.robots.crunchbot.arena import (
    PRESETS,
    ROBOT_RADIUS_M,
    Arena,
    Obstacle,
    Pose,
    arena_from_dict,
    get_arena,
    load_arena,
)
from vibrissa.robots.crunchbot.fsm import (
    STATES,
    FsmSettings,
    FsmState,
    MotorCommand,
    Observation,
    transition,
)
from vibrissa.robots.crunchbot.record import (
    CLASSIFIERS,
    N_OBSTACLE_WHISKERS,
    WHISKER_NAMES,
    RunRecord,
)
from vibrissa.robots.crunchbot.synthetic import (
    CRUNCHBOT_LAYOUT,
    cast_rays,
    synthetic_log,
    synthetic_record,
    texture_grid,
    whisker_contacts,
)

__all__ = [
    "CLASSIFIERS",
    "N_OBSTACLE_WHISKERS",
    "WHISKER_NAMES",
    "RunRecord",
    "CRUNCHBOT_LAYOUT",
    "PRESETS",
    "ROBOT_RADIUS_M",
    "STATES",
    "Arena",
    "FsmSettings",
    "FsmState",
    "MotorCommand",
    "Obstacle",
    "Observation",
    "Pose",
    "arena_from_dict",
    "cast_rays",
    "get_arena",
    "load_arena",
    "synthetic_log",
    "synthetic_record",
    "texture_grid",
    "transition",
    "whisker_contacts",
]
