"""Point-to-point motion of one axis of a Cartesian robot: the MI approach and retraction.

A servo controller such as the Yamaha RCX222 of the thesis' XY robot (3.3) moves an
axis along a velocity profile limited in speed, acceleration and (when set) jerk:

* **Trapezoid** (``jerk_mm_s3 = inf``): constant acceleration ``a`` up to the speed
  limit, cruise, constant deceleration ``a`` to a stop at the target. A short move
  never reaches the limit and is a triangle.
* **S-curve** (finite jerk ``j``): the trapezoid's velocity convolved with a box of
  width ``T_j = a / j``. Each step of the acceleration between 0 and +/-``a`` becomes a
  linear ramp over ``T_j`` (slope exactly ``j``; where two changes lie closer than
  ``T_j``, e.g. a short move reversing its acceleration from ``-a`` to ``+a``, the
  ramps overlap and the slope reaches ``2 j``), the
  move lasts ``T_j`` longer, and the end point is the same (the convolution keeps
  the area under the velocity).

:func:`mi_axis_motion` is the XY robot's minimal-impingement move along its axis:
advance at the approach speed until the controller's retract command, then one
move to the retract target: brake, reverse, and stop exactly there (3.3.2: "the
robot retracts the object as fast as possible (720 mm/s)").
"""

from __future__ import annotations

import math

import numpy as np

from vibrissa._validate import finite, positive

__all__ = ["mi_axis_motion", "trapezoid_breakpoints"]


def trapezoid_breakpoints(
    v0_mm_s: float, distance_mm: float, v_max_mm_s: float, acc_mm_s2: float
) -> tuple[np.ndarray, np.ndarray]:
    """Breakpoints of the time-optimal trapezoid from speed ``v0`` to rest ``distance`` back.

    The axis moves at ``v0_mm_s`` (>= 0, forwards) when the move starts; it must come
    to rest ``distance_mm`` behind where it was (a negative displacement), never
    exceeding ``v_max_mm_s`` backwards nor ``acc_mm_s2`` in magnitude. It brakes at
    ``-a`` through zero to the backward cruise speed (or to the triangle's peak when
    the move is short), cruises, and brakes at ``+a`` to rest at the target.

    Parameters
    ----------
    v0_mm_s
        Forward speed at the start of the move (mm/s, >= 0).
    distance_mm
        How far behind the start point the axis stops (mm, >= 0).
    v_max_mm_s
        Speed limit of the backward move (mm/s, > 0).
    acc_mm_s2
        Acceleration limit (mm/s^2, > 0).

    Returns
    -------
    times_s, velocities_mm_s : ndarray
        Times from the start of the move and the velocity there; velocity is linear
        between breakpoints and zero after the last.
    """
    v0 = finite("v0_mm_s", v0_mm_s)
    if v0 < 0:
        raise ValueError(f"v0_mm_s must be >= 0, got {v0!r}")
    d = finite("distance_mm", distance_mm)
    if d < 0:
        raise ValueError(f"distance_mm must be >= 0, got {d!r}")
    vm = positive("v_max_mm_s", v_max_mm_s)
    a = positive("acc_mm_s2", acc_mm_s2)
    t_stop = v0 / a
    back = d + v0 * v0 / (2 * a)  # distance from the turning point to the target
    if back >= vm * vm / a:  # reaches the limit: trapezoid
        t_up = vm / a
        t_cruise = (back - vm * vm / a) / vm
        peak = vm
    else:  # triangle
        t_up = math.sqrt(back / a)
        t_cruise = 0.0
        peak = a * t_up
    t = np.array(
        [0.0, t_stop, t_stop + t_up, t_stop + t_up + t_cruise, t_stop + 2 * t_up + t_cruise]
    )
    v = np.array([v0, 0.0, -peak, -peak, 0.0])
    return t, v


def mi_axis_motion(
    time_s: np.ndarray,
    approach_mm_s: float,
    t_retract_s: float,
    retract_mm_s: float,
    acc_mm_s2: float,
    jerk_mm_s3: float,
    x_start_mm: float,
    x_end_mm: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity of the MI move sampled at ``time_s``.

    The axis starts at ``x_start_mm`` moving at ``approach_mm_s`` (it reached that
    speed before ``t = 0``), keeps it until ``t_retract_s``, then makes one
    time-optimal move (:func:`trapezoid_breakpoints`, S-curved when ``jerk_mm_s3`` is
    finite) to rest at ``x_end_mm``.

    Parameters
    ----------
    time_s
        Increasing, uniformly spaced sample times starting at 0 (s).
    approach_mm_s
        Approach speed (mm/s, > 0).
    t_retract_s
        When the retract command takes effect (s, >= 0).
    retract_mm_s
        Retraction speed limit (mm/s).
    acc_mm_s2
        Acceleration limit (mm/s^2).
    jerk_mm_s3
        Jerk limit (mm/s^3); ``inf`` for a trapezoid.
    x_start_mm
        Position at ``t = 0`` (mm).
    x_end_mm
        Where the retraction stops (mm); must not lie ahead of the turning point.

    Returns
    -------
    position_mm, velocity_mm_s : ndarray
        Same shape as ``time_s``.
    """
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1 or t.size < 2 or t[0] != 0.0:
        raise ValueError("time_s must be a 1-D grid of at least 2 samples starting at 0")
    dt = float(t[1] - t[0])
    v = positive("approach_mm_s", approach_mm_s)
    a = positive("acc_mm_s2", acc_mm_s2)
    j = float(jerk_mm_s3)
    if not j > 0:
        raise ValueError(f"jerk_mm_s3 must be > 0 (inf for none), got {jerk_mm_s3!r}")
    t_rev = max(0.0, float(t_retract_s))
    x_rev = x_start_mm + v * t_rev
    width = max(1, int(round(a / j / dt))) if math.isfinite(j) else 1
    # the causal smoothing delays the braking by half its window on average, carrying
    # the axis v * T_j / 2 further: the trapezoid aims that much short of the target
    carry = v * (width - 1) * dt / 2
    bt, bv = trapezoid_breakpoints(v, x_rev + carry - x_end_mm, retract_mm_s, a)
    vel = np.where(t <= t_rev, v, np.interp(t - t_rev, bt, bv, right=0.0))
    if width > 1:
        # a causal box average: the S-curve starts at t_rev and ends T_j later
        padded = np.concatenate([np.full(width - 1, v), vel])
        c = np.cumsum(np.concatenate([[0.0], padded]))
        vel = (c[width:] - c[:-width]) / width
    x = x_start_mm + np.concatenate([[0.0], np.cumsum(0.5 * (vel[1:] + vel[:-1]) * dt)])
    return x, vel
