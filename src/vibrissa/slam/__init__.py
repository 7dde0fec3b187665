"""Tactile SLAM (thesis 6.5.3-6.5.6): a particle filter, mapping modes and the map error.

The particle filter is of poses and occupancy grids fed by a robot's per-step sensor log;
there are three mapping modes, and the map error is that of eq. 6.3.

The filter (:class:`ParticleFilter`) is an iterator over a log, one FSM step per ``next``;
:mod:`~vibrissa.slam.collectors` record what a caller wants of it as it runs, and
:func:`run_slam` runs it to the end. The mapping modes are :class:`Mapper` classes
registered in :data:`MAPPERS` by name (:mod:`~vibrissa.slam.mappers`).

This package reads only a :class:`SensorLog`: it never imports the simulator, so a log
written by a real robot runs the same way.
"""

from vibrissa.slam.collectors import Collector, Frames, FrameStack, PoseEstimates, Progress
from vibrissa.slam.error import arena_mask, map_error, random_map_error, smooth_ground_truth
from vibrissa.slam.filter import (
    MODES,
    SHAFT_POINTS,
    ParticleFilter,
    SlamRun,
    SlamSettings,
    effective_sample_size,
    run_slam,
    systematic_resample,
)
from vibrissa.slam.grid import add_blob, add_edge, edge_likelihood
from vibrissa.slam.log import SensorLog, WhiskerLayout
from vibrissa.slam.mappers import MAPPERS, Mapper, register_mapper

__all__ = [
    "MAPPERS",
    "MODES",
    "SHAFT_POINTS",
    "Collector",
    "FrameStack",
    "Frames",
    "Mapper",
    "ParticleFilter",
    "PoseEstimates",
    "Progress",
    "SensorLog",
    "SlamRun",
    "SlamSettings",
    "WhiskerLayout",
    "add_blob",
    "add_edge",
    "edge_likelihood",
    "effective_sample_size",
    "arena_mask",
    "map_error",
    "random_map_error",
    "register_mapper",
    "run_slam",
    "smooth_ground_truth",
    "systematic_resample",
]
