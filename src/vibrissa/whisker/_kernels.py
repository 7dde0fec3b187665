"""Numba kernels of the discrete elastic rod: forces, tangent matrices, contacts, solvers.

The whisker is a chain of nodes ``x[0..n-1]`` (shape ``(n, 3)``, metres):

* node 0 is the follicle pivot (always fixed);
* edge 0 (node 0 -> node 1) is the rigid shaft inside the follicle, carrying the
  magnet; its direction is the magnet's direction;
* nodes 1..n-1 are the free shaft from the base (node 1) to the tip (node n-1).

Energies (all isotropic in the two bending planes):

* stretching of edge ``e``: ``EA/(2 L0) (|e| - L0)^2`` (a stiff penalty keeping the
  rod practically inextensible);
* bending at node ``i``: ``k_i |t_i - t_{i-1}|^2`` with unit edge tangents ``t``;
  ``|t_i - t_{i-1}|^2 = 2 (1 - cos phi)`` for turning angle ``phi``, so
  ``k_i = E I_i / (2 lbar_i)`` recovers ``E I kappa^2 / 2`` per length;
* the follicle: ``k_f/2 |t_0 - a|^2 = k_f (1 - cos psi)`` about the rest axis ``a``,
  a rotational spring whose restoring moment is ``k_f sin psi``.

Dissipation is Rayleigh damping: ``alpha M v`` plus ``beta`` times the positive
semi-definite strain-rate part of the stiffness (Gauss-Newton bending terms and
axial terms), which is objective (no damping of rigid rotations) and passive.

Everything here is allocation-light numba code; the Python wrappers live in
:mod:`vibrissa.whisker.rod` and :mod:`vibrissa.whisker.simulate`.

Why every kernel lives in this one module
-----------------------------------------
The kernels are compiled with ``@njit(cache=True)``. Numba's on-disk cache
validates an entry only against the source file of the function it compiled
(its modification time and size), not against the files of the functions it
calls, which are compiled into the same machine code. If a kernel here called a
kernel defined in another file, editing only that other file would leave the
caller's cache entry looking valid, and the stale machine code (with the old
callee compiled in) would be loaded silently. With all kernels in one file, any
edit invalidates them all together. Keep it that way: do not split this module
and do not call numba functions from other modules here.

Argument bundles
----------------
The solvers take their inputs as a few immutable :class:`typing.NamedTuple`
bundles, built once on the Python side, instead of 30-odd positional arguments:

* :class:`RodArrays` -- the discretised rod (:meth:`RodModel.rod_arrays
  <vibrissa.whisker.rod.RodModel.rod_arrays>`);
* :class:`Damping` -- the Rayleigh and follicle damping coefficients;
* :class:`ContactSpec` -- which object is touched and its contact parameters;
* :class:`Anchors` -- the friction state (stick anchors), updated in place;
* :class:`NodeState` -- node positions, velocities, accelerations, updated in place;
* :class:`SolverSettings` -- time step and Newton/generalised-alpha controls.

Numba compiles a named tuple of arrays and scalars as a plain struct passed by
value (no reflected lists, no object mode); the arrays inside stay mutable.
Give the fields the dtypes documented (float64 arrays, a bool ``free`` mask,
Python/NumPy floats and ints for scalars): a different dtype or memory layout
compiles, and caches, a separate specialisation.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numba import njit, typeof

BW = 8  # half bandwidth of the tangent matrices (3 DOF per node, 3-node stencil)
assert BW == 8, "band_backsolve spells out a half bandwidth of eight"
STEADY_STEPS = 8  # steps of unchanged contact state before long steps are tried
#: A Newton update of a dynamic step is cut to this fraction of an element's length.
STEP_CAP_FRACTION = 0.2
#: Halvings of an exact Newton step that raised the residual before it is kept anyway.
MAX_BACKTRACKS = 6
#: Outcomes of a long step (:func:`_try_stride`).
STRIDE_OK = 0
STRIDE_DIVERGED = 1
STRIDE_CONTACT = 2
STRIDE_ERROR = 3
#: A long step is doubled for the next try when the doubled step's error estimate
#: (eight times this one's) would stay within this fraction of the tolerance.
STRIDE_SAFETY = 0.5

#: Newton has converged when its estimated remaining error is below this fraction of
#: the tolerance (see :func:`_ga_step`).
NEWTON_KAPPA = 0.3
#: From the second iteration on, a reused factorisation is replaced as soon as two
#: successive updates shrank by less than this factor.
THETA_REFACTOR = 0.3

#: Column of a trajectory row (``traj[k]``, ``tr``) holding the follicle housing's
#: whisk angle (rad); the next column holds its rate (rad/s). Rows of only
#: ``TR_BASE`` columns mean a housing at rest.
TR_BASE = 6

# contact kinds
NO_CONTACT = 0
POLE = 1
PLANE = 2


class RodArrays(NamedTuple):
    """The discretised rod, as the kernels read it (``n`` nodes, ``n - 1`` edges).

    Attributes
    ----------
    free : ndarray of bool, shape (n,)
        Whether each node moves (node 0, the pivot, never does).
    kb : ndarray, shape (n,)
        Bending constant at each node (N m); ``kb[0]`` and ``kb[n - 1]`` are unused.
    kf : float
        Rotational stiffness of the follicle (N m/rad).
    axis : ndarray, shape (3,)
        Rest direction of the follicle (unit vector).
    L0 : ndarray, shape (n - 1,)
        Rest lengths of the edges (m).
    EA : ndarray, shape (n - 1,)
        Axial rigidities of the edges (N).
    mass : ndarray, shape (n,)
        Diagonal of the node mass matrix (kg).
    mass_off : ndarray, shape (n - 1,)
        Mass coupling of nodes ``i`` and ``i + 1`` (kg): the off-diagonal of the
        tridiagonal consistent mass matrix; zeros for a lumped mass.
    radius : ndarray, shape (n,)
        Shaft radius at each node (m).
    s_rest : ndarray, shape (n,)
        Arc length of each node from the base at rest (m); negative for the pivot.
    """

    free: np.ndarray
    kb: np.ndarray
    kf: float
    axis: np.ndarray
    L0: np.ndarray
    EA: np.ndarray
    mass: np.ndarray
    mass_off: np.ndarray
    radius: np.ndarray
    s_rest: np.ndarray


class Damping(NamedTuple):
    """Damping coefficients (see :func:`add_internal`).

    Attributes
    ----------
    alpha : float
        Mass-proportional damping (1/s).
    beta_shaft : float
        Stiffness-proportional material damping of the shaft (s).
    beta_follicle : float
        The follicle's rubber damper: damping moment ``k_f beta_follicle dpsi/dt`` (s).
    """

    alpha: float
    beta_shaft: float
    beta_follicle: float


class ContactSpec(NamedTuple):
    """What the whisker touches; constant over a simulation.

    Attributes
    ----------
    kind : int
        :data:`NO_CONTACT`, :data:`POLE` or :data:`PLANE`.
    params : ndarray, shape (5,)
        Pole radius (m; 0 for a plane), normal penalty stiffness (N/m), approach
        damping (N s/m), Coulomb friction coefficient, presliding distance (m).
    frame : ndarray, shape (3, 3)
        Plane only: rows are the outward unit normal and the in-plane unit vectors
        ``u`` and ``w``.
    heights : ndarray, shape (nu, nw)
        Plane only: periodic height field (m).
    du, dw : float
        Plane only: grid spacing of ``heights`` along ``u`` and ``w`` (m).
    first_node : int
        Plane only: the first node tested for contact.
    h_max : float
        Plane only: the height field's largest value, ``heights.max()`` (m). The
        surface is a convex combination of the grid values (:func:`_height`), so no
        point of it is higher: nodes farther than this from the plane are out of
        contact without evaluating the surface under them. ``inf`` (the default)
        evaluates it under every node.
    """

    kind: int
    params: np.ndarray
    frame: np.ndarray
    heights: np.ndarray
    du: float
    dw: float
    first_node: int
    h_max: float = np.inf


class Anchors(NamedTuple):
    """Friction state carried between steps (updated in place).

    Attributes
    ----------
    pole : ndarray, shape (5,)
        Pole contact: stick anchor arc length (m), anchor ``y`` in the pole's frame
        (m), valid flag, contact angle on the pole (rad), side of the pole the shaft
        was on when last out of contact (see :func:`add_pole`).
    plane : ndarray, shape (n_nodes, 6)
        Plane contact, per node: anchor ``(U, W, valid)`` and the proposed new anchor
        ``(U, W, valid)`` of the current step (see :func:`add_plane`).
    """

    pole: np.ndarray
    plane: np.ndarray


class NodeState(NamedTuple):
    """Node positions (m), velocities (m/s) and accelerations (m/s^2), each (n, 3).

    Updated in place by the dynamic solver.
    """

    x: np.ndarray
    v: np.ndarray
    a: np.ndarray


class SolverSettings(NamedTuple):
    """Controls of :func:`run_dynamics`.

    Attributes
    ----------
    dt : float
        Time step (s).
    rho_inf : float
        Spectral radius of the generalised-alpha scheme at infinite frequency.
    tol : float
        Newton convergence tolerance on the position update (m).
    max_iter : int
        Newton iterations allowed per step.
    refactor_every : int
        Refresh the factorised iteration matrix at least every that many steps.
    max_halvings : int
        A failed step is retried in up to ``2**max_halvings`` sub-steps.
    record_every : int
        Store positions and velocities every that many steps (0: never).
    stop_tan : float
        Stop after the first step whose |tan_x| reaches this (0: never).
    stop_free : int
        Stop after this many consecutive steps without contact force (0: never): the
        hand-over point to the linear free-flight propagator.
    max_stride : int
        Largest step, in units of ``dt``, taken while the contact state is steady
        (1: fixed steps; see :func:`run_dynamics`).
    stride_tol : float
        Largest local error estimate (m) of an accepted long step.
    """

    dt: float
    rho_inf: float
    tol: float
    max_iter: int
    refactor_every: int
    max_halvings: int
    record_every: int
    stop_tan: float
    stop_free: int
    max_stride: int
    stride_tol: float


class _StepWork(NamedTuple):
    """Scratch arrays of one generalised-alpha step (allocated once per run)."""

    xn: np.ndarray
    vn: np.ndarray
    an: np.ndarray
    xa: np.ndarray
    va: np.ndarray
    F: np.ndarray
    S: np.ndarray
    R: np.ndarray
    info: np.ndarray
    newton: np.ndarray
    dx: np.ndarray
    xb: np.ndarray
    vb: np.ndarray


# ----------------------------------------------------------------------------------
# copies: an explicit loop, not ``dst[:, :] = src``, whose broadcasting check carries
# an error message that numba compiles string formatting for (about 5 s of every cold
# compile; the shapes here always agree)
# ----------------------------------------------------------------------------------
@njit(cache=True)
def _copy1(dst, src):
    """``dst[:] = src`` for two 1-D arrays of the same length."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]


@njit(cache=True)
def _copy2(dst, src):
    """``dst[:, :] = src`` for two 2-D arrays of the same shape."""
    for i in range(dst.shape[0]):
        for j in range(dst.shape[1]):
            dst[i, j] = src[i, j]


# ----------------------------------------------------------------------------------
# banded linear algebra (no pivoting: the iteration matrices are dominated by
# positive-definite stiffness and mass terms)
# ----------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def band_add_block(S, a, b, blk, coef):
    """Add ``coef * blk`` (3x3) to the (node a, node b) block of band matrix ``S``."""
    for r in range(3):
        row = 3 * a + r
        for c in range(3):
            S[row, BW + 3 * b + c - row] += coef * blk[r, c]


@njit(cache=True)
def band_factor(A):
    """LU-factorise band matrix ``A`` in place (no pivoting). False if a pivot vanishes.

    The diagonal receives the *reciprocals* of the pivots, which
    :func:`band_backsolve` expects.
    """
    n = A.shape[0]
    rowk = np.empty(BW + 1)
    for k in range(n):
        piv = A[k, BW]
        if not (abs(piv) > 1e-300) or not np.isfinite(piv):
            return False
        inv = 1.0 / piv
        A[k, BW] = inv
        iend = min(n, k + BW + 1)
        m = iend - k
        # row k's upper band, copied so that the updates below are contiguous,
        # non-aliasing loops
        for jj in range(1, m):
            rowk[jj] = A[k, BW + jj]
        if m == BW + 1:
            # a full band: fixed trip counts, which the compiler unrolls
            for di in range(1, BW + 1):
                i = k + di
                base = BW - di
                lik = A[i, base] * inv
                if lik != 0.0:
                    A[i, base] = lik
                    for jj in range(1, BW + 1):
                        A[i, base + jj] -= lik * rowk[jj]
            continue
        for i in range(k + 1, iend):
            base = BW + k - i
            lik = A[i, base] * inv
            if lik != 0.0:
                A[i, base] = lik
                for jj in range(1, m):
                    A[i, base + jj] -= lik * rowk[jj]
    return True


@njit(cache=True)
def band_backsolve(A, rhs):
    """Solve in place with the factors left in ``A`` by :func:`band_factor`."""
    n = A.shape[0]
    # a row's eight products are summed as a tree, not as a chain of dependent
    # subtractions (whose latency bounded the loop); rows with a full band only
    for i in range(n):
        if i >= BW:
            t0 = A[i, 0] * rhs[i - 8] + A[i, 1] * rhs[i - 7]
            t1 = A[i, 2] * rhs[i - 6] + A[i, 3] * rhs[i - 5]
            t2 = A[i, 4] * rhs[i - 4] + A[i, 5] * rhs[i - 3]
            t3 = A[i, 6] * rhs[i - 2] + A[i, 7] * rhs[i - 1]
            rhs[i] -= (t0 + t1) + (t2 + t3)
        else:
            s = rhs[i]
            for k in range(i):
                s -= A[i, BW + k - i] * rhs[k]
            rhs[i] = s
    for i in range(n - 1, -1, -1):
        if i + BW < n:
            t0 = A[i, 9] * rhs[i + 1] + A[i, 10] * rhs[i + 2]
            t1 = A[i, 11] * rhs[i + 3] + A[i, 12] * rhs[i + 4]
            t2 = A[i, 13] * rhs[i + 5] + A[i, 14] * rhs[i + 6]
            t3 = A[i, 15] * rhs[i + 7] + A[i, 16] * rhs[i + 8]
            rhs[i] = (rhs[i] - ((t0 + t1) + (t2 + t3))) * A[i, BW]
        else:
            s = rhs[i]
            for j in range(i + 1, n):
                s -= A[i, BW + j - i] * rhs[j]
            rhs[i] = s * A[i, BW]


@njit(cache=True)
def band_solve(A, rhs):
    """Solve ``A x = rhs`` in place (``A`` is overwritten by its LU factors)."""
    if not band_factor(A):
        return False
    band_backsolve(A, rhs)
    return True


# ----------------------------------------------------------------------------------
# elastic and damping elements
# ----------------------------------------------------------------------------------
@njit(cache=True)
def _unit(e):
    n = np.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return e / n, n


@njit(cache=True, inline="always")
def _proj_into(t, P):
    for i in range(3):
        for j in range(3):
            P[i, j] = (1.0 if i == j else 0.0) - t[i] * t[j]


@njit(cache=True, inline="always")
def _matvec(P, v, out, scale):
    for i in range(3):
        out[i] = scale * (P[i, 0] * v[0] + P[i, 1] * v[1] + P[i, 2] * v[2])


@njit(cache=True, inline="always")
def _pvec(t, v, out, scale):
    """Out = scale * (I - t t^T) v, without forming the projector."""
    tv = t[0] * v[0] + t[1] * v[1] + t[2] * v[2]
    for i in range(3):
        out[i] = scale * (v[i] - t[i] * tv)


@njit(cache=True, inline="always")
def _bend_self_into(P, t, d, length, sign, H):
    """Second-derivative block of ``k|d|^2`` w.r.t. one edge, divided by 2k, into ``H``.

    ``sign`` is +1 for the trailing edge (d = t2 - t1 depends on -t1) and -1 for the
    leading edge.
    """
    pd0 = P[0, 0] * d[0] + P[0, 1] * d[1] + P[0, 2] * d[2]
    pd1 = P[1, 0] * d[0] + P[1, 1] * d[1] + P[1, 2] * d[2]
    pd2 = P[2, 0] * d[0] + P[2, 1] * d[1] + P[2, 2] * d[2]
    pd = (pd0, pd1, pd2)
    a = t[0] * d[0] + t[1] * d[1] + t[2] * d[2]
    inv = 1.0 / (length * length)
    for i in range(3):
        for j in range(3):
            H[i, j] = (P[i, j] + sign * (pd[i] * t[j] + t[i] * pd[j] + a * P[i, j])) * inv


@njit(cache=True)
def add_internal(x, v, rod, damping, F, S, cD, cK, jac):
    """Add elastic and damping forces to ``F`` and, if ``jac``, ``cD D + cK K`` to ``S``.

    ``rod`` (:class:`RodArrays`) gives the bending constants ``kb[i]`` at nodes
    i = 1..n-2, the follicle's ``kf`` and rest ``axis``, the edges' rest lengths
    ``L0`` and axial rigidities ``EA`` and the node mass matrix. ``damping``
    (:class:`Damping`): ``alpha`` (mass proportional), ``beta_shaft`` (shaft
    stiffness proportional: material damping) and ``beta_follicle`` (the follicle's
    rubber: damping moment ``k_f beta_follicle dpsi/dt``). The follicle housing is
    at rest; :func:`add_internal_whisking` turns it.
    """
    add_internal_whisking(x, v, rod, damping, F, S, cD, cK, jac, 0.0, 0.0)


@njit(cache=True)
def _housing_axis(axis, theta, out):
    """``axis`` turned by ``theta`` (rad) about ``y``, from ``z`` toward ``x``."""
    c = np.cos(theta)
    s = np.sin(theta)
    out[0] = c * axis[0] + s * axis[2]
    out[1] = axis[1]
    out[2] = -s * axis[0] + c * axis[2]


@njit(cache=True)
def add_internal_whisking(x, v, rod, damping, F, S, cD, cK, jac, theta, theta_dot):
    """:func:`add_internal` with the follicle housing turned by ``theta`` about ``y``.

    Whisking: a motor turns the follicle housing (and with it the follicle's rest
    direction ``rod.axis``) by the angle ``theta`` (rad, from ``z`` toward ``x``)
    about the ``y`` axis through the pivot (node 0), at the rate ``theta_dot``
    (rad/s). The follicle spring pulls the magnet toward the turned rest direction
    and its rubber damper resists the magnet's angular velocity *relative to the
    housing*: the rate of the shaft tangent ``t0`` minus ``omega x t0`` with
    ``omega = theta_dot y``. With ``theta = theta_dot = 0`` this is exactly the
    fixed follicle (the same operations, the same bytes). The Jacobian omits the
    small derivative of the housing-rate term with respect to positions (a
    modified-Newton approximation; convergence is judged on the full residual).
    """
    kb = rod.kb
    kf = rod.kf
    axis = rod.axis
    turned = theta != 0.0 or theta_dot != 0.0
    if turned:
        axis = np.empty(3)
        _housing_axis(rod.axis, theta, axis)
    L0 = rod.L0
    EA = rod.EA
    mass = rod.mass
    alpha_d = damping.alpha
    beta_d = damping.beta_shaft
    beta_f = damping.beta_follicle
    n = x.shape[0]
    vec = np.empty((11, 3))
    t1 = vec[0]
    t2 = vec[1]
    d = vec[2]
    g1 = vec[3]
    g2 = vec[4]
    de1 = vec[5]
    de2 = vec[6]
    ddot = vec[7]
    r1 = vec[8]
    r2 = vec[9]
    tmp = vec[10]
    mat = np.empty((6, 3, 3))
    P1 = mat[0]
    P2 = mat[1]
    G1 = mat[2]
    G2 = mat[3]
    H = mat[4]
    J12 = mat[5]
    # unit tangents and lengths of every edge, computed once
    tan = np.empty((n - 1, 3))
    lens = np.empty(n - 1)
    for e in range(n - 1):
        e0 = x[e + 1, 0] - x[e, 0]
        e1 = x[e + 1, 1] - x[e, 1]
        e2 = x[e + 1, 2] - x[e, 2]
        ln = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        il = 1.0 / ln
        tan[e, 0] = e0 * il
        tan[e, 1] = e1 * il
        tan[e, 2] = e2 * il
        lens[e] = ln
    # --- stretching of every edge
    for e in range(n - 1):
        a = e
        b = e + 1
        ln = lens[e]
        t1[0] = tan[e, 0]
        t1[1] = tan[e, 1]
        t1[2] = tan[e, 2]
        ka = EA[e] / L0[e]
        rate = (
            t1[0] * (v[b, 0] - v[a, 0]) + t1[1] * (v[b, 1] - v[a, 1]) + t1[2] * (v[b, 2] - v[a, 2])
        )
        fmag = ka * (ln - L0[e]) + beta_d * ka * rate
        for c in range(3):
            F[a, c] += fmag * t1[c]
            F[b, c] -= fmag * t1[c]
        if jac:
            # the force fmag t turns with the edge: its elastic part and its damping
            # part (whose rate t . dv also turns) both add geometric stiffness
            geo = cK * ka * (1.0 - L0[e] / ln + beta_d * rate / ln)
            tt_coef = cK * ka + cD * beta_d * ka
            cdv = cK * beta_d * ka / ln
            for c in range(3):
                d[c] = v[b, c] - v[a, c] - rate * t1[c]  # (I - t t^T) dv
            for i in range(3):
                for j in range(3):
                    tt = t1[i] * t1[j]
                    H[i, j] = (
                        tt_coef * tt + geo * ((1.0 if i == j else 0.0) - tt) + cdv * t1[i] * d[j]
                    )
            for r in range(3):
                ra = 3 * a + r
                rb = 3 * b + r
                for c in range(3):
                    h = H[r, c]
                    S[ra, BW + 3 * a + c - ra] += h
                    S[rb, BW + 3 * b + c - rb] += h
                    S[ra, BW + 3 * b + c - ra] -= h
                    S[rb, BW + 3 * a + c - rb] -= h
    # --- follicle: k_f/2 |t0 - axis|^2 ; only node 1 moves (node 0 is the pivot)
    l2 = lens[0]
    t2[0] = tan[0, 0]
    t2[1] = tan[0, 1]
    t2[2] = tan[0, 2]
    _proj_into(t2, P2)
    k = 0.5 * kf
    for c in range(3):
        d[c] = t2[c] - axis[c]
        de2[c] = v[1, c] - v[0, c]
    if turned:
        # relative to the housing: subtract the edge's rigid motion with it,
        # l2 * (omega x t0), omega = theta_dot * y
        de2[0] -= l2 * theta_dot * t2[2]
        de2[2] += l2 * theta_dot * t2[0]
    _matvec(P2, d, g2, 1.0 / l2)
    _matvec(P2, de2, ddot, 1.0 / l2)
    _matvec(P2, ddot, r2, 1.0 / l2)
    for c in range(3):
        f = -2.0 * k * (g2[c] + beta_f * r2[c])
        F[1, c] += f
        F[0, c] -= f
    if jac:
        _bend_self_into(P2, t2, d, l2, -1.0, G2)
        inv = 1.0 / (l2 * l2)
        for i in range(3):
            for j in range(3):
                H[i, j] = 2.0 * k * (cK * G2[i, j] + cD * beta_f * P2[i, j] * inv)
        band_add_block(S, 1, 1, H, 1.0)
    # --- bending at nodes 1..n-2 between edge i-1 (a->b) and edge i (b->c)
    for i in range(1, n - 1):
        k = kb[i]
        if k == 0.0:
            continue
        a = i - 1
        b = i
        c = i + 1
        l1 = lens[a]
        l2 = lens[b]
        il1 = 1.0 / l1
        il2 = 1.0 / l2
        for q in range(3):
            t1[q] = tan[a, q]
            t2[q] = tan[b, q]
            d[q] = t2[q] - t1[q]
            de1[q] = v[b, q] - v[a, q]
            de2[q] = v[c, q] - v[b, q]
        _pvec(t1, d, g1, -il1)
        _pvec(t2, d, g2, il2)
        if beta_d != 0.0:
            _pvec(t1, de1, r1, -il1)
            _pvec(t2, de2, tmp, il2)
            for q in range(3):
                ddot[q] = r1[q] + tmp[q]
            _pvec(t1, ddot, r1, -il1)
            _pvec(t2, ddot, r2, il2)
        else:
            for q in range(3):
                r1[q] = 0.0
                r2[q] = 0.0
        for q in range(3):
            fe1 = -2.0 * k * (g1[q] + beta_d * r1[q])
            fe2 = -2.0 * k * (g2[q] + beta_d * r2[q])
            F[a, q] -= fe1
            F[b, q] += fe1 - fe2
            F[c, q] += fe2
        if jac:
            _proj_into(t1, P1)
            _proj_into(t2, P2)
            _bend_self_into(P1, t1, d, l1, 1.0, G1)
            _bend_self_into(P2, t2, d, l2, -1.0, G2)
            i11 = 1.0 / (l1 * l1)
            i22 = 1.0 / (l2 * l2)
            i12 = -1.0 / (l1 * l2)
            kk = 2.0 * k
            c12 = kk * (cK + cD * beta_d) * i12
            for p in range(3):
                for q in range(3):
                    s12 = P1[p, 0] * P2[0, q] + P1[p, 1] * P2[1, q] + P1[p, 2] * P2[2, q]
                    J12[p, q] = c12 * s12
                    G1[p, q] = kk * cK * G1[p, q] + kk * cD * beta_d * P1[p, q] * i11
                    G2[p, q] = kk * cK * G2[p, q] + kk * cD * beta_d * P2[p, q] * i22
            # node blocks: with e1 = xb - xa, e2 = xc - xb
            # aa = H11; ab = -H11 + H12; ac = -H12; bb = H11 - H12 - H21 + H22;
            # bc = H12 - H22; cc = H22  (H21 = H12^T)
            for p in range(3):
                ra = 3 * a + p
                rb = 3 * b + p
                rc = 3 * c + p
                for q in range(3):
                    h11 = G1[p, q]
                    h22 = G2[p, q]
                    h12 = J12[p, q]
                    h21 = J12[q, p]
                    S[ra, BW + 3 * a + q - ra] += h11
                    S[ra, BW + 3 * b + q - ra] += -h11 + h12
                    S[ra, BW + 3 * c + q - ra] += -h12
                    S[rb, BW + 3 * a + q - rb] += -h11 + h21
                    S[rb, BW + 3 * b + q - rb] += h11 - h12 - h21 + h22
                    S[rb, BW + 3 * c + q - rb] += h12 - h22
                    S[rc, BW + 3 * a + q - rc] += -h21
                    S[rc, BW + 3 * b + q - rc] += h21 - h22
                    S[rc, BW + 3 * c + q - rc] += h22
    # --- mass-proportional damping (with the tridiagonal mass matrix)
    if alpha_d != 0.0:
        mass_off = rod.mass_off
        for i in range(n):
            for c in range(3):
                mv = mass[i] * v[i, c]
                if i > 0:
                    mv += mass_off[i - 1] * v[i - 1, c]
                if i < n - 1:
                    mv += mass_off[i] * v[i + 1, c]
                F[i, c] -= alpha_d * mv
            if jac:
                for c in range(3):
                    r = 3 * i + c
                    S[r, BW] += cD * alpha_d * mass[i]
                    if i > 0:
                        S[r, BW - 3] += cD * alpha_d * mass_off[i - 1]
                    if i < n - 1:
                        S[r, BW + 3] += cD * alpha_d * mass_off[i]


# ----------------------------------------------------------------------------------
# contacts
# ----------------------------------------------------------------------------------
PEN_SMOOTH_M = 2.0e-6  # penetration over which the penalty force ramps in (C1 onset)


@njit(cache=True)
def _penalty(kn, pen):
    """Smoothed penalty: force and stiffness for penetration ``pen`` (m).

    Quadratic onset over ``PEN_SMOOTH_M`` then linear, so that the force is
    continuously differentiable and Newton's method does not cycle at contact onset.
    Within ``PEN_SMOOTH_M`` *outside* contact a small stiffness is reported (with no
    force) to keep Newton steps from overshooting into deep penetration. Returns
    (force, stiffness, d ramp / d pen) where ramp = stiffness / kn scales the contact
    damping.
    """
    d = PEN_SMOOTH_M
    if pen <= 0.0:
        if pen > -d:
            return 0.0, 0.25 * kn, 0.0
        return 0.0, 0.0, 0.0
    if pen < d:
        return 0.5 * kn * pen * pen / d, kn * pen / d, 1.0 / d
    return kn * (pen - 0.5 * d), kn, 0.0


@njit(cache=True)
def _add_weighted3(S, i0, w0, w1, w2, blk):
    """Add w_p w_q blk to the blocks of nodes (i0, i0 + 1, i0 + 2)^2."""
    for p in range(3):
        wp = w0 if p == 0 else (w1 if p == 1 else w2)
        for q in range(3):
            wq = w0 if q == 0 else (w1 if q == 1 else w2)
            ww = wp * wq * 1.0
            if ww != 0.0:
                band_add_block(S, i0 + p, i0 + q, blk, ww)


@njit(cache=True)
def _curve_weights(n, j, u):
    """Node weights of the C1 centreline at parameter u of piece j.

    The centreline of the free shaft (nodes 1..n-1) is the quadratic B-spline with
    the nodes as control points, clamped at both ends: piece j (2 <= j <= n-2) runs
    from the midpoint of edge (j-1, j) to that of edge (j, j+1) with node j as
    control point; piece 1 is the straight half-edge from the base node and piece
    n-1 the straight half-edge to the tip. Returns (w0, w1, w2, i0) for nodes i0,
    i0+1, i0+2.
    """
    if j == 1:
        return 1.0 - 0.5 * u, 0.5 * u, 0.0, 1
    if j == n - 1:
        return 0.0, 0.5 * (1.0 - u), 0.5 * (1.0 + u), n - 3
    a = 1.0 - u
    return 0.5 * a * a, 0.5 * a * a + 2.0 * u * a + 0.5 * u * u, 0.5 * u * u, j - 1


@njit(cache=True)
def _closest_u(x, j, px, pz):
    """Parameter of the point of piece j closest to (px, pz) in the x-z plane."""
    n = x.shape[0]
    w0, w1, w2, i0 = _curve_weights(n, j, 0.0)
    ax = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0]
    az = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2]
    w0, w1, w2, i0 = _curve_weights(n, j, 1.0)
    bx = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0] - ax
    bz = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2] - az
    ll = bx * bx + bz * bz
    u = ((px - ax) * bx + (pz - az) * bz) / ll if ll > 0 else 0.0
    u = min(1.0, max(0.0, u))
    if j == 1 or j == n - 1:
        return u
    # quadratic piece: a few Newton steps on |q(u) - p|^2
    d1x = x[j, 0] - x[j - 1, 0]
    d1z = x[j, 2] - x[j - 1, 2]
    d2x = x[j + 1, 0] - x[j, 0]
    d2z = x[j + 1, 2] - x[j, 2]
    qqx = d2x - d1x
    qqz = d2z - d1z
    for _ in range(4):
        w0, w1, w2, i0 = _curve_weights(n, j, u)
        rx = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0] - px
        rz = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2] - pz
        tx = (1.0 - u) * d1x + u * d2x
        tz = (1.0 - u) * d1z + u * d2z
        g = rx * tx + rz * tz
        hh = tx * tx + tz * tz + rx * qqx + rz * qqz
        if hh <= 0.0:
            break
        u = min(1.0, max(0.0, u - g / hh))
    return u


@njit(cache=True)
def add_pole(x, v, rod, contact, pole, anchor, F, S, cD, cK, jac, info):
    """Point contact with a thin pole parallel to ``y`` at ``(pole[0], pole[1])`` in x-z.

    ``pole`` is the object state (x, z, vx, vz, y, vy): the pole may also slide along
    its own axis (``y``), which friction resists. ``contact.params`` holds the pole's
    radius, the penalty stiffness ``kn``, approach damping ``cn``, friction ``mu``
    and presliding distance ``kt`` (see :class:`ContactSpec`); ``rod`` supplies the
    shaft's radius and rest arc lengths.

    Friction is elasto-plastic Coulomb: a tangential spring of stiffness
    ``mu N / kt`` (``kt`` is the presliding distance, m) from a stick anchor
    (``anchor[0]`` whisker arc length, ``anchor[1]`` pole coordinate ``y``,
    ``anchor[2]`` > 0 when the anchor is valid, ``anchor[3]`` the angle of the contact
    on the pole's circumference, ``anchor[4]`` the side of the pole the shaft was on
    when last out of contact); when the spring force would exceed
    ``mu * N`` the contact slips. The anchor *proposed* for the end of the step is
    written to ``info[4:7]``; the caller commits it once the step has converged.
    ``info`` receives [normal force N, arc length of contact (m), slipping flag,
    gap (m), new anchor s, new anchor y, anchor valid, fx, fz, new anchor angle, fy,
    side].
    """
    radius = rod.radius
    s_rest = rod.s_rest
    cpar = contact.params
    pole_v = np.array([pole[2], pole[5], pole[3]])
    pole_radius = cpar[0]
    kn = cpar[1]
    cn = cpar[2]
    mu = cpar[3]
    kt = cpar[4]
    n = x.shape[0]
    # closest point on the C1 centreline (quadratic B-spline through the segment
    # midpoints, see _curve_point): the polyline's kinks would make the distance
    # non-smooth at nodes and Newton's method cycle there
    best = 1e300
    best_d = 1e300
    bj = -1
    bu = 0.0
    # coarse pass: distance to each piece's chord (cheap); then refine the nearest
    # piece and its neighbours on the curve itself
    jc = 1
    dc = 1e300
    for j in range(1, n):
        w0, w1, w2, i0 = _curve_weights(n, j, 0.5)
        qx = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0] - pole[0]
        qz = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2] - pole[1]
        d2 = qx * qx + qz * qz
        if d2 < dc:
            dc = d2
            jc = j
    for j in range(max(1, jc - 2), min(n, jc + 3)):
        u = _closest_u(x, j, pole[0], pole[1])
        w0, w1, w2, i0 = _curve_weights(n, j, u)
        qx = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0] - pole[0]
        qz = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2] - pole[1]
        dist = np.sqrt(qx * qx + qz * qz)
        # select by centreline distance (the point where the normal passes through
        # the pole's axis); the taper's radius enters the gap only at that point
        if dist < best_d:
            best_d = dist
            best = (
                dist - pole_radius - (w0 * radius[i0] + w1 * radius[i0 + 1] + w2 * radius[i0 + 2])
            )
            bj = j
            bu = u
    info[0] = 0.0
    info[2] = 0.0
    info[3] = best
    info[6] = 0.0
    info[7] = 0.0
    info[8] = 0.0
    if bj < 0:
        return
    j = bj
    u = bu
    w0, w1, w2, i0 = _curve_weights(n, j, u)
    q0 = w0 * x[i0, 0] + w1 * x[i0 + 1, 0] + w2 * x[i0 + 2, 0]
    q1 = w0 * x[i0, 1] + w1 * x[i0 + 1, 1] + w2 * x[i0 + 2, 1]
    q2 = w0 * x[i0, 2] + w1 * x[i0 + 1, 2] + w2 * x[i0 + 2, 2]
    s_c = w0 * s_rest[i0] + w1 * s_rest[i0 + 1] + w2 * s_rest[i0 + 2]
    rad_c = w0 * radius[i0] + w1 * radius[i0 + 1] + w2 * radius[i0 + 2]
    # unit tangent (toward the tip) of the centreline at parameter u of piece j
    if j == 1:
        tw0 = x[2, 0] - x[1, 0]
        tw1 = x[2, 1] - x[1, 1]
        tw2 = x[2, 2] - x[1, 2]
    elif j == n - 1:
        tw0 = x[n - 1, 0] - x[n - 2, 0]
        tw1 = x[n - 1, 1] - x[n - 2, 1]
        tw2 = x[n - 1, 2] - x[n - 2, 2]
    else:
        tw0 = (1.0 - u) * (x[j, 0] - x[j - 1, 0]) + u * (x[j + 1, 0] - x[j, 0])
        tw1 = (1.0 - u) * (x[j, 1] - x[j - 1, 1]) + u * (x[j + 1, 1] - x[j, 1])
        tw2 = (1.0 - u) * (x[j, 2] - x[j - 1, 2]) + u * (x[j + 1, 2] - x[j, 2])
    tl = np.sqrt(tw0 * tw0 + tw1 * tw1 + tw2 * tw2)
    tw0 = tw0 / tl
    tw1 = tw1 / tl
    tw2 = tw2 / tl
    info[1] = s_c
    nx = q0 - pole[0]
    nz = q2 - pole[1]
    nd = np.sqrt(nx * nx + nz * nz)
    if nd == 0.0:
        return
    nv0 = nx / nd
    nv2 = nz / nd
    # which side of the pole the shaft is on (sign of the offset across the segment);
    # remembered between steps so that a fast whisker cannot tunnel through the pole
    at_tip = j == n - 1 and u >= 1.0
    side_now = 0.0
    if not at_tip:
        side_now = 1.0 if nx * tw2 - nz * tw0 >= 0.0 else -1.0
    info[11] = side_now
    pen = -best
    if anchor[4] != 0.0 and side_now != 0.0 and side_now != anchor[4]:
        # crossed to the wrong side within a step: push back out the way it came
        nv0 = -nv0
        nv2 = -nv2
        pen = nd + pole_radius + rad_c
    info[3] = -pen
    fpen, kpen, dramp = _penalty(kn, pen)
    if kpen == 0.0:
        return
    vr0 = (w0 * v[i0, 0] + w1 * v[i0 + 1, 0] + w2 * v[i0 + 2, 0]) - pole_v[0]
    vr2 = (w0 * v[i0, 2] + w1 * v[i0 + 1, 2] + w2 * v[i0 + 2, 2]) - pole_v[2]
    vn = vr0 * nv0 + vr2 * nv2
    blk = np.empty((3, 3))
    if fpen == 0.0:
        # just outside contact: stiffness only (see _penalty)
        if jac:
            for p in range(3):
                np_ = nv0 if p == 0 else (0.0 if p == 1 else nv2)
                for r in range(3):
                    nr_ = nv0 if r == 0 else (0.0 if r == 1 else nv2)
                    blk[p, r] = cK * kpen * np_ * nr_
            _add_weighted3(S, i0, w0, w1, w2, blk)
        return
    ramp = kpen / kn  # damping ramps in with the penalty (no force jump at touch)
    damp = -cn * ramp * vn if vn < 0.0 else 0.0
    kpen += -cn * vn * dramp if vn < 0.0 else 0.0  # d(damping force)/d(penetration)
    fn = fpen + damp
    if fn < 0.0:
        fn = 0.0
    # tangential directions: along the whisker (in contact plane) and along the pole (y)
    tn = tw0 * nv0 + tw2 * nv2
    tw0 -= tn * nv0
    tw2 -= tn * nv2
    tl = np.sqrt(tw0 * tw0 + tw1 * tw1 + tw2 * tw2)
    tw0 = tw0 / tl
    tw1 = tw1 / tl
    tw2 = tw2 / tl
    # angle of the contact normal about +y: the contact point's position on the pole
    psi = np.arctan2(-nv2, nv0)
    if anchor[2] <= 0.0:
        # first touch: stick where the contact is first found
        anchor[0] = s_c
        anchor[1] = q1 - pole[4]
        anchor[2] = 1.0
        anchor[3] = psi
    # slip = arc travelled by the contact along the whisker minus that along the pole's
    # surface (rolling on the round pole moves the contact without any slip)
    sigma = nv2 * tw0 - nv0 * tw2
    dpsi = psi - anchor[3]
    if dpsi > np.pi:
        dpsi -= 2.0 * np.pi
    elif dpsi < -np.pi:
        dpsi += 2.0 * np.pi
    rel_s = -(s_c - anchor[0]) + sigma * pole_radius * dpsi
    rel_y = q1 - pole[4] - anchor[1]  # anchor[1] is in the pole's own frame
    # elasto-plastic Coulomb friction with a presliding distance: the tangential
    # stiffness is mu * N / d_slip, so the contact slips once the elastic tangential
    # displacement exceeds d_slip (``kt`` holds d_slip in metres)
    kt_eff = mu * fn / kt if kt > 0.0 else 0.0
    ft_s = -kt_eff * rel_s
    ft_y = -kt_eff * rel_y
    ftm = np.sqrt(ft_s * ft_s + ft_y * ft_y)
    slipping = False
    lim = mu * fn
    scale = 1.0
    if ftm > lim * (1.0 + 1e-12):
        slipping = True
        scale = lim / ftm
        ft_s *= scale
        ft_y *= scale
        rel_s *= scale
        rel_y *= scale
    fv0 = fn * nv0 + ft_s * tw0
    fv1 = fn * 0.0 + ft_s * tw1
    fv2 = fn * nv2 + ft_s * tw2
    fv1 += ft_y
    F[i0, 0] += w0 * fv0
    F[i0, 1] += w0 * fv1
    F[i0, 2] += w0 * fv2
    F[i0 + 1, 0] += w1 * fv0
    F[i0 + 1, 1] += w1 * fv1
    F[i0 + 1, 2] += w1 * fv2
    F[i0 + 2, 0] += w2 * fv0
    F[i0 + 2, 1] += w2 * fv1
    F[i0 + 2, 2] += w2 * fv2
    info[0] = fn
    info[2] = 1.0 if slipping else 0.0
    info[4] = s_c + rel_s  # re-anchored at the current pole angle, same elastic slip
    info[5] = q1 - pole[4] - rel_y
    info[6] = 1.0
    info[9] = psi
    info[10] = fv1
    info[7] = fv0
    info[8] = fv2
    if jac:
        # friction scales with the normal force (non-symmetric term); when slipping,
        # the consistent tangent of the return map kt * ratio * (P_t - f f^T)
        inv_lim = 1.0 / max(lim, 1e-300)
        for p in range(3):
            twp = tw0 if p == 0 else (tw1 if p == 1 else tw2)
            eyp = 1.0 if p == 1 else 0.0
            nvp = nv0 if p == 0 else (0.0 if p == 1 else nv2)
            fdp = (ft_s * twp + ft_y * eyp) * inv_lim
            for r in range(3):
                twr = tw0 if r == 0 else (tw1 if r == 1 else tw2)
                eyr = 1.0 if r == 1 else 0.0
                nvr = nv0 if r == 0 else (0.0 if r == 1 else nv2)
                fdr = (ft_s * twr + ft_y * eyr) * inv_lim
                pt = twp * twr + eyp * eyr
                if slipping:
                    pt = scale * (pt - fdp * fdr)
                blk[p, r] = cK * (kpen * nvp * nvr + mu * kpen * fdp * nvr + kt_eff * pt)
                if vn < 0.0:
                    blk[p, r] += cD * cn * ramp * nvp * nvr
        _add_weighted3(S, i0, w0, w1, w2, blk)


@njit(cache=True)
def _height(H, du, dw, U, W):
    """Height and slopes of a periodic height field at surface coords (U, W).

    Uniform quadratic B-spline through the grid values as control points: C1
    continuous (no jumps in the surface normal, which would make Newton cycle).
    """
    nu = H.shape[0]
    nw = H.shape[1]
    fu = U / du
    fw = W / dw
    iu = int(np.floor(fu + 0.5))
    iw = int(np.floor(fw + 0.5))
    tu = fu - iu
    tw = fw - iw
    bu0 = 0.5 * (0.5 - tu) ** 2
    bu1 = 0.75 - tu * tu
    bu2 = 0.5 * (0.5 + tu) ** 2
    du0 = -(0.5 - tu)
    du1 = -2.0 * tu
    du2 = 0.5 + tu
    bw0 = 0.5 * (0.5 - tw) ** 2
    bw1 = 0.75 - tw * tw
    bw2 = 0.5 * (0.5 + tw) ** 2
    dw0 = -(0.5 - tw)
    dw1 = -2.0 * tw
    dw2 = 0.5 + tw
    h = 0.0
    hu = 0.0
    hw = 0.0
    for a in range(3):
        ia = (iu - 1 + a) % nu
        ba = bu0 if a == 0 else (bu1 if a == 1 else bu2)
        da = du0 if a == 0 else (du1 if a == 1 else du2)
        for b in range(3):
            ib = (iw - 1 + b) % nw
            bb = bw0 if b == 0 else (bw1 if b == 1 else bw2)
            db = dw0 if b == 0 else (dw1 if b == 1 else dw2)
            z = H[ia, ib]
            h += ba * bb * z
            hu += da * bb * z
            hw += ba * db * z
    return h, hu / du, hw / dw


#: Margin (m) added to a height field's largest value (``ContactSpec.h_max``) where it
#: bounds a gap from below: it covers the rounding of :func:`_height`'s weighted sum
#: (heights are ~1e-3 m, so 1e-9 m is millions of ulps), so that a node's lower bound
#: is never above the gap :func:`add_plane` computes for it.
H_MAX_MARGIN_M = 1e-9


@njit(cache=True)
def _plane_lower_gap(x, i, origin, nrm, radius, h_max):
    """A lower bound of node ``i``'s gap to a rough plane: its height less ``h_max``."""
    top = h_max + H_MAX_MARGIN_M
    Z = (
        (x[i, 0] - origin[0]) * nrm[0]
        + (x[i, 1] - origin[1]) * nrm[1]
        + (x[i, 2] - origin[2]) * nrm[2]
    )
    return Z - radius[i] - top


@njit(cache=True)
def _plane_nearest_gap(x, origin, contact, radius):
    """The gap (m) of the node whose lower bound is smallest, as :func:`add_plane` has it.

    The smallest gap of all nodes is at most this value, so a node whose lower bound
    (:func:`_plane_lower_gap`) exceeds it cannot hold the smallest gap.
    """
    nrm = contact.frame[0]
    tu = contact.frame[1]
    tw = contact.frame[2]
    best = np.inf
    ib = -1
    for i in range(contact.first_node, x.shape[0]):
        lower = _plane_lower_gap(x, i, origin, nrm, radius, contact.h_max)
        if lower < best:
            best = lower
            ib = i
    if ib < 0:
        return np.inf
    r = x[ib] - origin
    U = r[0] * tu[0] + r[1] * tu[1] + r[2] * tu[2]
    W = r[0] * tw[0] + r[1] * tw[1] + r[2] * tw[2]
    Z = r[0] * nrm[0] + r[1] * nrm[1] + r[2] * nrm[2]
    h, _, _ = _height(contact.heights, contact.du, contact.dw, U, W)
    return Z - h - radius[ib]


@njit(cache=True)
def add_plane(x, v, rod, contact, plane, anchors, F, S, cD, cK, jac, info):
    """Contact of every node from ``contact.first_node`` on with a (rough) plane.

    ``plane`` is the object state: the plane passes through ``origin = plane[0:3]``
    (moving with velocity ``origin_v = plane[3:6]``) with unit normal ``nrm``
    (pointing toward the whisker) and in-plane unit vectors ``tu``, ``tw`` (the rows
    of ``contact.frame``); ``H = contact.heights`` is a periodic height field (m) on
    a grid of spacing ``du``, ``dw`` in surface coordinates; ``contact.params`` holds
    the penalty stiffness ``kn``, approach damping ``cn``, friction ``mu`` and
    presliding distance ``kt`` (see :class:`ContactSpec`); ``rod`` supplies the
    shaft's radius. ``anchors[i] = (U, W, valid)`` are the stick anchors of node i;
    proposed new anchors go to ``anchors[i, 3:6]``. ``info`` receives [total normal
    force, number of nodes in contact, number slipping, min gap, force x, force z].
    """
    radius = rod.radius
    origin = plane[0:3]
    origin_v = plane[3:6]
    nrm = contact.frame[0]
    tu = contact.frame[1]
    tw = contact.frame[2]
    H = contact.heights
    du = contact.du
    dw = contact.dw
    cpar = contact.params
    kn = cpar[1]
    cn = cpar[2]
    mu = cpar[3]
    kt = cpar[4]
    first_node = contact.first_node
    n = x.shape[0]
    info[0] = 0.0
    info[1] = 0.0
    info[2] = 0.0
    info[3] = 1e300
    info[4] = 0.0
    info[5] = 0.0
    # A node's gap is at least its height over the plane less its radius and the
    # surface's highest point (``lower``). Only nodes whose lower bound is inside the
    # penalty's reach, or not above the gap of the node nearest the plane (the
    # smallest gap, ``info[3]``, can only come from those), need the surface under
    # them; the rest are out of contact and change nothing but their anchor flag.
    near = _plane_nearest_gap(x, origin, contact, radius)
    for i in range(first_node, n):
        lower = _plane_lower_gap(x, i, origin, nrm, radius, contact.h_max)
        if lower >= PEN_SMOOTH_M and lower > near:
            anchors[i, 5] = 0.0
            continue
        r = x[i] - origin
        U = r[0] * tu[0] + r[1] * tu[1] + r[2] * tu[2]
        W = r[0] * tw[0] + r[1] * tw[1] + r[2] * tw[2]
        Z = r[0] * nrm[0] + r[1] * nrm[1] + r[2] * nrm[2]
        h, hu, hw = _height(H, du, dw, U, W)
        gap = Z - h - radius[i]
        if gap < info[3]:
            info[3] = gap
        anchors[i, 5] = 0.0
        fpen, kpen, dramp = _penalty(kn, -gap)
        if kpen == 0.0:
            continue
        nl = nrm - hu * tu - hw * tw
        nl, _ = _unit(nl)
        if fpen == 0.0:
            if jac:
                blk = np.empty((3, 3))
                for p in range(3):
                    for q in range(3):
                        blk[p, q] = cK * kpen * nl[p] * nl[q]
                band_add_block(S, i, i, blk, 1.0)
            continue
        vrel = v[i] - origin_v
        vn = vrel[0] * nl[0] + vrel[1] * nl[1] + vrel[2] * nl[2]
        ramp = kpen / kn  # damping ramps in with the penalty (no force jump at touch)
        damp = -cn * ramp * vn if vn < 0.0 else 0.0
        kpen += -cn * vn * dramp if vn < 0.0 else 0.0  # d(damping force)/d(penetration)
        fn = fpen + damp
        if fn < 0.0:
            fn = 0.0
        # local tangent directions
        a1 = tu - (tu[0] * nl[0] + tu[1] * nl[1] + tu[2] * nl[2]) * nl
        a1, _ = _unit(a1)
        a2 = np.empty(3)
        a2[0] = nl[1] * a1[2] - nl[2] * a1[1]
        a2[1] = nl[2] * a1[0] - nl[0] * a1[2]
        a2[2] = nl[0] * a1[1] - nl[1] * a1[0]
        if anchors[i, 2] <= 0.0:
            anchors[i, 0] = U
            anchors[i, 1] = W
            anchors[i, 2] = 1.0
        ru = U - anchors[i, 0]
        rw = W - anchors[i, 1]
        # express the surface-coordinate slip in the local tangent frame
        sgn = a2[0] * tw[0] + a2[1] * tw[1] + a2[2] * tw[2]
        kt_eff = mu * fn / kt if kt > 0.0 else 0.0  # presliding distance kt (m)
        fu = -kt_eff * ru
        fw = -kt_eff * rw
        fm = np.sqrt(fu * fu + fw * fw)
        lim = mu * fn
        slipping = fm > lim * (1.0 + 1e-12)
        sc = 1.0
        if slipping:
            sc = lim / fm
            fu *= sc
            fw *= sc
            ru *= sc
            rw *= sc
            info[2] += 1.0
        fvec = fn * nl + fu * a1 + fw * sgn * a2
        for c in range(3):
            F[i, c] += fvec[c]
        info[0] += fn
        info[1] += 1.0
        info[4] += fvec[0]
        info[5] += fvec[2]
        anchors[i, 3] = U - ru
        anchors[i, 4] = W - rw
        anchors[i, 5] = 1.0
        if jac:
            blk = np.empty((3, 3))
            for p in range(3):
                fdir_p = (fu * a1[p] + fw * sgn * a2[p]) / max(lim, 1e-300)
                for q in range(3):
                    fdir_q = (fu * a1[q] + fw * sgn * a2[q]) / max(lim, 1e-300)
                    pt = a1[p] * a1[q] + a2[p] * a2[q]
                    if slipping:
                        pt = sc * (pt - fdir_p * fdir_q)
                    blk[p, q] = cK * (
                        kpen * nl[p] * nl[q] + mu * kpen * fdir_p * nl[q] + kt_eff * pt
                    )
                    if vn < 0.0:
                        blk[p, q] += cD * cn * ramp * nl[p] * nl[q]
            band_add_block(S, i, i, blk, 1.0)


# ----------------------------------------------------------------------------------
# solvers: static equilibrium (Newton) and implicit dynamics (generalised-alpha)
#
# Time integration uses the generalised-alpha method of Chung & Hulbert (1993) with
# all forces evaluated at the intermediate state ``x_{n+1-alpha_f}``; with spectral
# radius ``rho_inf < 1`` it is unconditionally stable for linear systems, second-order
# accurate, practically free of numerical damping at the whisker's bending
# frequencies and strongly dissipative at the (irrelevant) axial frequencies of the
# stiff stretching springs. Each step is solved by Newton's method on the banded
# tangent matrix.
# ----------------------------------------------------------------------------------
@njit(cache=True)
def _assemble(x, v, rod, damping, contact, tr, anchors, F, S, cD, cK, jac, info):
    """Forces into ``F`` and, if ``jac``, the iteration matrix into ``S`` (both zeroed).

    ``tr`` is the contact object's state at this instant (see :func:`run_dynamics`).
    """
    F[:, :] = 0.0
    if jac:
        S[:, :] = 0.0
    if tr.shape[0] > TR_BASE:
        add_internal_whisking(x, v, rod, damping, F, S, cD, cK, jac, tr[TR_BASE], tr[TR_BASE + 1])
    else:
        add_internal(x, v, rod, damping, F, S, cD, cK, jac)
    if contact.kind == POLE:
        add_pole(x, v, rod, contact, tr, anchors.pole, F, S, cD, cK, jac, info)
    elif contact.kind == PLANE:
        add_plane(x, v, rod, contact, tr, anchors.plane, F, S, cD, cK, jac, info)


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
def commit_anchors(kind, info, anchors):
    """Make the anchors proposed by the last converged contact evaluation current.

    ``kind`` is the contact kind, ``info`` the contact's output (see :func:`add_pole`),
    ``anchors`` the :class:`Anchors` to update in place.
    """
    pole_anchor = anchors.pole
    plane_anchors = anchors.plane
    if kind == POLE:
        if info[6] > 0.0:
            pole_anchor[0] = info[4]
            pole_anchor[1] = info[5]
            pole_anchor[2] = 1.0
            pole_anchor[3] = info[9]
        else:
            pole_anchor[2] = 0.0
        if info[3] > 0.0:
            # out of contact: remember the side the shaft is on
            pole_anchor[4] = info[11]
    elif kind == PLANE:
        for i in range(plane_anchors.shape[0]):
            if plane_anchors[i, 5] > 0.0:
                plane_anchors[i, 0] = plane_anchors[i, 3]
                plane_anchors[i, 1] = plane_anchors[i, 4]
                plane_anchors[i, 2] = 1.0
            else:
                plane_anchors[i, 2] = 0.0


@njit(cache=True)
def solve_static(x, f_app, rod, contact, tr, anchors, tol, max_iter, info):
    """Newton iterations for ``F_internal(x) + F_contact(x) + f_app = 0`` from ``x``.

    ``x`` (n, 3) is updated in place; ``f_app`` (n, 3) are applied forces (N);
    ``rod`` a :class:`RodArrays`, ``contact`` a :class:`ContactSpec` with the
    object's state ``tr`` and friction ``anchors`` (:class:`Anchors`; the pole's
    first touch writes its anchor, the rest is left to :func:`commit_anchors`);
    ``tol`` the tolerance on the update (m); ``info`` receives the contact's output.
    There is no damping (no velocities).

    Returns the number of iterations used, or -1 if it did not converge.
    """
    free = rod.free
    L0 = rod.L0
    no_damping = Damping(0.0, 0.0, 0.0)
    n = x.shape[0]
    v = np.zeros_like(x)
    F = np.zeros_like(x)
    S = np.zeros((3 * n, 2 * BW + 1))
    R = np.zeros(3 * n)
    # a runtime bool, not the literal True: numba would compile every callee once
    # more for a literal argument
    jac = max_iter > 0
    for it in range(max_iter):
        _assemble(x, v, rod, no_damping, contact, tr, anchors, F, S, 0.0, 1.0, jac, info)
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
def _fix_rhs(R, free):
    for i in range(free.shape[0]):
        if not free[i]:
            for c in range(3):
                R[3 * i + c] = 0.0


@njit(cache=True)
def _plane_entry_fraction(xa, dx, contact, tr, radius, af):
    """Largest safe fraction (<= 1) of the Newton update ``dx`` (flat, ``3 n``).

    That is, the largest that takes no node from outside a plane contact's smoothing zone
    to inside the surface.

    The forces are evaluated at the alpha point ``xa``, which moves by ``(1 - af) dx``.
    A node that the full update would carry from a gap of more than the penalty's
    smoothing length to a negative gap is stopped where it meets the surface, so the
    next iteration sees the contact's stiffness instead of jumping deep into it.
    """
    if contact.kind != PLANE:
        return 1.0
    origin = tr[0:3]
    nrm = contact.frame[0]
    tu = contact.frame[1]
    tw = contact.frame[2]
    H = contact.heights
    top = contact.h_max + H_MAX_MARGIN_M
    n = xa.shape[0]
    alpha = 1.0
    for i in range(contact.first_node, n):
        # a node that ends the update farther from the plane than the surface's
        # highest point cannot end it inside the surface
        r0 = xa[i, 0] + (1.0 - af) * dx[3 * i] - origin[0]
        r1 = xa[i, 1] + (1.0 - af) * dx[3 * i + 1] - origin[1]
        r2 = xa[i, 2] + (1.0 - af) * dx[3 * i + 2] - origin[2]
        if r0 * nrm[0] + r1 * nrm[1] + r2 * nrm[2] - radius[i] - top >= 0.0:
            continue
        g0 = 0.0
        g1 = 0.0
        for side in range(2):
            s = (1.0 - af) * side
            r0 = xa[i, 0] + s * dx[3 * i] - origin[0]
            r1 = xa[i, 1] + s * dx[3 * i + 1] - origin[1]
            r2 = xa[i, 2] + s * dx[3 * i + 2] - origin[2]
            U = r0 * tu[0] + r1 * tu[1] + r2 * tu[2]
            W = r0 * tw[0] + r1 * tw[1] + r2 * tw[2]
            Z = r0 * nrm[0] + r1 * nrm[1] + r2 * nrm[2]
            h, _, _ = _height(H, contact.du, contact.dw, U, W)
            if side == 0:
                g0 = Z - h - radius[i]
                if g0 <= PEN_SMOOTH_M:
                    break  # already at or in the contact's smoothing zone: never limited
            else:
                g1 = Z - h - radius[i]
        if g0 > PEN_SMOOTH_M and g1 < 0.0:
            f = g0 / (g0 - g1)
            if f < alpha:
                alpha = f
    return alpha


@njit(cache=True)
def _ga_step(state, work, rod, damping, contact, tr, anchors, h, settings):
    """One generalised-alpha step of size ``h`` from (xn, vn, an) of ``work`` into ``state``.

    ``work.newton`` carries the modified-Newton bookkeeping between calls:
    [need_factor, steps since factorisation, step size of the factors,
    iterations used, the last long step's error estimate]. Returns True on
    convergence.

    Newton has converged when its update is below ``settings.tol``, or when the
    error left after it, estimated from the observed contraction
    ``theta = |dx_k| / |dx_{k-1}|`` of two successive full updates as
    ``theta / (1 - theta) |dx_k|`` (Hairer and Wanner, *Solving ODEs II*, IV.8), is
    below :data:`NEWTON_KAPPA` times ``settings.tol``: the second saves the
    iteration that would only confirm a fast contraction. The factorisation is
    reused across iterations and steps (a modified Newton method) and replaced when a
    step starts with another step size or after a step that needed more than two
    iterations, and within a step once two successive updates shrank by less than
    :data:`THETA_REFACTOR`.

    The Newton updates are globalised: one longer than :data:`STEP_CAP_FRACTION` of
    an element is shortened to that length, and when an update computed from a fresh
    factorisation raised the squared residual it is halved (up to
    :data:`MAX_BACKTRACKS` times) before the next direction is computed. Without
    this a node at a grazing contact (a whisker's thin tip brushing a wall with
    millinewton forces) was carried in and out of the penalty by alternate
    iterations until the step failed and was retried in halves.

    Two more guards keep Newton on the physical branch when a node flies at a plane
    (a tip whipped against a wall): an update that would carry a node from outside
    the penalty's smoothing zone to inside the surface is shortened so that node stops
    at the surface (:func:`_plane_entry_fraction`), and an update from a reused
    factorisation longer than the cap is not taken: the matrix is factorised afresh at
    the same point. Without them the first Newton step of free flight put the tip deep
    inside the wall, Newton converged there on a solution with a penalty force of
    ~16 N (the CrunchBot whisker buckles under 0.6 N even clamped at both ends) and
    the whisker bounced off the wall in a chatter of such impacts, at 8-14 iterations
    a step.
    """
    x = state.x
    v = state.v
    a = state.a
    xn = work.xn
    vn = work.vn
    an = work.an
    xa = work.xa
    va = work.va
    F = work.F
    S = work.S
    R = work.R
    info = work.info
    newton = work.newton
    free = rod.free
    mass = rod.mass
    mass_off = rod.mass_off
    rho_inf = settings.rho_inf
    tol = settings.tol
    max_iter = settings.max_iter
    n = x.shape[0]
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gam = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    cM = (1.0 - am) / (beta * h * h)
    cD = (1.0 - af) * gam / (beta * h)
    cK = 1.0 - af
    if newton[2] != h or newton[3] > 2.0:
        # a new step size, or a last step that needed more than two iterations (its
        # contact is changing fast): start from a fresh factorisation
        newton[0] = 1.0
    # the step's fixed parts: a_new = (x - xb) / (beta h^2), v_new = vb + gam h a_new
    xb = work.xb
    vb = work.vb
    inv_bh2 = 1.0 / (beta * h * h)
    gh = gam * h
    for i in range(n):
        for c in range(3):
            xb[i, c] = xn[i, c] + h * vn[i, c] + h * h * (0.5 - beta) * an[i, c]
            vb[i, c] = vn[i, c] + h * (1.0 - gam) * an[i, c]
            if free[i]:
                x[i, c] = xn[i, c] + h * vn[i, c] + 0.5 * h * h * an[i, c]
            else:
                x[i, c] = xn[i, c]
    dx = work.dx
    step_cap = STEP_CAP_FRACTION * rod.L0[1]
    r_prev = np.inf  # squared residual where the last Newton direction was computed
    mx_prev = 0.0  # the last full Newton update's largest component (0: none yet)
    exact_prev = False  # ... and whether that direction came from a fresh factorisation
    backtracks = 0
    for it in range(max_iter):
        for i in range(n):
            fr = free[i]
            for c in range(3):
                anew = (x[i, c] - xb[i, c]) * inv_bh2 if fr else 0.0
                vnew = vb[i, c] + gh * anew if fr else 0.0
                a[i, c] = anew
                v[i, c] = vnew
                xa[i, c] = (1.0 - af) * x[i, c] + af * xn[i, c]
                va[i, c] = (1.0 - af) * vnew + af * vn[i, c]
        factor = newton[0] > 0.0
        _assemble(xa, va, rod, damping, contact, tr, anchors, F, S, cD, cK, factor, info)
        rr = 0.0
        for i in range(n):
            m = mass[i]
            mp = mass_off[i - 1] if i > 0 else 0.0
            mn = mass_off[i] if i < n - 1 else 0.0
            for c in range(3):
                ma = m * ((1.0 - am) * a[i, c] + am * an[i, c])
                if mp != 0.0:
                    ma += mp * ((1.0 - am) * a[i - 1, c] + am * an[i - 1, c])
                if mn != 0.0:
                    ma += mn * ((1.0 - am) * a[i + 1, c] + am * an[i + 1, c])
                R[3 * i + c] = F[i, c] - ma
        _fix_rhs(R, free)
        for k in range(3 * n):
            rr += R[k] * R[k]
        if exact_prev and rr > r_prev and backtracks < MAX_BACKTRACKS:
            # the last exact Newton step raised the residual (a contact switched on or
            # off across it and its linearisation overshot): go back half of it
            for i in range(n):
                for c in range(3):
                    dx[i, c] *= 0.5
                    x[i, c] -= dx[i, c]
            backtracks += 1
            newton[0] = 1.0
            continue
        if factor:
            for i in range(n):
                for c in range(3):
                    r = 3 * i + c
                    S[r, BW] += cM * mass[i]
                    if i > 0:
                        S[r, BW - 3] += cM * mass_off[i - 1]
                    if i < n - 1:
                        S[r, BW + 3] += cM * mass_off[i]
            _fix_rows(S, R, free)
            if not band_factor(S):
                newton[0] = 1.0
                return False
            newton[0] = 0.0
            newton[1] = 0.0
            newton[2] = h
        band_backsolve(S, R)
        mx = 0.0
        for k in range(3 * n):
            if abs(R[k]) > mx:
                mx = abs(R[k])
        if not np.isfinite(mx):
            newton[0] = 1.0
            return False
        if not factor and mx > step_cap:
            # a reused factorisation proposed an update longer than the cap: it no
            # longer describes the rod here; factorise afresh at this same point
            newton[0] = 1.0
            exact_prev = False
            continue
        # a Newton update longer than a fraction of an element is cut to that length
        frac = 1.0 if mx <= step_cap else step_cap / mx
        frac = min(frac, _plane_entry_fraction(xa, R, contact, tr, rod.radius, af))
        for i in range(n):
            for c in range(3):
                d = frac * R[3 * i + c]
                dx[i, c] = d
                x[i, c] += d
        r_prev = rr
        exact_prev = factor
        theta = mx / mx_prev if frac == 1.0 and mx_prev > 0.0 else 1.0
        mx_prev = mx if frac == 1.0 else 0.0
        if mx < tol or (theta < 1.0 and theta / (1.0 - theta) * mx <= NEWTON_KAPPA * tol):
            newton[3] = it + 1
            for i in range(n):
                if free[i]:
                    for c in range(3):
                        anew = (x[i, c] - xb[i, c]) * inv_bh2
                        a[i, c] = anew
                        v[i, c] = vb[i, c] + gh * anew
            newton[1] += 1.0
            return True
        if it >= 1 and theta > THETA_REFACTOR:
            # the reused factorisation contracts too slowly here: factorise afresh
            newton[0] = 1.0
    newton[0] = 1.0
    return False


@njit(cache=True)
def _write_tan(out, row, ex, ey, ez, traj, trow):
    """``out[row, 0:2]``: the magnet's tilt tangents from its edge vector ``e``.

    Read in the follicle housing's frame: turned back by the housing's whisk angle
    ``traj[trow, TR_BASE]`` when ``traj`` carries one (the Hall sensor turns with
    the housing), else the fixed frame.
    """
    if traj.shape[1] > TR_BASE:
        th = traj[trow, TR_BASE]
        c = np.cos(th)
        s = np.sin(th)
        exh = c * ex - s * ez
        ezh = s * ex + c * ez
        out[row, 0] = exh / ezh
        out[row, 1] = ey / ezh
    else:
        out[row, 0] = ex / ez
        out[row, 1] = ey / ez


@njit(cache=True)
def _max_speed(v, vn):
    """The largest node speed (m/s) in either of two velocity arrays."""
    m = 0.0
    for i in range(v.shape[0]):
        a = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        b = vn[i, 0] * vn[i, 0] + vn[i, 1] * vn[i, 1] + vn[i, 2] * vn[i, 2]
        m = max(m, a, b)
    return np.sqrt(m)


@njit(cache=True)
def _object_speed(kind, traj, row):
    """The contact object's speed (m/s) at trajectory row ``row`` (see run_dynamics)."""
    if kind == POLE:
        return np.sqrt(traj[row, 2] ** 2 + traj[row, 3] ** 2 + traj[row, 5] ** 2)
    return np.sqrt(traj[row, 3] ** 2 + traj[row, 4] ** 2 + traj[row, 5] ** 2)


@njit(cache=True)
def _try_stride(
    state, work, rod, damping, contact, traj, anchors, settings, k, K, prev_contact, prev_slip, out
):
    """Try one step of ``K * dt`` from step ``k``; keep it only if it passes the checks.

    The checks: the contact state stayed the same and the local error estimate is within
    ``settings.stride_tol``.

    On success rows ``out[k + 1 .. k + K]`` are filled (the intermediate rows by
    cubic Hermite interpolation of the magnet's motion, forces linearly) and
    :data:`STRIDE_OK` is returned; otherwise the state and anchors are restored and
    the reason is returned: :data:`STRIDE_DIVERGED` (Newton did not converge),
    :data:`STRIDE_CONTACT` (the contact state changed) or :data:`STRIDE_ERROR` (the
    error estimate exceeded the tolerance). The error estimate is Zienkiewicz and
    Xie's for the Newmark family, ``(beta - 1/6) h^2 max |a_{n+1} - a_n|``; it is
    left in ``work.newton[4]`` whenever the step converged.
    """
    x = state.x
    v = state.v
    a = state.a
    xn = work.xn
    vn = work.vn
    an = work.an
    info = work.info
    dt = settings.dt
    af = settings.rho_inf / (settings.rho_inf + 1.0)
    am = (2.0 * settings.rho_inf - 1.0) / (settings.rho_inf + 1.0)
    beta = 0.25 * (1.0 - am + af) ** 2
    h = K * dt
    pa_save = anchors.pole.copy()
    pl_save = anchors.plane.copy() if contact.kind == PLANE else anchors.plane
    tf = k + (1.0 - af) * K  # the alpha point, in steps
    i0 = int(tf)
    w = tf - i0
    tr = np.empty(traj.shape[1])
    for c in range(traj.shape[1]):
        tr[c] = (1.0 - w) * traj[i0, c] + w * traj[i0 + 1, c]
    code = STRIDE_OK
    if not _ga_step(state, work, rod, damping, contact, tr, anchors, h, settings):
        code = STRIDE_DIVERGED
    else:
        da = 0.0
        for i in range(x.shape[0]):
            for c in range(3):
                d = abs(a[i, c] - an[i, c])
                if d > da:
                    da = d
        est = (beta - 1.0 / 6.0) * h * h * da
        work.newton[4] = est
        contact_now = 1.0 if info[0] > 0.0 else 0.0
        if contact_now != prev_contact or info[2] != prev_slip:
            code = STRIDE_CONTACT
        elif (
            contact_now == 0.0
            and contact.kind != NO_CONTACT
            and info[3] < h * (_max_speed(v, vn) + _object_speed(contact.kind, traj, i0 + 1))
        ):
            # out of contact, and the object is closer than whisker and object could
            # come together within one step this long: a touch could start (or
            # start and end) inside it; leave the approach to single steps
            code = STRIDE_CONTACT
        elif est > settings.stride_tol:
            code = STRIDE_ERROR
    if code != STRIDE_OK:
        _copy2(x, xn)
        _copy2(v, vn)
        _copy2(a, an)
        _copy1(anchors.pole, pa_save)
        if contact.kind == PLANE:
            _copy2(anchors.plane, pl_save)
        work.newton[0] = 1.0
        return code
    commit_anchors(contact.kind, info, anchors)
    # outputs: the end of the step, and the rows in between interpolated
    p00 = xn[0, 0]
    p01 = xn[0, 1]
    p02 = xn[0, 2]
    end = np.empty(8)
    end[2] = info[0]
    end[3] = info[1]
    end[4] = info[2]
    if contact.kind == POLE:
        end[5] = info[7]
        end[6] = info[8]
    else:
        end[5] = info[4]
        end[6] = info[5]
    q = np.empty(3)
    for j in range(1, K + 1):
        sj = j / K
        h00 = (2.0 * sj - 3.0) * sj * sj + 1.0
        h10 = ((sj - 2.0) * sj + 1.0) * sj
        h01 = (3.0 - 2.0 * sj) * sj * sj
        h11 = (sj - 1.0) * sj * sj
        for c in range(3):
            q[c] = h00 * xn[1, c] + h10 * h * vn[1, c] + h01 * x[1, c] + h11 * h * v[1, c]
        if j == K:
            for c in range(3):
                q[c] = x[1, c]
        row = k + j
        _write_tan(out, row, q[0] - p00, q[1] - p01, q[2] - p02, traj, row)
        for c in range(2, 7):
            if c == 4:
                out[row, c] = end[4]
            else:
                out[row, c] = (1.0 - sj) * out[k, c] + sj * end[c]
        out[row, 7] = work.newton[3] if j == K else 0.0
    _copy2(xn, x)
    _copy2(vn, v)
    _copy2(an, a)
    return STRIDE_OK


@njit(cache=True, nogil=True)
def run_dynamics(state, anchors, rod, damping, contact, traj, settings, out, records, status):
    """Integrate ``len(traj) - 1`` steps of size ``settings.dt`` from ``state`` in place.

    ``state`` (:class:`NodeState`) and ``anchors`` (:class:`Anchors`) are advanced in
    place; ``rod``, ``damping``, ``contact`` and ``settings`` are the other bundles.
    ``traj[k]`` is the contact object's state at step k (pole: x, z, vx, vz, y, vy;
    plane: origin xyz, velocity xyz), optionally followed by the follicle housing's
    whisk angle (rad) and rate (rad/s) in columns ``TR_BASE`` and ``TR_BASE + 1``
    (:func:`add_internal_whisking`; the magnet's tangents are then read in the
    housing's frame), linearly interpolated within steps. ``out[k]``
    receives per-step outputs [tan_x, tan_y of the magnet, contact normal force (N),
    contact arc length (m), slipping, contact force x, contact force z, Newton
    iterations]. Every ``settings.record_every`` steps (if > 0) positions and
    velocities are stored in ``records[:, 0]`` and ``records[:, 1]``.

    Newton's method reuses the factorised iteration matrix across iterations and
    steps (a modified Newton method); it is refreshed every ``refactor_every``
    steps, whenever the contact state changes, and when it converges slowly (see
    :func:`_ga_step`). Convergence is always judged on the full update (see
    :func:`_ga_step`), so the reuse changes the cost, not the solution (to within
    ``tol``).

    While the contact state has not changed for :data:`STEADY_STEPS` steps, long
    steps of ``K * dt`` are tried (:func:`_try_stride`), ``K`` adapted between 2 and
    ``settings.max_stride``: doubled after a step whose error estimate leaves room
    for it (:data:`STRIDE_SAFETY`), halved and tried again at once after one whose
    estimate was too large, and back to single steps when the contact state
    changed or Newton failed. A step that does not
    converge is retried as 2, 4, ... sub-steps (at most ``2**max_halvings``).

    If ``settings.stop_tan > 0`` the integration stops after the first step whose
    |tan_x| reaches it (an event for closed-loop control); ``state`` and ``anchors``
    then hold the state at that step, ready to continue. If ``settings.stop_free > 0``
    it likewise stops after that many consecutive steps without contact force.

    Returns the number of completed steps (less than requested if a step failed or
    a stop event fired); ``status[0]`` says why it returned: 0 all steps done, 1 the
    ``stop_tan`` event, 2 the ``stop_free`` event, -1 a step failed.
    """
    x = state.x
    v = state.v
    a = state.a
    pole_anchor = anchors.pole
    plane_anchors = anchors.plane
    kind = contact.kind
    dt = settings.dt
    rho_inf = settings.rho_inf
    refactor_every = settings.refactor_every
    max_halvings = settings.max_halvings
    state_every = settings.record_every
    stop_tan = settings.stop_tan
    stop_free = settings.stop_free
    n_free = 0
    status[0] = 0
    n = x.shape[0]
    nsteps = traj.shape[0] - 1
    af = rho_inf / (rho_inf + 1.0)
    work = _StepWork(
        x.copy(),
        v.copy(),
        a.copy(),
        np.zeros_like(x),
        np.zeros_like(x),
        np.zeros_like(x),
        np.zeros((3 * n, 2 * BW + 1)),
        np.zeros(3 * n),
        np.zeros(12),
        np.array([1.0, 0.0, 0.0, 0.0, 0.0]),
        np.zeros_like(x),
        np.zeros_like(x),
        np.zeros_like(x),
    )
    xn = work.xn
    vn = work.vn
    an = work.an
    info = work.info
    newton = work.newton
    tr = np.zeros(traj.shape[1])
    pa_save = pole_anchor.copy()
    pl_save = plane_anchors.copy()
    row0 = np.int64(0)  # not a literal 0, which would compile _write_tan a second time
    _write_tan(out, row0, x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2], traj, row0)
    out[0, 2:] = 0.0
    si = 0
    if state_every > 0:
        _copy2(records[0, 0], x)
        _copy2(records[0, 1], v)
        si = 1
    prev_contact = 0.0
    prev_slip = 0.0
    max_sub = 1 << max_halvings
    max_stride = settings.max_stride if state_every == 0 else 1
    steady = 0  # steps since the contact state last changed (or a long step failed)
    stride = 2  # the next long step to try, in steps of dt
    k = np.int64(0)  # not a literal 0, which would compile _try_stride a second time
    while k < nsteps:
        if newton[1] >= refactor_every:
            newton[0] = 1.0
        # a long step while the contact state is steady
        K = min(stride, max_stride, nsteps - k) if steady >= STEADY_STEPS else 1
        if K > 1:
            code = _try_stride(
                state,
                work,
                rod,
                damping,
                contact,
                traj,
                anchors,
                settings,
                k,
                K,
                prev_contact,
                prev_slip,
                out,
            )
            if code == STRIDE_OK:
                # the error estimate grows like h^2 |a_{n+1} - a_n|, ~h^3 on smooth
                # motion (~h^2 where |a_{n+1} - a_n| does not grow with h): double
                # the stride while eight times this estimate keeps a margin
                if 8.0 * newton[4] <= STRIDE_SAFETY * settings.stride_tol:
                    stride = min(2 * K, max_stride)
                stop = False
                for j in range(k + 1, k + K + 1):
                    if stop_tan > 0.0 and abs(out[j, 0]) >= stop_tan:
                        status[0] = 1
                        return j
                    n_free = n_free + 1 if out[j, 2] == 0.0 else 0
                    if stop_free > 0 and n_free >= stop_free:
                        stop = True
                k += K
                if stop:
                    status[0] = 2
                    return k
                continue
            if code == STRIDE_ERROR and K // 2 > 1:
                stride = K // 2  # try again at once, half as long
                continue
            steady = 0
            stride = 2
        sub = 1
        done = 0  # completed sub-steps, in units of 1/sub
        iters = 0
        while done < sub:
            h = dt / sub
            fa = (done + 1.0 - af) / sub  # fraction of the step at the alpha point
            for c in range(traj.shape[1]):
                tr[c] = (1.0 - fa) * traj[k, c] + fa * traj[k + 1, c]
            _copy1(pa_save, pole_anchor)
            if kind == PLANE:  # only surfaces keep per-node anchors
                _copy2(pl_save, plane_anchors)
            ok = _ga_step(state, work, rod, damping, contact, tr, anchors, h, settings)
            if not ok:
                _copy1(pole_anchor, pa_save)
                if kind == PLANE:
                    _copy2(plane_anchors, pl_save)
                if sub >= max_sub:
                    status[0] = -1
                    return k
                sub *= 2
                done *= 2
                continue
            iters += int(newton[3])
            commit_anchors(kind, info, anchors)
            contact_now = 1.0 if info[0] > 0.0 else 0.0
            if contact_now != prev_contact or info[2] != prev_slip:
                newton[0] = 1.0
                steady = 0
            else:
                steady += 1
            prev_contact = contact_now
            prev_slip = info[2]
            _copy2(xn, x)
            _copy2(vn, v)
            _copy2(an, a)
            done += 1
        _write_tan(out, k + 1, x[1, 0] - x[0, 0], x[1, 1] - x[0, 1], x[1, 2] - x[0, 2], traj, k + 1)
        out[k + 1, 2] = info[0]
        out[k + 1, 3] = info[1]
        out[k + 1, 4] = info[2]
        if kind == POLE:
            out[k + 1, 5] = info[7]
            out[k + 1, 6] = info[8]
        else:
            out[k + 1, 5] = info[4]
            out[k + 1, 6] = info[5]
        out[k + 1, 7] = iters
        if state_every > 0 and (k + 1) % state_every == 0 and si < records.shape[0]:
            _copy2(records[si, 0], x)
            _copy2(records[si, 1], v)
            si += 1
        if stop_tan > 0.0 and abs(out[k + 1, 0]) >= stop_tan:
            status[0] = 1
            return k + 1
        n_free = n_free + 1 if info[0] == 0.0 else 0
        if stop_free > 0 and n_free >= stop_free:
            status[0] = 2
            return k + 1
        k += 1
    return nsteps


# ----------------------------------------------------------------------------------
# linear free flight (see vibrissa.whisker.modal)
# ----------------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def modal_advance(
    z, decay, out_modes, pivot, magnet_rest, steps, stop_tan, out, gain0, gain1, load0, load1
):
    """Advance complex modal amplitudes ``z`` by ``steps`` exact steps, in place.

    ``decay[k] = exp(lambda_k dt)``; ``out_modes`` (3, m) maps the amplitudes to the
    displacement of node 1 (the magnet end of the follicle's rigid edge) so that its
    position is ``magnet_rest + Re(out_modes @ z)``; ``pivot`` is node 0. Rows
    ``out[1..]`` receive [tan_x, tan_y, 0 (no contact force), nan (no contact
    point), 0, 0, 0, 0 (no Newton iterations)], in :func:`run_dynamics`' layout.
    Stops after the first step whose |tan_x| reaches ``stop_tan`` (if > 0). Returns
    the number of steps done.

    A load varying linearly over each step, from ``load0[k]`` to ``load1[k]``
    (arrays of at least ``steps`` values; empty: no load), drives the amplitudes
    through ``z' = lambda z + b load``: the exact step is ``z <- decay z + gain0
    load0[k] + gain1 (load1[k] - load0[k])`` with ``gain0 = b (decay - 1) /
    lambda`` and ``gain1 = b (decay - 1 - lambda dt) / (lambda^2 dt)``.
    """
    m = z.shape[0]
    loaded = load0.shape[0] > 0
    g0r = np.empty(m)
    g0i = np.empty(m)
    g1r = np.empty(m)
    g1i = np.empty(m)
    for j in range(m):
        g0r[j] = gain0[j].real
        g0i[j] = gain0[j].imag
        g1r[j] = gain1[j].real
        g1i[j] = gain1[j].imag
    # real and imaginary parts in separate arrays: plain multiply-adds
    zr = np.empty(m)
    zi = np.empty(m)
    dr = np.empty(m)
    di = np.empty(m)
    wr = np.empty((3, m))
    wi = np.empty((3, m))
    for j in range(m):
        zr[j] = z[j].real
        zi[j] = z[j].imag
        dr[j] = decay[j].real
        di[j] = decay[j].imag
        for c in range(3):
            wr[c, j] = out_modes[c, j].real
            wi[c, j] = out_modes[c, j].imag
    done = steps
    for k in range(steps):
        u0 = 0.0
        u1 = 0.0
        u2 = 0.0
        p0 = 0.0
        p1 = 0.0
        if loaded:
            p0 = load0[k]
            p1 = load1[k] - load0[k]
        for j in range(m):
            a = zr[j] * dr[j] - zi[j] * di[j]
            b = zr[j] * di[j] + zi[j] * dr[j]
            if loaded:
                a += g0r[j] * p0 + g1r[j] * p1
                b += g0i[j] * p0 + g1i[j] * p1
            # a decayed mode is set to zero before it reaches the subnormal range,
            # where floating-point arithmetic is very slow
            if abs(a) + abs(b) < 1e-250:
                a = 0.0
                b = 0.0
            zr[j] = a
            zi[j] = b
            u0 += wr[0, j] * a - wi[0, j] * b
            u1 += wr[1, j] * a - wi[1, j] * b
            u2 += wr[2, j] * a - wi[2, j] * b
        ez = magnet_rest[2] + u2 - pivot[2]
        out[k + 1, 0] = (magnet_rest[0] + u0 - pivot[0]) / ez
        out[k + 1, 1] = (magnet_rest[1] + u1 - pivot[1]) / ez
        out[k + 1, 2] = 0.0
        out[k + 1, 3] = np.nan
        for c in range(4, 8):
            out[k + 1, c] = 0.0
        if stop_tan > 0.0 and abs(out[k + 1, 0]) >= stop_tan:
            done = k + 1
            break
    for j in range(m):
        z[j] = zr[j] + 1j * zi[j]
    return done


@njit(cache=True)
def max_edge_rotation_sq(x, tangents):
    """The largest squared angle (rad^2) between an edge of ``x`` and its rest tangent.

    ``x`` (n, 3) are node positions, ``tangents`` (n - 1, 3) the edges' unit rest
    directions: every edge normalised, its dot product with the rest direction
    clipped to [-1, 1], the largest arc cosine squared
    (:meth:`vibrissa.whisker.modal.LinearModes.nonlinearity`).
    """
    cmin = 1.0
    for e in range(x.shape[0] - 1):
        d0 = x[e + 1, 0] - x[e, 0]
        d1 = x[e + 1, 1] - x[e, 1]
        d2 = x[e + 1, 2] - x[e, 2]
        ln = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        c = (d0 / ln) * tangents[e, 0] + (d1 / ln) * tangents[e, 1] + (d2 / ln) * tangents[e, 2]
        if not c >= cmin:  # also takes a NaN, which then fails the caller's test
            cmin = c
    return np.arccos(max(cmin, -1.0)) ** 2


@njit(cache=True)
def _transverse_into(u, tangents, out):
    """``u`` (flat, three per moving node) without its components along ``tangents``."""
    for i in range(tangents.shape[0]):
        t0 = tangents[i, 0]
        t1 = tangents[i, 1]
        t2 = tangents[i, 2]
        a = u[3 * i] * t0 + u[3 * i + 1] * t1 + u[3 * i + 2] * t2
        out[3 * i] = u[3 * i] - a * t0
        out[3 * i + 1] = u[3 * i + 1] - a * t1
        out[3 * i + 2] = u[3 * i + 2] - a * t2


@njit(cache=True)
def _energy(u, w, stiffness, mass):
    """``u . (K u) + w . (M w)`` over the moving degrees of freedom (``M`` dense)."""
    e = 0.0
    nd = u.shape[0]
    for i in range(nd):
        ku = 0.0
        mw = 0.0
        for j in range(nd):
            ku += stiffness[i, j] * u[j]
            mw += mass[i, j] * w[j]
        e += u[i] * ku + w[i] * mw
    return e


@njit(cache=True)
def modal_amplitudes(
    x, v, x_rest, dofs, mass, shapes, stiffness, tangents, inv_re, inv_im, z_re, z_im
):
    """Complex modal amplitudes of a state, and the energy fraction outside the modes.

    See :meth:`vibrissa.whisker.modal.LinearModes.amplitudes`: the displacement
    ``u`` and velocity ``w`` from rest over the moving degrees of freedom ``dofs``
    are projected on the mass-normalised ``shapes`` (``q = Phi^T M u``), the
    first-order amplitudes are ``inverse @ [q, qd]`` (written to ``z_re``, ``z_im``),
    and the transverse energy (bending, follicle, kinetic) of what the modes leave
    out is returned as a fraction of the state's.
    """
    nd = dofs.shape[0]
    m = shapes.shape[1]
    u = np.empty(nd)
    w = np.empty(nd)
    for k in range(nd):
        d = dofs[k]
        u[k] = x[d // 3, d % 3] - x_rest[d // 3, d % 3]
        w[k] = v[d // 3, d % 3]
    qq = np.zeros(2 * m)
    for k in range(nd):
        mu = 0.0
        mw = 0.0
        for q in range(nd):
            mu += mass[k, q] * u[q]
            mw += mass[k, q] * w[q]
        for j in range(m):
            qq[j] += shapes[k, j] * mu
            qq[m + j] += shapes[k, j] * mw
    ru = np.empty(nd)
    rw = np.empty(nd)
    for k in range(nd):
        a = u[k]
        b = w[k]
        for j in range(m):
            a -= shapes[k, j] * qq[j]
            b -= shapes[k, j] * qq[m + j]
        ru[k] = a
        rw[k] = b
    ut = np.empty(nd)
    wt = np.empty(nd)
    _transverse_into(u, tangents, ut)
    _transverse_into(w, tangents, wt)
    _transverse_into(ru, tangents, u)  # u, w reused for the transverse remainders
    _transverse_into(rw, tangents, w)
    total = _energy(ut, wt, stiffness, mass)
    lost = _energy(u, w, stiffness, mass)
    for i in range(2 * m):
        a = 0.0
        b = 0.0
        for j in range(2 * m):
            a += inv_re[i, j] * qq[j]
            b += inv_im[i, j] * qq[j]
        z_re[i] = a
        z_im[i] = b
    return 0.0 if total <= 0.0 else max(lost, 0.0) / total


@njit(cache=True)
def modal_state(z_re, z_im, vec_re, vec_im, x_rest, dofs, shapes, edge_lengths, x, v):
    """Positions and velocities (into ``x``, ``v``) of the rod for complex amplitudes.

    See :meth:`vibrissa.whisker.modal.LinearModes.state`: the modal displacements and
    velocities ``Re(vectors @ z)`` are superposed on the rest shape, then the edges
    keep the superposition's directions at their rest lengths, built out from the
    pivot, and lose their relative velocities along themselves.
    """
    n2 = z_re.shape[0]
    m = shapes.shape[1]
    qq = np.empty(n2)
    for i in range(n2):
        a = 0.0
        for j in range(n2):
            a += vec_re[i, j] * z_re[j] - vec_im[i, j] * z_im[j]
        qq[i] = a
    n = x_rest.shape[0]
    for i in range(n):
        for c in range(3):
            x[i, c] = x_rest[i, c]
            v[i, c] = 0.0
    for k in range(dofs.shape[0]):
        d = dofs[k]
        a = 0.0
        b = 0.0
        for j in range(m):
            a += shapes[k, j] * qq[j]
            b += shapes[k, j] * qq[m + j]
        x[d // 3, d % 3] += a
        v[d // 3, d % 3] = b
    # edge directions of the superposition, at rest length, from the pivot outwards;
    # relative velocities along each edge removed
    step = np.empty((n - 1, 3))
    dv = np.empty((n - 1, 3))
    for e in range(n - 1):
        t0 = x[e + 1, 0] - x[e, 0]
        t1 = x[e + 1, 1] - x[e, 1]
        t2 = x[e + 1, 2] - x[e, 2]
        ln = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        t0 /= ln
        t1 /= ln
        t2 /= ln
        d0 = v[e + 1, 0] - v[e, 0]
        d1 = v[e + 1, 1] - v[e, 1]
        d2 = v[e + 1, 2] - v[e, 2]
        a = t0 * d0 + t1 * d1 + t2 * d2
        step[e, 0] = edge_lengths[e] * t0
        step[e, 1] = edge_lengths[e] * t1
        step[e, 2] = edge_lengths[e] * t2
        dv[e, 0] = d0 - t0 * a
        dv[e, 1] = d1 - t1 * a
        dv[e, 2] = d2 - t2 * a
    for c in range(3):
        sx = 0.0
        sv = 0.0
        for e in range(n - 1):
            sx += step[e, c]
            sv += dv[e, c]
            x[e + 1, c] = x[0, c] + sx
            v[e + 1, c] = v[0, c] + sv


@njit(cache=True)
def interp_into(x, xp, fp, out):
    """``out[:] = np.interp(x, xp, fp)`` for finite data, bit for bit, in one pass.

    ``xp`` must increase. NumPy searches every point afresh; the object's trajectory
    is sampled at increasing times, so here the interval is carried from one point to
    the next (and searched for afresh only where ``x`` goes back).
    """
    m = xp.shape[0]
    j = 0
    for i in range(x.shape[0]):
        xi = x[i]
        if xi < xp[0]:
            out[i] = fp[0]
            continue
        if xi >= xp[m - 1]:
            out[i] = fp[m - 1]
            continue
        if xi < xp[j]:
            j = np.searchsorted(xp, xi, side="right") - 1
        while xp[j + 1] <= xi:
            j += 1
        if xp[j] == xi:
            out[i] = fp[j]
        else:
            slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
            out[i] = slope * (xi - xp[j]) + fp[j]


@njit(cache=True)
def first_possible_contact(
    kind, params, frame, h_max, traj, x_rest, radius, bound, margin, first_node
):
    """First row of ``traj`` at which the object could touch the whisker, or len(traj).

    The whisker stays within ``bound[i]`` (m) of its rest position ``x_rest[i]``
    (a decreasing bound of the free motion), so contact is impossible while every
    node's clearance from the object, less that bound, exceeds ``margin`` (m).
    A pole (``kind`` POLE, radius ``params[0]``, axis along y at ``traj[t, 0:2]`` =
    (x, z)) is checked against each segment of the free shaft; a plane (``kind``
    PLANE, rows of ``frame`` its normal and in-plane axes, origin ``traj[t, 0:3]``,
    heights at most ``h_max``) against each node from ``first_node``.
    """
    nt = traj.shape[0]
    n = x_rest.shape[0]
    # the clearance is 1-Lipschitz in the object's position: rows until the object
    # has moved by the clearance's excess over ``margin`` cannot touch and are skipped
    t = 0
    if kind == POLE:
        rp = params[0]
        while t < nt:
            px = traj[t, 0]
            pz = traj[t, 1]
            least = np.inf
            for j in range(1, n - 1):
                ax = x_rest[j, 0]
                az = x_rest[j, 2]
                bx = x_rest[j + 1, 0] - ax
                bz = x_rest[j + 1, 2] - az
                ll = bx * bx + bz * bz
                u = ((px - ax) * bx + (pz - az) * bz) / ll if ll > 0.0 else 0.0
                u = min(1.0, max(0.0, u))
                dx = ax + u * bx - px
                dz = az + u * bz - pz
                clear = (
                    np.sqrt(dx * dx + dz * dz)
                    - rp
                    - max(radius[j], radius[j + 1])
                    - max(bound[j], bound[j + 1])
                )
                if clear <= margin:
                    return t
                least = min(least, clear)
            slack = 0.5 * (least - margin)  # half: room for rounding
            moved = 0.0
            t += 1
            while t < nt:
                moved += np.sqrt(
                    (traj[t, 0] - traj[t - 1, 0]) ** 2 + (traj[t, 1] - traj[t - 1, 1]) ** 2
                )
                if moved >= slack:
                    break
                t += 1
        return nt
    if kind == PLANE:
        nrm = frame[0]
        while t < nt:
            least = np.inf
            for i in range(first_node, n):
                zc = (
                    nrm[0] * (x_rest[i, 0] - traj[t, 0])
                    + nrm[1] * (x_rest[i, 1] - traj[t, 1])
                    + nrm[2] * (x_rest[i, 2] - traj[t, 2])
                )
                clear = zc - h_max - radius[i] - bound[i]
                if clear <= margin:
                    return t
                least = min(least, clear)
            slack = 0.5 * (least - margin)
            moved = 0.0
            t += 1
            while t < nt:
                moved += abs(
                    nrm[0] * (traj[t, 0] - traj[t - 1, 0])
                    + nrm[1] * (traj[t, 1] - traj[t - 1, 1])
                    + nrm[2] * (traj[t, 2] - traj[t - 1, 2])
                )
                if moved >= slack:
                    break
                t += 1
        return nt
    return nt


# ------------------------------------------------------------------ surfaces (surfaces.py)
@njit(cache=True)
def dilate_axis(h, dx, R, k):
    """Grey dilation of a periodic height field ``h`` along axis 0 by a sphere of radius ``R``.

    The samples are spaced ``dx``, ``k`` of them each way. The result is what a probe tip of
    radius ``R`` can reach (:meth:`vibrissa.whisker.surfaces.Surface.for_tip`).
    """
    n, m = h.shape
    out = h.copy()
    for off in range(1, k + 1):
        drop = (off * dx) ** 2 / (2.0 * R)
        for i in range(n):
            ip = (i + off) % n
            im = (i - off) % n
            for j in range(m):
                a = h[ip, j] - drop
                b = h[im, j] - drop
                if a > out[i, j]:
                    out[i, j] = a
                if b > out[i, j]:
                    out[i, j] = b
    return out


@njit(cache=True)
def stamp_grains(H, dx, cu, cw, rad, top):
    """Raise the periodic height field ``H`` (spacing ``dx``) in place to spherical grain caps.

    The grains are centred at ``(cu, cw)`` with radii ``rad`` and tops ``top``
    (:func:`vibrissa.whisker.surfaces.make_surface`).
    """
    n, m = H.shape
    for g in range(cu.shape[0]):
        r = rad[g]
        ku = int(r / dx) + 1
        iu0 = int(cu[g] / dx)
        iw0 = int(cw[g] / dx)
        for a in range(-ku, ku + 1):
            for b in range(-ku, ku + 1):
                du = (iu0 + a) * dx - cu[g]
                dw = (iw0 + b) * dx - cw[g]
                q = r * r - du * du - dw * dw
                if q <= 0.0:
                    continue
                z = top[g] - r + np.sqrt(q)
                i = (iu0 + a) % n
                j = (iw0 + b) % m
                if z > H[i, j]:
                    H[i, j] = z


# ---------------------------------------------------------------- closed-loop whisking
# The whisking robots' RCP loop (vibrissa.robots.whisking.run_whisking) compiled whole:
# here, beside run_dynamics, because numba's cache does not see changes in callees from
# other files. Per control period: each side's command (the oscillator suppressed by the
# gating variable z and scaled by the contact-induced asymmetry), its servo, every
# whisker's rod for the period, then each side's contact filter (eq. 3.2) and gate (eq.
# 3.3); the arithmetic of the loop in Python, operation for operation. What goes is the
# per-period cost of calling the integrator from Python for every whisker (argument
# checks, interpolation, the dispatcher's typing of about forty arrays).


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
                    for c in range(6):
                        traj[k, c] = objects[w, c]
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
