"""Simulate a protocol's trials: the unit of work of a (parallel) generation.

:func:`simulate_trials` runs any subset of a protocol's trials and returns plain
arrays. Every trial draws from its own random stream, the SeedSequence spawn
key ``(TRIALS, trial index)`` of the protocol's seed
(:mod:`vibrissa.experiments.streams`), so results do not depend on how trials are
split into chunks, which process runs them, or in which order: the same seed
gives the same bytes.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import Any

import numpy as np

from vibrissa.experiments.protocols import Protocol, TrialSpec
from vibrissa.experiments.streams import SURFACES, TRIALS, stream
from vibrissa.robots.xy_stage import PoleStimulus, SurfaceStimulus, run_trial
from vibrissa.robots.xy_variability import VariabilityState
from vibrissa.whisker.geometry import WhiskerGeometry, preset
from vibrissa.whisker.hall import HallSensor
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.surfaces import TEXTURES, Surface, make_surface

__all__ = [
    "TRIAL_DIAGNOSTICS",
    "hall_sensor",
    "n_samples",
    "session_surface",
    "simulate_trials",
    "whisker_attrs",
    "whisker_model",
]

#: Per-trial quantities recorded besides the signal.
TRIAL_DIAGNOSTICS = (
    "contact_onset_s",
    "threshold_time_s",
    "retract_start_s",
    "contact_end_s",
    "latency_s",
    "contact_duration_s",
    "slipped_off",
    "saturated",
    "peak_deflection_v",
)

#: Diagnostics that are flags (stored as bool).
_BOOL_DIAGNOSTICS = ("slipped_off", "saturated")

_DRIFT_LEVELS = 20


def n_samples(protocol: Protocol) -> int:
    """Samples per recorded trial."""
    fs = protocol.sensor.sample_rate_hz
    return int(round(protocol.window_s[0] * fs)) + int(round(protocol.window_s[1] * fs)) + 1


@lru_cache(maxsize=8)
def _specs(protocol: Protocol) -> tuple[TrialSpec, ...]:
    return tuple(protocol.trials())


@lru_cache(maxsize=64)
def whisker_model(whisker: str, n_elements: int, drift: float) -> RodModel:
    """The rod model of a whisker preset, its stiffness drifted by a fraction (cached).

    Parameters
    ----------
    whisker : str
        Preset name.
    n_elements : int
        Rod discretisation.
    drift : float
        Relative change of Young's modulus and follicle stiffness (0: the nominal
        whisker).

    Returns
    -------
    RodModel
    """
    g = preset(whisker)
    if drift != 0.0:
        g = g.replace(
            youngs_modulus_gpa=g.youngs_modulus_gpa * (1 + drift),
            follicle_stiffness_nm_per_rad=g.follicle_stiffness_nm_per_rad * (1 + drift),
        )
    return RodModel(g, n_elements)


@lru_cache(maxsize=8)
def hall_sensor(protocol: Protocol) -> HallSensor:
    """The session's Hall sensor (cached).

    ``protocol.sensor`` calibrated on the nominal whisker: calibration precedes a
    session, so the drifting whisker is read through the same gain throughout.
    """
    return protocol.sensor.calibrate(preset(protocol.whisker), protocol.n_elements)


@lru_cache(maxsize=16)
def session_surface(texture: str, seed: int) -> Surface:
    """The one physical sheet of ``texture`` used for a whole session of ``seed`` (cached).

    Drawn from the session's ``SURFACES`` stream (:mod:`vibrissa.experiments.streams`).
    """
    return make_surface(
        texture, seed=np.random.default_rng(stream(seed, SURFACES, list(TEXTURES).index(texture)))
    )


def whisker_attrs(protocol: Protocol) -> dict[str, Any]:
    """What a classifier needs to know about the whisker and sensor (Dataset attr)."""
    g: WhiskerGeometry = preset(protocol.whisker)
    s = hall_sensor(protocol)
    d = g.to_dict()
    d.update(
        n_elements=protocol.n_elements,
        hall_gain_v=s.gain_v,
        hall_offset_v=s.offset_v,
        hall_calibration_mm=list(protocol.sensor.calibration_point(g)),
        hall_sensor=s.to_dict(),
        natural_frequencies_hz=whisker_model(protocol.whisker, protocol.n_elements, 0.0)
        .natural_frequencies_hz[:3]
        .tolist(),
        # the resonance of chapter-5 recordings (tip held by the surface; 5.3.1)
        tip_pinned_frequency_hz=float(
            whisker_model(protocol.whisker, protocol.n_elements, 0.0).pinned_frequencies_hz(
                g.length_mm, 1
            )[0]
        ),
    )
    return d


def simulate_trials(protocol: Protocol, indices: Sequence[int]) -> dict[str, np.ndarray]:
    """Simulate the trials ``indices`` of ``protocol``.

    Returns
    -------
    dict
        ``index`` (n,), ``signal`` (n, 2, n_samples) in volts, and one array per
        name in :data:`TRIAL_DIAGNOSTICS`.
    """
    specs = _specs(protocol)
    idx = np.asarray(indices, dtype=np.int64)
    if idx.size and (idx.min() < 0 or idx.max() >= len(specs)):
        raise ValueError(f"trial indices must lie in [0, {len(specs)})")
    ns = n_samples(protocol)
    out: dict[str, np.ndarray] = {
        "index": idx,
        "signal": np.empty((idx.size, 2, ns)),
        **{
            name: np.empty(idx.size, dtype=bool if name in _BOOL_DIAGNOSTICS else float)
            for name in TRIAL_DIAGNOSTICS
        },
    }
    sensor = hall_sensor(protocol)
    n_total = len(specs)
    for k, i in enumerate(idx):
        spec = specs[int(i)]
        rng = np.random.default_rng(stream(protocol.seed, TRIALS, int(i)))
        # each trial's physical variability, drawn first from its own stream (no creep
        # memory: see Protocol.variability)
        perturbation = VariabilityState(protocol.variability).draw(
            rng, previous_peak_tan=0.0, previous_direction=0, interval_s=0.0
        )
        drift = 0.0
        if protocol.drift_fraction:
            level = round(spec.order / max(n_total - 1, 1) * _DRIFT_LEVELS) / _DRIFT_LEVELS
            drift = protocol.drift_fraction * level
        # the modulus' temperature change joins the session's drift on the drift levels'
        # grid (0.25 % steps for the default -5 %): a few dozen cached models per worker,
        # each costing ~0.2 s to set up (its damping), instead of one per trial
        step = abs(protocol.drift_fraction) / _DRIFT_LEVELS if protocol.drift_fraction else 0.0025
        drift = round(((1 + drift) * perturbation.modulus_factor - 1) / step) * step
        model = whisker_model(protocol.whisker, protocol.n_elements, drift)
        surface = None
        if protocol.name == "radial-distance":
            stim: PoleStimulus | SurfaceStimulus = PoleStimulus(spec.labels["radial_distance_mm"])
        else:
            stim = SurfaceStimulus(spec.labels["texture"], spec.labels["angle_deg"])
            surface = session_surface(spec.labels["texture"], protocol.seed)
        res = run_trial(
            protocol.stage,
            model,
            sensor,
            stim,
            spec.labels["speed_mm_s"],
            spec.direction,
            protocol.window_s,
            rng,
            dt_s=protocol.dt_s,
            surface=surface,
            perturbation=perturbation,
        )
        out["signal"][k] = res.signal_v
        for name in TRIAL_DIAGNOSTICS:
            out[name][k] = getattr(res, name)
    return out
