"""Robots that move objects into (or whiskers onto) things.

The XY positioning stage and whisking robots (:mod:`vibrissa.robots.whisking`: SCRATCHbot
and BIOTACT G1's whisking pattern generator with rapid cessation of protraction), and
CrunchBot's arenas, state machine and synthetic runs (:mod:`vibrissa.robots.crunchbot`).
"""

from vibrissa.robots.whisking import (
    RCPControl,
    VaryingWhiskPattern,
    WhiskerSetup,
    WhiskPattern,
    rcp_gating,
    run_whisking,
)
from vibrissa.robots.xy_stage import (
    LatencyModel,
    PoleStimulus,
    SurfaceStimulus,
    TrialResult,
    XYStage,
    run_trial,
)

__all__ = [
    "LatencyModel",
    "PoleStimulus",
    "RCPControl",
    "SurfaceStimulus",
    "TrialResult",
    "VaryingWhiskPattern",
    "WhiskPattern",
    "WhiskerSetup",
    "XYStage",
    "rcp_gating",
    "run_trial",
    "run_whisking",
]
