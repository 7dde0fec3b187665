"""Compiled closed loops of the whisking robots (issue 32, item 3).

:func:`rcp_loop` runs the whole RCP loop of :func:`vibrissa.robots.whisking.run_whisking`
inside one compiled call: per control period, each side's command (the oscillator
suppressed by the gating variable ``z`` and scaled by the contact-induced asymmetry),
its servo, every whisker's rod for the period (the integrator of
:mod:`vibrissa.whisker.simulate`, the whisker's state carried over), then each side's
contact filter (eq. 3.2) and gate (eq. 3.3). The arithmetic is that of the loop in
Python, operation for operation, so the two give the same numbers bit for bit; what
goes is the per-period cost of calling the integrator from Python for every whisker
(argument checks, interpolation, the dispatcher's typing of about forty arrays).

The whiskers' kernel inputs come as tuples of one type each (one rod discretisation
kind, one contact kind), which a compiled loop can index at run time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit, typeof

from vibrissa.whisker.simulate import TR_BASE, run_dynamics

__all__ = ["DEG", "rcp_loop", "same_kernel_type"]

#: Degrees to radians, as ``numpy.radians`` multiplies.
DEG = np.pi / 180.0


def same_kernel_type(items: tuple[Any, ...]) -> bool:
    """Whether ``items`` are all of one compiled type (a tuple a kernel can index)."""
    return len({typeof(x) for x in items}) == 1


@njit(cache=True, nogil=True)
def rcp_loop(
    states,
    anchors,
    rods,
    dampings,
    contacts,
    settings,
    objects,
    side_of,
    osc,
    osc_ctrl,
    retracted,
    servo,
    motors,
    sos,
    filters,
    full_tan,
    decays,
    sigma_z,
    cia_gain,
    signal_scale,
    spp,
    tan_x,
    tan_y,
    force,
    angle,
    command,
    pis,
    zs,
    defl,
    failure,
):
    """Run every control period of an RCP loop; return the periods completed.

    Parameters
    ----------
    states, anchors, rods, dampings, contacts : tuple
        Per whisker, the integrator's bundles (:class:`~vibrissa.whisker.simulate.
        StepperKernelInputs`); ``states`` and ``anchors`` advance in place.
    settings : SolverSettings
        The integrator's settings (one for all whiskers).
    objects : ndarray, shape (n_whiskers, 6)
        Each whisker's still object (zeros without one).
    side_of : ndarray of int, shape (n_whiskers,)
        The side each whisker belongs to.
    osc : ndarray, shape (n_sides, n_steps + 1)
        Each side's oscillator (deg) at every integration step.
    osc_ctrl : ndarray, shape (n_sides, n_periods + 1)
        Each side's oscillator (deg) at the control samples.
    retracted : ndarray, shape (n_sides,)
        Each side's full retraction (deg).
    servo : ndarray, shape (4,)
        The servo's exact step matrix ``p11, p12, p21, p22``
        (:func:`vibrissa.robots.whisking.motor_follow`).
    motors : ndarray, shape (n_sides, 2)
        Each servo's angle (deg) and rate (deg/s); advanced in place.
    sos : ndarray, shape (n_sections, 5)
        The contact filter's sections ``b0, b1, b2, a1, a2``.
    filters : ndarray, shape (n_whiskers, n_sections, 2)
        Each whisker's filter state; advanced in place.
    full_tan, decays : ndarray
        Each whisker's full-scale tangent; each side's per-period decay of ``z``.
    sigma_z, cia_gain, signal_scale : float
        RCP's gain, the contact-induced asymmetry's gain, the contact signal's scale.
    spp : int
        Integration steps per control period.
    tan_x, tan_y, force, angle : ndarray, shape (n_whiskers, n_steps + 1)
        Outputs at every step (``angle`` in deg); column 0 is the start.
    command, pis, zs : ndarray, shape (n_sides, n_periods + 1)
        Outputs at the control samples; column 0 is the start.
    defl : ndarray, shape (n_whiskers, n_periods + 1)
        Normalised deflection at the control samples.
    failure : ndarray of int, shape (3,)
        On a failed step: the period, the whisker and the steps it completed.

    Returns
    -------
    int
        Periods completed (all of them unless a step failed).
    """
    n_w = side_of.shape[0]
    n_sides = retracted.shape[0]
    n_periods = osc_ctrl.shape[1] - 1
    p11, p12, p21, p22 = servo[0], servo[1], servo[2], servo[3]
    traj = np.empty((spp + 1, 8))
    out = np.zeros((spp + 1, 8))
    records = np.zeros((1, 2, 1, 3))
    status = np.zeros(1, dtype=np.int64)
    ang = np.empty(spp + 1)
    rate = np.empty(spp + 1)
    for n in range(n_periods):
        k0 = n * spp
        for s in range(n_sides):
            others = False
            top = 0.0
            for o in range(n_sides):
                if o != s and (not others or zs[o, n] > top):
                    top = zs[o, n]
                    others = True
            gain = 1.0 + cia_gain * (top if others else 0.0)
            z = zs[s, n]
            ret = retracted[s]
            a = motors[s, 0]
            r = motors[s, 1]
            ang[0] = a
            rate[0] = r
            for k in range(spp):
                u = ret + (1.0 - z) * gain * (osc[s, k0 + k] - ret)
                a, r = u + p11 * (a - u) + p12 * r, p21 * (a - u) + p22 * r
                ang[k + 1] = a
                rate[k + 1] = r
            motors[s, 0] = a
            motors[s, 1] = r
            command[s, n + 1] = ret + (1.0 - z) * gain * (osc_ctrl[s, n + 1] - ret)
            for w in range(n_w):
                if side_of[w] != s:
                    continue
                for k in range(spp + 1):
                    traj[k, :6] = objects[w]
                    traj[k, TR_BASE] = ang[k] * DEG
                    traj[k, TR_BASE + 1] = rate[k] * DEG
                out[:] = 0.0
                done = run_dynamics(
                    states[w],
                    anchors[w],
                    rods[w],
                    dampings[w],
                    contacts[w],
                    traj,
                    settings,
                    out,
                    records,
                    status,
                )
                ok = status[0] >= 0 and done == spp
                for k in range(done + 1):
                    for c in range(8):
                        if c != 3 and not np.isfinite(out[k, c]):
                            ok = False
                if not ok:
                    failure[0] = n
                    failure[1] = w
                    failure[2] = done
                    return n
                for k in range(spp + 1):
                    tan_x[w, k0 + k] = out[k, 0]
                    tan_y[w, k0 + k] = out[k, 1]
                    force[w, k0 + k] = out[k, 2]
                    angle[w, k0 + k] = ang[k]
        for w in range(n_w):
            defl[w, n + 1] = tan_x[w, k0 + spp] / full_tan[w]
        for s in range(n_sides):
            best = 0.0
            for w in range(n_w):
                if side_of[w] != s:
                    continue
                y = defl[w, n + 1]
                for j in range(sos.shape[0]):
                    x_in = y
                    y = sos[j, 0] * x_in + filters[w, j, 0]
                    filters[w, j, 0] = sos[j, 1] * x_in - sos[j, 3] * y + filters[w, j, 1]
                    filters[w, j, 1] = sos[j, 2] * x_in - sos[j, 4] * y
                best = max(best, abs(y))
            pis[s, n + 1] = signal_scale * best
            zs[s, n + 1] = min(max(max(decays[s] * zs[s, n], sigma_z * pis[s, n + 1]), 0.0), 1.0)
    return n_periods
