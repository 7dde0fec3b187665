"""Tactile SLAM (thesis 6.5.3-6.5.6): a particle filter of poses and occupancy grids fed by
a robot's per-step sensor log, three mapping modes and the map error of eq. 6.3.

This package reads only a :class:`SensorLog`: it never imports the simulator, so a log
written by a real robot runs the same way.
"""

from vibrissa.slam.error import map_error, random_map_error, smooth_ground_truth
from vibrissa.slam.filter import (
    MODES,
    ParticleFilter,
    SlamRun,
    SlamSettings,
    effective_sample_size,
    run_slam,
    systematic_resample,
)
from vibrissa.slam.grid import add_blob, add_edge, edge_likelihood
from vibrissa.slam.log import SensorLog, WhiskerLayout

__all__ = [
    "MODES",
    "ParticleFilter",
    "SensorLog",
    "SlamRun",
    "SlamSettings",
    "WhiskerLayout",
    "add_blob",
    "add_edge",
    "edge_likelihood",
    "effective_sample_size",
    "map_error",
    "random_map_error",
    "run_slam",
    "smooth_ground_truth",
    "systematic_resample",
]
