"""The simulated artificial whisker: geometry, rod dynamics, follicle, Hall sensor, contacts.

See ``docs/physics.md`` for the model and its validation.
"""

from vibrissa.whisker.geometry import PRESETS, WhiskerGeometry, preset, preset_names
from vibrissa.whisker.hall import HallSensor, calibrated_gain
from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS, RodModel, SimulationError
from vibrissa.whisker.simulate import (
    BaseMotion,
    DynamicState,
    PoleContact,
    SimulationResult,
    SurfaceContact,
    Trajectory,
    free_vibration,
    simulate,
)
from vibrissa.whisker.surfaces import TEXTURES, Surface, make_surface, texture_names

__all__ = [
    "BaseMotion",
    "DEFAULT_N_ELEMENTS",
    "PRESETS",
    "TEXTURES",
    "DynamicState",
    "HallSensor",
    "PoleContact",
    "RodModel",
    "SimulationError",
    "SimulationResult",
    "Surface",
    "SurfaceContact",
    "Trajectory",
    "WhiskerGeometry",
    "calibrated_gain",
    "free_vibration",
    "make_surface",
    "preset",
    "preset_names",
    "simulate",
    "texture_names",
]
