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
"""

from __future__ import annotations

import numpy as np
from numba import njit

BW = 8  # half bandwidth of the tangent matrices (3 DOF per node, 3-node stencil)

# contact kinds
NO_CONTACT = 0
POLE = 1
PLANE = 2


# ----------------------------------------------------------------------------------
# banded linear algebra (no pivoting: the iteration matrices are dominated by
# positive-definite stiffness and mass terms)
# ----------------------------------------------------------------------------------
@njit(cache=True)
def band_add_block(S, a, b, blk, coef):
    """Add ``coef * blk`` (3x3) to the (node a, node b) block of band matrix ``S``."""
    for r in range(3):
        row = 3 * a + r
        for c in range(3):
            S[row, BW + 3 * b + c - row] += coef * blk[r, c]


@njit(cache=True)
def band_solve(A, rhs):
    """Solve ``A x = rhs`` in place for a band matrix (LU without pivoting).

    Returns False if a pivot is not finite or vanishes.
    """
    n = A.shape[0]
    for k in range(n):
        piv = A[k, BW]
        if not (abs(piv) > 1e-300) or not np.isfinite(piv):
            return False
        iend = min(n, k + BW + 1)
        for i in range(k + 1, iend):
            lik = A[i, BW + k - i] / piv
            if lik != 0.0:
                A[i, BW + k - i] = lik
                for j in range(k + 1, iend):
                    A[i, BW + j - i] -= lik * A[k, BW + j - k]
    for i in range(n):
        s = rhs[i]
        for k in range(max(0, i - BW), i):
            s -= A[i, BW + k - i] * rhs[k]
        rhs[i] = s
    for i in range(n - 1, -1, -1):
        s = rhs[i]
        for j in range(i + 1, min(n, i + BW + 1)):
            s -= A[i, BW + j - i] * rhs[j]
        rhs[i] = s / A[i, BW]
    return True


# ----------------------------------------------------------------------------------
# elastic and damping elements
# ----------------------------------------------------------------------------------
@njit(cache=True)
def _unit(e):
    n = np.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return e / n, n


@njit(cache=True)
def _proj(t):
    P = np.eye(3)
    for i in range(3):
        for j in range(3):
            P[i, j] -= t[i] * t[j]
    return P


@njit(cache=True)
def _bend_hessian_self(P, t, d, length, sign):
    """Second-derivative block of ``k|d|^2`` w.r.t. one edge, divided by 2k.

    ``sign`` is +1 for the trailing edge (d = t2 - t1 depends on -t1) and -1 for the
    leading edge.
    """
    Pd = P @ d
    a = t[0] * d[0] + t[1] * d[1] + t[2] * d[2]
    H = np.empty((3, 3))
    inv = 1.0 / (length * length)
    for i in range(3):
        for j in range(3):
            H[i, j] = (P[i, j] + sign * (Pd[i] * t[j] + t[i] * Pd[j] + a * P[i, j])) * inv
    return H


@njit(cache=True)
def add_internal(x, v, kb, kf, axis, L0, EA, mass, alpha_d, beta_d, F, S, cD, cK, jac):
    """Add elastic and damping forces to ``F`` and, if ``jac``, ``cD D + cK K`` to ``S``.

    ``kb[i]`` is the bending constant at node i (i = 1..n-2), ``kf`` the follicle's,
    ``axis`` the follicle's rest direction, ``L0``/``EA`` the edges' rest lengths and
    axial rigidities, ``mass`` the lumped node masses.
    """
    n = x.shape[0]
    # --- stretching of every edge
    for e in range(n - 1):
        a = e
        b = e + 1
        ev = x[b] - x[a]
        t, ln = _unit(ev)
        ka = EA[e] / L0[e]
        fmag = ka * (ln - L0[e])
        dv = v[b] - v[a]
        rate = t[0] * dv[0] + t[1] * dv[1] + t[2] * dv[2]
        fmag += beta_d * ka * rate
        for c in range(3):
            F[a, c] += fmag * t[c]
            F[b, c] -= fmag * t[c]
        if jac:
            geo = 1.0 - L0[e] / ln
            H = np.empty((3, 3))
            Dm = np.empty((3, 3))
            for i in range(3):
                for j in range(3):
                    tt = t[i] * t[j]
                    pij = (1.0 if i == j else 0.0) - tt
                    H[i, j] = ka * (tt + geo * pij)
                    Dm[i, j] = beta_d * ka * tt
            for i in range(3):
                for j in range(3):
                    H[i, j] = cK * H[i, j] + cD * Dm[i, j]
            band_add_block(S, a, a, H, 1.0)
            band_add_block(S, b, b, H, 1.0)
            band_add_block(S, a, b, H, -1.0)
            band_add_block(S, b, a, H, -1.0)
    # --- follicle: k_f/2 |t0 - axis|^2 ; only node 1 moves (node 0 is the pivot)
    e2 = x[1] - x[0]
    t2, l2 = _unit(e2)
    P2 = _proj(t2)
    k = 0.5 * kf
    d = t2 - axis
    g = (P2 @ d) / l2  # dd/de2 applied: gradient of |d|^2 / 2
    de2 = v[1] - v[0]
    ddot = (P2 @ de2) / l2
    rd = (P2 @ ddot) / l2
    for c in range(3):
        f = -2.0 * k * g[c] - 2.0 * k * beta_d * rd[c]
        F[1, c] += f
        F[0, c] -= f
    if jac:
        Hs = _bend_hessian_self(P2, t2, d, l2, -1.0)
        JJ = P2 / (l2 * l2)
        H = np.empty((3, 3))
        for i in range(3):
            for j in range(3):
                H[i, j] = 2.0 * k * (cK * Hs[i, j] + cD * beta_d * JJ[i, j])
        band_add_block(S, 1, 1, H, 1.0)
    # --- bending at nodes 1..n-2 between edge i-1 (a->b) and edge i (b->c)
    C = np.array([[-1.0, 0.0], [1.0, -1.0], [0.0, 1.0]])
    for i in range(1, n - 1):
        k = kb[i]
        if k == 0.0:
            continue
        a = i - 1
        b = i
        c = i + 1
        t1, l1 = _unit(x[b] - x[a])
        t2, l2 = _unit(x[c] - x[b])
        P1 = _proj(t1)
        P2 = _proj(t2)
        d = t2 - t1
        g1 = -(P1 @ d) / l1  # (dd/de1)^T d
        g2 = (P2 @ d) / l2
        de1 = v[b] - v[a]
        de2 = v[c] - v[b]
        ddot = -(P1 @ de1) / l1 + (P2 @ de2) / l2
        r1 = -(P1 @ ddot) / l1
        r2 = (P2 @ ddot) / l2
        # generalised forces on e1, e2
        fe1 = -2.0 * k * (g1 + beta_d * r1)
        fe2 = -2.0 * k * (g2 + beta_d * r2)
        for cc in range(3):
            F[a, cc] += -fe1[cc]
            F[b, cc] += fe1[cc] - fe2[cc]
            F[c, cc] += fe2[cc]
        if jac:
            J11 = P1 / (l1 * l1)
            J22 = P2 / (l2 * l2)
            J12 = -(P1 @ P2) / (l1 * l2)
            G1 = _bend_hessian_self(P1, t1, d, l1, 1.0)
            G2 = _bend_hessian_self(P2, t2, d, l2, -1.0)
            He = np.zeros((6, 6))
            for p in range(3):
                for q in range(3):
                    He[p, q] = 2.0 * k * (cK * G1[p, q] + cD * beta_d * J11[p, q])
                    He[3 + p, 3 + q] = 2.0 * k * (cK * G2[p, q] + cD * beta_d * J22[p, q])
                    He[p, 3 + q] = 2.0 * k * (cK + cD * beta_d) * J12[p, q]
                    He[3 + q, p] = He[p, 3 + q]
            nodes = (a, b, c)
            blk = np.empty((3, 3))
            for pn in range(3):
                for qn in range(3):
                    for p in range(3):
                        for q in range(3):
                            s = 0.0
                            for ie in range(2):
                                cpi = C[pn, ie]
                                if cpi == 0.0:
                                    continue
                                for je in range(2):
                                    cqj = C[qn, je]
                                    if cqj == 0.0:
                                        continue
                                    s += cpi * cqj * He[3 * ie + p, 3 * je + q]
                            blk[p, q] = s
                    band_add_block(S, nodes[pn], nodes[qn], blk, 1.0)
    # --- mass-proportional damping
    for i in range(n):
        for c in range(3):
            F[i, c] -= alpha_d * mass[i] * v[i, c]
        if jac:
            for c in range(3):
                S[3 * i + c, BW] += cD * alpha_d * mass[i]


# ----------------------------------------------------------------------------------
# contacts
# ----------------------------------------------------------------------------------
@njit(cache=True)
def _add_weighted(S, j, w, blk, coef):
    """Add coef * w_p w_q blk to the blocks of nodes (j, j+1) x (j, j+1)."""
    for p in range(2):
        for q in range(2):
            ww = w[p] * w[q] * coef
            if ww != 0.0:
                band_add_block(S, j + p, j + q, blk, ww)


@njit(cache=True)
def add_pole(x, v, radius, s_rest, pole, pole_v, pole_radius, kn, cn, mu, kt, anchor,
             F, S, cD, cK, jac, info):
    """Point contact with a thin pole parallel to ``y`` at ``(pole[0], pole[1])`` in x-z.

    Friction is elasto-plastic Coulomb: a tangential spring ``kt`` from a stick anchor
    (``anchor[0]`` whisker arc length, ``anchor[1]`` pole coordinate ``y``,
    ``anchor[2]`` > 0 when the anchor is valid); when the spring force would exceed
    ``mu * N`` the contact slips. The anchor *proposed* for the end of the step is
    written to ``info[4:7]``; the caller commits it once the step has converged.
    ``info`` receives [normal force N, arc length of contact (m), slipping flag,
    gap (m), new anchor s, new anchor y, anchor valid, fx, fz].
    """
    n = x.shape[0]
    best = 1e300
    bj = -1
    bu = 0.0
    for j in range(1, n - 1):
        ax = x[j, 0]
        az = x[j, 2]
        bx = x[j + 1, 0] - ax
        bz = x[j + 1, 2] - az
        px = pole[0] - ax
        pz = pole[1] - az
        ll = bx * bx + bz * bz
        u = (px * bx + pz * bz) / ll if ll > 0 else 0.0
        u = min(1.0, max(0.0, u))
        qx = ax + u * bx - pole[0]
        qz = az + u * bz - pole[1]
        dist = np.sqrt(qx * qx + qz * qz)
        gap = dist - pole_radius - ((1.0 - u) * radius[j] + u * radius[j + 1])
        if gap < best:
            best = gap
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
    q = (1.0 - u) * x[j] + u * x[j + 1]
    s_c = (1.0 - u) * s_rest[j] + u * s_rest[j + 1]
    info[1] = s_c
    if best >= 0.0:
        return
    nx = q[0] - pole[0]
    nz = q[2] - pole[1]
    nd = np.sqrt(nx * nx + nz * nz)
    if nd == 0.0:
        return
    nvec = np.array([nx / nd, 0.0, nz / nd])
    w = np.array([1.0 - u, u])
    vq = (1.0 - u) * v[j] + u * v[j + 1]
    vrel = vq - pole_v
    vn = vrel[0] * nvec[0] + vrel[2] * nvec[2]
    pen = -best
    damp = -cn * vn if vn < 0.0 else 0.0
    fn = kn * pen + damp
    if fn < 0.0:
        fn = 0.0
    # tangential directions: along the whisker (in contact plane) and along the pole (y)
    tw, _ = _unit(x[j + 1] - x[j])
    tn = tw[0] * nvec[0] + tw[2] * nvec[2]
    for c in range(3):
        tw[c] -= tn * nvec[c]
    tw, _ = _unit(tw)
    if anchor[2] > 0.0:
        rel_s = -(s_c - anchor[0])
        rel_y = q[1] - anchor[1]
    else:
        rel_s = 0.0
        rel_y = 0.0
    ft_s = -kt * rel_s
    ft_y = -kt * rel_y
    ftm = np.sqrt(ft_s * ft_s + ft_y * ft_y)
    slipping = False
    lim = mu * fn
    if ftm > lim:
        slipping = True
        scale = lim / ftm
        ft_s *= scale
        ft_y *= scale
        rel_s *= scale
        rel_y *= scale
    fvec = np.empty(3)
    for c in range(3):
        fvec[c] = fn * nvec[c] + ft_s * tw[c]
    fvec[1] += ft_y
    for c in range(3):
        F[j, c] += w[0] * fvec[c]
        F[j + 1, c] += w[1] * fvec[c]
    info[0] = fn
    info[2] = 1.0 if slipping else 0.0
    info[4] = s_c + rel_s
    info[5] = q[1] - rel_y
    info[6] = 1.0
    info[7] = fvec[0]
    info[8] = fvec[2]
    if jac:
        blk = np.empty((3, 3))
        ey = np.array([0.0, 1.0, 0.0])
        if slipping:
            # sliding: friction magnitude follows the normal force (non-symmetric term)
            fdir = np.empty(3)
            for c in range(3):
                fdir[c] = (ft_s * tw[c] + ft_y * ey[c]) / max(lim, 1e-300)
            for p in range(3):
                for r in range(3):
                    blk[p, r] = cK * (kn * nvec[p] * nvec[r] + mu * kn * fdir[p] * nvec[r])
                    if vn < 0.0:
                        blk[p, r] += cD * cn * nvec[p] * nvec[r]
        else:
            for p in range(3):
                for r in range(3):
                    blk[p, r] = cK * (kn * nvec[p] * nvec[r] + kt * (tw[p] * tw[r] + ey[p] * ey[r]))
                    if vn < 0.0:
                        blk[p, r] += cD * cn * nvec[p] * nvec[r]
        _add_weighted(S, j, w, blk, 1.0)


@njit(cache=True)
def _height(H, du, dw, U, W):
    """Bilinear height and slopes of a periodic height field at surface coords (U, W)."""
    nu = H.shape[0]
    nw = H.shape[1]
    fu = U / du
    fw = W / dw
    iu = int(np.floor(fu))
    iw = int(np.floor(fw))
    ru = fu - iu
    rw = fw - iw
    i0 = iu % nu
    i1 = (iu + 1) % nu
    k0 = iw % nw
    k1 = (iw + 1) % nw
    h00 = H[i0, k0]
    h10 = H[i1, k0]
    h01 = H[i0, k1]
    h11 = H[i1, k1]
    h = (1 - ru) * (1 - rw) * h00 + ru * (1 - rw) * h10 + (1 - ru) * rw * h01 + ru * rw * h11
    hu = ((1 - rw) * (h10 - h00) + rw * (h11 - h01)) / du
    hw = ((1 - ru) * (h01 - h00) + ru * (h11 - h10)) / dw
    return h, hu, hw


@njit(cache=True)
def add_plane(x, v, radius, origin, origin_v, nrm, tu, tw, H, du, dw, kn, cn, mu, kt,
              anchors, F, S, cD, cK, jac, info, first_node):
    """Contact of every node from ``first_node`` on with a (rough) plane.

    The plane passes through ``origin`` (moving with velocity ``origin_v``) with unit
    normal ``nrm`` (pointing toward the whisker) and in-plane unit vectors ``tu``,
    ``tw``; ``H`` is a periodic height field (m) on a grid of spacing ``du``, ``dw``
    in surface coordinates. ``anchors[i] = (U, W, valid)`` are the stick anchors of
    node i; proposed new anchors go to ``anchors[i, 3:6]``. ``info`` receives
    [total normal force, number of nodes in contact, number slipping, min gap,
    force x, force z].
    """
    n = x.shape[0]
    info[0] = 0.0
    info[1] = 0.0
    info[2] = 0.0
    info[3] = 1e300
    info[4] = 0.0
    info[5] = 0.0
    for i in range(first_node, n):
        r = x[i] - origin
        U = r[0] * tu[0] + r[1] * tu[1] + r[2] * tu[2]
        W = r[0] * tw[0] + r[1] * tw[1] + r[2] * tw[2]
        Z = r[0] * nrm[0] + r[1] * nrm[1] + r[2] * nrm[2]
        h, hu, hw = _height(H, du, dw, U, W)
        gap = Z - h - radius[i]
        if gap < info[3]:
            info[3] = gap
        anchors[i, 5] = 0.0
        if gap >= 0.0:
            continue
        nl = nrm - hu * tu - hw * tw
        nl, _ = _unit(nl)
        vrel = v[i] - origin_v
        vn = vrel[0] * nl[0] + vrel[1] * nl[1] + vrel[2] * nl[2]
        damp = -cn * vn if vn < 0.0 else 0.0
        fn = kn * (-gap) + damp
        if fn < 0.0:
            fn = 0.0
        # local tangent directions
        a1 = tu - (tu[0] * nl[0] + tu[1] * nl[1] + tu[2] * nl[2]) * nl
        a1, _ = _unit(a1)
        a2 = np.empty(3)
        a2[0] = nl[1] * a1[2] - nl[2] * a1[1]
        a2[1] = nl[2] * a1[0] - nl[0] * a1[2]
        a2[2] = nl[0] * a1[1] - nl[1] * a1[0]
        if anchors[i, 2] > 0.0:
            ru = U - anchors[i, 0]
            rw = W - anchors[i, 1]
        else:
            ru = 0.0
            rw = 0.0
        # express the surface-coordinate slip in the local tangent frame
        sgn = a2[0] * tw[0] + a2[1] * tw[1] + a2[2] * tw[2]
        fu = -kt * ru
        fw = -kt * rw
        fm = np.sqrt(fu * fu + fw * fw)
        lim = mu * fn
        slipping = fm > lim
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
                for q in range(3):
                    if slipping:
                        fdir = (fu * a1[p] + fw * sgn * a2[p]) / max(lim, 1e-300)
                        blk[p, q] = cK * (kn * nl[p] * nl[q] + mu * kn * fdir * nl[q])
                    else:
                        blk[p, q] = cK * (kn * nl[p] * nl[q]
                                          + kt * (a1[p] * a1[q] + a2[p] * a2[q]))
                    if vn < 0.0:
                        blk[p, q] += cD * cn * nl[p] * nl[q]
            band_add_block(S, i, i, blk, 1.0)
