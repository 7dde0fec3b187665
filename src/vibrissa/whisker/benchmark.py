"""The physics benchmark: real-time factor of the standard pole-contact trial.

:func:`physics_benchmark` times the standard scenario (:data:`SCENARIO`,
parameters in :data:`STANDARD`): a thin pole sweeps into the XY-robot whisker and
back, simulated by :func:`vibrissa.whisker.simulate.simulate` and read out by the
Hall sensor at 4 kHz. It reports the real-time factor (simulated seconds per
wall-clock second on one core), CPU time and the peak memory of one trial.
``vibrissa bench physics`` prints it; ``benchmarks/bench_physics.py`` runs it over
time steps and element counts.
"""

from __future__ import annotations

import gc
import math
import os
import platform
import resource
import time
import tracemalloc
from typing import Any

import numpy as np

from vibrissa._validate import in_range
from vibrissa.whisker.hall import HallSettings, steps_per_sample

__all__ = [
    "CONTACT_SCENARIO",
    "FREE_FLIGHT_SCENARIO",
    "MEMORY_METHOD",
    "SCENARIO",
    "STANDARD",
    "physics_benchmark",
    "standard_trajectory",
    "whisk_in_air",
    "WHISKING_SCENARIO",
]

#: The standard scenario: a thin pole sweeps into the XY-robot whisker and back.
STANDARD: dict[str, Any] = {
    "preset": "xy-robot",
    "radial_distance_mm": 140.0,
    "start_gap_mm": 1.0,
    "pole_radius_mm": 0.5,
    "friction": 0.3,
    "speed_mm_s": 100.0,
    "advance_s": 0.3,
    "retract_speed_mm_s": 720.0,
    "retract_distance_mm": 36.0,
    "duration_s": 1.5,
    "dt_s": 2.5e-4,
    "sample_rate_hz": 4000.0,
}

SCENARIO = (
    "xy-robot whisker; thin pole (0.5 mm radius, friction 0.3) parallel to y at "
    "r = 140 mm, starting 1 mm from the shaft, advancing at 100 mm/s for 0.3 s, "
    "retracting at 720 mm/s by 36 mm, then still; 1.5 s simulated; Hall output "
    "sampled at 4 kHz"
)

MEMORY_METHOD = (
    "tracemalloc: peak of Python/NumPy allocations during one trial (simulate + "
    "hall_volts), above the level before it; memory allocated inside numba kernels "
    "is not traced"
)


def standard_trajectory(model: Any, duration_s: float | None = None) -> Any:
    """The pole's motion in the standard scenario, for ``model``'s whisker.

    Parameters
    ----------
    model : vibrissa.whisker.rod.RodModel
        The whisker (its radius at the contact sets the starting gap).
    duration_s : float, optional
        Length of the trajectory (default the scenario's 1.5 s).

    Returns
    -------
    vibrissa.whisker.simulate.Trajectory
        Piecewise-linear (x, z) positions in mm with exact piecewise-constant
        velocities, sampled every 0.125 ms.
    """
    from vibrissa.whisker.simulate import Trajectory

    sc = STANDARD
    T = sc["duration_s"] if duration_s is None else duration_s
    r = sc["radial_distance_mm"]
    shaft_r = float(model.geometry.radius_m(r * 1e-3)) * 1e3
    x0 = -(sc["start_gap_mm"] + sc["pole_radius_mm"] + shaft_r)
    t_adv = sc["advance_s"]
    t_ret = t_adv + sc["retract_distance_mm"] / sc["retract_speed_mm_s"]
    t = np.arange(int(math.ceil(T / 1.25e-4)) + 1) * 1.25e-4
    v = np.where(t < t_adv, sc["speed_mm_s"], np.where(t < t_ret, -sc["retract_speed_mm_s"], 0.0))
    x = x0 + sc["speed_mm_s"] * np.minimum(t, t_adv)
    x = x - sc["retract_speed_mm_s"] * np.clip(t - t_adv, 0.0, t_ret - t_adv)
    pos = np.column_stack([x, np.full_like(t, r)])
    vel = np.column_stack([v, np.zeros_like(t)])
    return Trajectory(t, pos, vel)


def _trial(
    model: Any,
    contact: Any,
    trajectory: Any,
    duration_s: float,
    dt_s: float,
    sensor: Any,
    **options: Any,
) -> Any:
    from vibrissa.whisker.simulate import simulate

    res = simulate(model, contact, trajectory, duration_s, dt_s, **options)
    volts = res.hall_volts(sensor=sensor)
    return res, volts


#: The free-flight figure: the whisker released from a static 10 mm tip deflection
#: rings down for 1.5 s, touching nothing.
FREE_FLIGHT_SCENARIO = (
    "xy-robot whisker released from a static 10 mm tip deflection, ringing down for "
    "1.5 s without contact; Hall output sampled at 4 kHz"
)

#: The whisking-in-air figure: the follicle housing turns through a raised-cosine
#: whisk of 12 degrees at 2 Hz (a SCRATCHbot-like whisk, thesis 6.3) for 1.5 s.
WHISKING_SCENARIO = (
    "xy-robot whisker whisking in air: the follicle housing turns through a raised-"
    "cosine whisk of 12 deg at 2 Hz for 1.5 s; Hall output sampled at 4 kHz"
)
WHISK_HZ = 2.0
WHISK_DEG = 12.0


def whisk_in_air(duration_s: float) -> Any:
    """The housing's motion of :data:`WHISKING_SCENARIO`, sampled every 62.5 us."""
    from vibrissa.whisker.simulate import BaseMotion

    t = np.arange(0.0, duration_s + 0.1, 6.25e-5)
    amp = math.radians(WHISK_DEG)
    w = 2.0 * math.pi * WHISK_HZ
    return BaseMotion(t, 0.5 * amp * (1.0 - np.cos(w * t)), 0.5 * amp * w * np.sin(w * t))


#: The contact figure: the standard scenario's first 0.35 s (the pole touches at
#: about 10 ms and leaves during the retraction), nearly all of it in contact.
CONTACT_SCENARIO = "the standard scenario's first 0.35 s: approach, 0.3 s push, retraction"
CONTACT_PHASE_S = 0.35


def _phase_rates(
    model: Any,
    contact: Any,
    traj: Any,
    dt_s: float,
    sensor: Any,
    repeats: int,
    options: dict[str, Any],
) -> dict[str, float]:
    """Real-time factors (best of ``repeats``) of the benchmark figures.

    The figures are free-flight, whisking-in-air and contact.
    """
    from vibrissa.whisker.simulate import free_vibration, simulate

    free_s = STANDARD["duration_s"]
    # the released shape, solved once (untimed)
    x0 = free_vibration(model, 10.0, dt_s, dt_s, record_every=1).states_m[0]
    whisk = whisk_in_air(free_s)
    best = {"free_flight": math.inf, "whisking": math.inf, "contact": math.inf}
    for _ in range(repeats):
        gc.collect()
        w0 = time.perf_counter()
        free = simulate(model, None, None, free_s, dt_s, initial_positions_m=x0, **options)
        free.hall_volts(sensor=sensor)
        best["free_flight"] = min(best["free_flight"], time.perf_counter() - w0)
        w0 = time.perf_counter()
        air = simulate(model, None, None, free_s, dt_s, base_motion=whisk, **options)
        air.hall_volts(sensor=sensor)
        best["whisking"] = min(best["whisking"], time.perf_counter() - w0)
        w0 = time.perf_counter()
        _trial(model, contact, traj, CONTACT_PHASE_S, dt_s, sensor, **options)
        best["contact"] = min(best["contact"], time.perf_counter() - w0)
    return {
        "free_flight": free_s / best["free_flight"],
        "whisking": free_s / best["whisking"],
        "contact": CONTACT_PHASE_S / best["contact"],
    }


def _single_thread_blas() -> Any:
    """Context limiting BLAS/OpenMP pools to one thread (a no-op without threadpoolctl)."""
    import contextlib

    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl is a scikit-learn dependency
        return contextlib.nullcontext()
    return threadpool_limits(limits=1)


def physics_benchmark(
    dt_s: float = STANDARD["dt_s"],
    n_elements: int | None = None,
    duration_s: float = STANDARD["duration_s"],
    repeats: int = 5,
    measure_memory: bool = True,
    speedups: bool = True,
) -> dict[str, Any]:
    """Time the standard pole-contact trial and return its real-time factor.

    A short warm-up trial first (loads or compiles the numba kernels and fills the
    Hall calibration cache), then ``repeats`` timed trials of
    ``simulate(...)`` + ``hall_volts(...)`` at 4 kHz; the best is kept. The Hall
    sensor (:class:`~vibrissa.whisker.hall.HallSettings` at 4 kHz) is calibrated
    for the same element count before timing. The model is built (and its damping
    solved) before timing. BLAS pools are limited to one thread; the numba kernels
    are serial.

    Parameters
    ----------
    dt_s : float
        Internal time step (s); must divide the 0.25 ms sample period
        (:func:`~vibrissa.whisker.hall.steps_per_sample`).
    n_elements : int, optional
        Elements along the shaft, 4-400 (default the model's default).
    duration_s : float
        Simulated time (s), 0.01-60; the standard is 1.5 s (shorter runs truncate
        the scenario, e.g. for quick tests).
    repeats : int
        Timed trials, 1-100; the fastest counts.
    measure_memory : bool
        Also run one trial under :mod:`tracemalloc` (not timed).
    speedups : bool
        Simulate as :func:`~vibrissa.whisker.simulate.simulate` does by default
        (linear free flight, long steps while the contact is steady); False
        integrates every step of ``dt_s`` with the nonlinear rod, as before
        those existed, for a before/after comparison on the same machine.

    Returns
    -------
    dict
        ``real_time_factor``, ``free_flight_real_time_factor``,
        ``whisking_in_air_real_time_factor`` (:data:`WHISKING_SCENARIO`) and
        ``contact_real_time_factor`` (best of ``repeats`` each; see
        :data:`FREE_FLIGHT_SCENARIO` and :data:`CONTACT_SCENARIO`),
        ``linear_free_flight_fraction`` (of the standard trial's steps),
        ``scenario`` and its parameters, ``wall_seconds``
        (best), ``wall_seconds_all``, ``cpu_seconds`` (process CPU time of the best
        trial: about equal to wall time on one core), ``peak_memory_mb`` and
        ``peak_memory_method``, ``process_max_rss_mb``, ``n_steps``,
        ``n_samples``, ``warmup_seconds``, ``model_build_seconds``,
        ``peak_follicle_moment_nm``, ``peak_hall_x_v``, ``hall_gain_v_per_tan``,
        ``hall_gain_n_elements`` and platform information.
    """
    from vibrissa.whisker.geometry import preset
    from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS, RodModel
    from vibrissa.whisker.simulate import PoleContact

    dt = float(dt_s)
    steps_per_sample(dt, STANDARD["sample_rate_hz"])
    T = in_range("duration_s", duration_s, 0.01, 60.0, "s")
    if isinstance(repeats, bool) or not 1 <= int(repeats) <= 100:
        raise ValueError(f"repeats must lie in [1, 100], got {repeats}")
    n_el = DEFAULT_N_ELEMENTS if n_elements is None else n_elements
    if not 4 <= n_el <= 400:
        raise ValueError(f"n_elements must lie in [4, 400], got {n_el}")

    t0 = time.perf_counter()
    model = RodModel(preset(STANDARD["preset"]), n_el)
    _ = model.damping, model.natural_frequencies_hz
    build_s = time.perf_counter() - t0
    sensor = HallSettings(sample_rate_hz=STANDARD["sample_rate_hz"]).calibrate(
        model.geometry, model.n_elements
    )
    contact = PoleContact(radius_mm=STANDARD["pole_radius_mm"], friction=STANDARD["friction"])
    traj = standard_trajectory(model, max(T, STANDARD["duration_s"]))
    opts: dict[str, Any] = {} if speedups else {"linear_free_flight": False, "max_stride": 1}

    with _single_thread_blas():
        t0 = time.perf_counter()
        _trial(model, contact, traj, min(T, 0.05), dt, sensor, **opts)  # warm-up (touches)
        warmup_s = time.perf_counter() - t0
        walls: list[float] = []
        cpus: list[float] = []
        res = volts = None
        for _ in range(int(repeats)):
            gc.collect()
            c0, w0 = time.process_time(), time.perf_counter()
            res, volts = _trial(model, contact, traj, T, dt, sensor, **opts)
            walls.append(time.perf_counter() - w0)
            cpus.append(time.process_time() - c0)
        peak_mb: float | None = None
        if measure_memory:
            gc.collect()
            tracemalloc.start()
            base, _ = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            _trial(model, contact, traj, T, dt, sensor, **opts)
            _, peak = tracemalloc.get_traced_memory()
            tracemalloc.stop()
            peak_mb = (peak - base) / 2**20
    phases = _phase_rates(model, contact, traj, dt, sensor, int(repeats), opts)
    best = int(np.argmin(walls))
    n_steps = int(res.time_s.size - 1)
    simulated = n_steps * dt
    rss_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {
        "real_time_factor": simulated / walls[best],
        "free_flight_real_time_factor": phases["free_flight"],
        "whisking_in_air_real_time_factor": phases["whisking"],
        "whisking_in_air_scenario": WHISKING_SCENARIO,
        "contact_real_time_factor": phases["contact"],
        "free_flight_scenario": FREE_FLIGHT_SCENARIO,
        "contact_scenario": CONTACT_SCENARIO,
        "linear_free_flight_fraction": float(np.mean(res.newton_iterations == 0)),
        "speedups": bool(speedups),
        "scenario": SCENARIO,
        "preset": STANDARD["preset"],
        "radial_distance_mm": STANDARD["radial_distance_mm"],
        "speed_mm_s": STANDARD["speed_mm_s"],
        "retract_speed_mm_s": STANDARD["retract_speed_mm_s"],
        "retract_distance_mm": STANDARD["retract_distance_mm"],
        "pole_radius_mm": STANDARD["pole_radius_mm"],
        "friction": STANDARD["friction"],
        "dt_s": dt,
        "n_elements": model.n_elements,
        "duration_s": simulated,
        "sample_rate_hz": STANDARD["sample_rate_hz"],
        "wall_seconds": walls[best],
        "wall_seconds_all": walls,
        "cpu_seconds": cpus[best],
        "repeats": int(repeats),
        "peak_memory_mb": peak_mb,
        "peak_memory_method": MEMORY_METHOD if measure_memory else None,
        "process_max_rss_mb": rss_kb / 1024.0,
        "n_steps": n_steps,
        "n_samples": int(volts.shape[0]),
        "warmup_seconds": warmup_s,
        "model_build_seconds": build_s,
        "peak_follicle_moment_nm": float(np.max(np.abs(res.follicle_moment_nm[:, 0]))),
        "peak_hall_x_v": float(np.max(volts[:, 0])),
        "hall_gain_v_per_tan": sensor.gain_v,
        "hall_gain_n_elements": model.n_elements,
        "python": platform.python_version(),
        "machine": platform.machine(),
        "cpu_count": os.cpu_count(),
    }
