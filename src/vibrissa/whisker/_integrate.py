"""Numba solvers: static equilibrium (Newton) and implicit dynamics (generalised-alpha).

Time integration uses the generalised-alpha method of Chung & Hulbert (1993) with
all forces evaluated at the intermediate state ``x_{n+1-alpha_f}``; with spectral
radius ``rho_inf < 1`` it is unconditionally stable for linear systems, second-order
accurate, practically free of numerical damping at the whisker's bending
frequencies and strongly dissipative at the (irrelevant) axial frequencies of the
stiff stretching springs. Each step is solved by Newton's method on the banded
tangent matrix.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vibrissa.whisker._kernels import (
    BW,
    PLANE,
    POLE,
    add_internal,
    add_plane,
    add_pole,
    band_solve,
)


@njit(cache=True)
def _assemble(x, v, free, kb, kf, axis, L0, EA, mass, alpha_d, beta_d, radius, s_rest,
              kind, cpar, tr, frame, H, du, dw, first_node, pole_anchor, plane_anchors,
              F, S, cD, cK, jac, info):
    F[:, :] = 0.0
    if jac:
        S[:, :] = 0.0
    add_internal(x, v, kb, kf, axis, L0, EA, mass, alpha_d, beta_d, F, S, cD, cK, jac)
    if kind == POLE:
        add_pole(x, v, radius, s_rest, tr[0:2], np.array([tr[2], 0.0, tr[3]]), cpar[0],
                 cpar[1], cpar[2], cpar[3], cpar[4], pole_anchor, F, S, cD, cK, jac, info)
    elif kind == PLANE:
        add_plane(x, v, radius, tr[0:3], tr[3:6], frame[0], frame[1], frame[2], H, du, dw,
                  cpar[1], cpar[2], cpar[3], cpar[4], plane_anchors, F, S, cD, cK, jac, info,
                  first_node)


@njit(cache=True)
def _fix_rows(S, R, free):
    n = free.shape[0]
    for i in range(n):
        if not free[i]:
            for c in range(3):
                row = 3 * i + c
                S[row, :] = 0.0
                S[row, BW] = 1.0
                R[row] = 0.0


@njit(cache=True)
def _commit_anchors(kind, info, pole_anchor, plane_anchors):
    if kind == POLE:
        if info[6] > 0.0:
            pole_anchor[0] = info[4]
            pole_anchor[1] = info[5]
            pole_anchor[2] = 1.0
        else:
            pole_anchor[2] = 0.0
    elif kind == PLANE:
        for i in range(plane_anchors.shape[0]):
            if plane_anchors[i, 5] > 0.0:
                plane_anchors[i, 0] = plane_anchors[i, 3]
                plane_anchors[i, 1] = plane_anchors[i, 4]
                plane_anchors[i, 2] = 1.0
            else:
                plane_anchors[i, 2] = 0.0


@njit(cache=True)
def solve_static(x, free, kb, kf, axis, L0, EA, mass, radius, s_rest, kind, cpar, tr, frame,
                 H, du, dw, first_node, pole_anchor, plane_anchors, f_app, tol, max_iter, info):
    """Newton iterations for ``F_internal(x) + F_contact(x) + f_app = 0`` from ``x``.

    Returns the number of iterations used, or -1 if it did not converge.
    """
    n = x.shape[0]
    v = np.zeros_like(x)
    F = np.zeros_like(x)
    S = np.zeros((3 * n, 2 * BW + 1))
    R = np.zeros(3 * n)
    for it in range(max_iter):
        _assemble(x, v, free, kb, kf, axis, L0, EA, mass, 0.0, 0.0, radius, s_rest, kind, cpar,
                  tr, frame, H, du, dw, first_node, pole_anchor, plane_anchors, F, S, 0.0, 1.0,
                  True, info)
        for i in range(n):
            for c in range(3):
                R[3 * i + c] = F[i, c] + f_app[i, c]
        _fix_rows(S, R, free)
        if not band_solve(S, R):
            return -1
        # limit the step to keep Newton inside its basin on strongly nonlinear problems
        mx = 0.0
        for k in range(3 * n):
            if abs(R[k]) > mx:
                mx = abs(R[k])
        scale = 1.0
        lim = 0.2 * L0[1]
        if mx > lim:
            scale = lim / mx
        for i in range(n):
            for c in range(3):
                x[i, c] += scale * R[3 * i + c]
        if mx * scale < tol and scale == 1.0:
            return it + 1
    return -1


@njit(cache=True)
def run_dynamics(x, v, a, free, kb, kf, axis, L0, EA, mass, alpha_d, beta_d, radius, s_rest,
                 kind, cpar, traj, frame, H, du, dw, first_node, pole_anchor, plane_anchors,
                 dt, rho_inf, tol, max_iter, out, states, state_every):
    """Integrate ``len(traj) - 1`` steps of size ``dt`` from (x, v, a) in place.

    ``traj[k]`` is the contact object's state at step k (pole: x, z, vx, vz; plane:
    origin xyz, velocity xyz). ``out[k]`` receives per-step outputs
    [tan_x, tan_y of the magnet, contact normal force (N), contact arc length (m),
    slipping, contact force x, contact force z, Newton iterations]. Every
    ``state_every`` steps (if > 0) the positions are stored in ``states``.

    Returns the number of completed steps (less than requested if a step failed).
    """
    n = x.shape[0]
    nsteps = traj.shape[0] - 1
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gam = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    cM = (1.0 - am) / (beta * dt * dt)
    cD = (1.0 - af) * gam / (beta * dt)
    cK = 1.0 - af
    F = np.zeros_like(x)
    S = np.zeros((3 * n, 2 * BW + 1))
    R = np.zeros(3 * n)
    xn = x.copy()
    vn = v.copy()
    an = a.copy()
    xa = np.zeros_like(x)
    va = np.zeros_like(x)
    info = np.zeros(9)
    tr = np.zeros(traj.shape[1])

    out[0, 0] = (x[1, 0] - x[0, 0]) / (x[1, 2] - x[0, 2])
    out[0, 1] = (x[1, 1] - x[0, 1]) / (x[1, 2] - x[0, 2])
    out[0, 2:] = 0.0
    si = 0
    if state_every > 0:
        states[0] = x
        si = 1
    for k in range(nsteps):
        for c in range(traj.shape[1]):
            tr[c] = (1.0 - af) * traj[k + 1, c] + af * traj[k, c]
        # predictor: constant acceleration
        for i in range(n):
            if free[i]:
                for c in range(3):
                    x[i, c] = xn[i, c] + dt * vn[i, c] + 0.5 * dt * dt * an[i, c]
        converged = False
        it = 0
        for it in range(max_iter):
            for i in range(n):
                for c in range(3):
                    anew = (x[i, c] - xn[i, c] - dt * vn[i, c]
                            - dt * dt * (0.5 - beta) * an[i, c]) / (beta * dt * dt)
                    vnew = vn[i, c] + dt * ((1.0 - gam) * an[i, c] + gam * anew)
                    if not free[i]:
                        anew = 0.0
                        vnew = 0.0
                    a[i, c] = anew
                    v[i, c] = vnew
                    xa[i, c] = (1.0 - af) * x[i, c] + af * xn[i, c]
                    va[i, c] = (1.0 - af) * vnew + af * vn[i, c]
            _assemble(xa, va, free, kb, kf, axis, L0, EA, mass, alpha_d, beta_d, radius, s_rest,
                      kind, cpar, tr, frame, H, du, dw, first_node, pole_anchor, plane_anchors,
                      F, S, cD, cK, True, info)
            for i in range(n):
                m = mass[i]
                for c in range(3):
                    R[3 * i + c] = F[i, c] - m * ((1.0 - am) * a[i, c] + am * an[i, c])
                    S[3 * i + c, BW] += cM * m
            _fix_rows(S, R, free)
            if not band_solve(S, R):
                return k
            mx = 0.0
            for i in range(n):
                for c in range(3):
                    d = R[3 * i + c]
                    x[i, c] += d
                    if abs(d) > mx:
                        mx = abs(d)
            if not np.isfinite(mx):
                return k
            if mx < tol:
                converged = True
                break
        if not converged:
            return k
        # final consistent velocity/acceleration for the converged positions
        for i in range(n):
            for c in range(3):
                if free[i]:
                    anew = (x[i, c] - xn[i, c] - dt * vn[i, c]
                            - dt * dt * (0.5 - beta) * an[i, c]) / (beta * dt * dt)
                    a[i, c] = anew
                    v[i, c] = vn[i, c] + dt * ((1.0 - gam) * an[i, c] + gam * anew)
        _commit_anchors(kind, info, pole_anchor, plane_anchors)
        xn[:, :] = x
        vn[:, :] = v
        an[:, :] = a
        out[k + 1, 0] = (x[1, 0] - x[0, 0]) / (x[1, 2] - x[0, 2])
        out[k + 1, 1] = (x[1, 1] - x[0, 1]) / (x[1, 2] - x[0, 2])
        out[k + 1, 2] = info[0]
        out[k + 1, 3] = info[1]
        out[k + 1, 4] = info[2]
        if kind == POLE:
            out[k + 1, 5] = info[7]
            out[k + 1, 6] = info[8]
        else:
            out[k + 1, 5] = info[4]
            out[k + 1, 6] = info[5]
        out[k + 1, 7] = it + 1
        if state_every > 0 and (k + 1) % state_every == 0 and si < states.shape[0]:
            states[si] = x
            si += 1
    return nsteps
