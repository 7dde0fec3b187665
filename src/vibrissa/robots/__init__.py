"""Robots that move objects into (or whiskers onto) things: the XY positioning stage."""

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
    "SurfaceStimulus",
    "TrialResult",
    "XYStage",
    "run_trial",
]
