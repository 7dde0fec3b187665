"""Exact linear free flight: the whisker's motion between contacts in modal coordinates.

A whisker that touches nothing, on a fixed base, is a linear system once its
deflection is small: ``M u'' + C u' + K u = 0`` for the displacement ``u`` from
rest, with the rod's mass matrix ``M``, the damping ``C`` (Rayleigh damping of the shaft
plus the follicle's rubber damper) and the stiffness ``K``, all the rod model's
own tangents at rest (:func:`~vibrissa.whisker._kernels.add_internal`). Its
solution is a sum of damped complex exponentials, so the free motion can be
advanced *exactly* by any number of steps at the cost of a few complex
multiplications per mode, instead of a nonlinear implicit step with Newton
iterations. :func:`vibrissa.whisker.simulate.simulate` hands the state over to
this propagator when three conditions hold, and back to the nonlinear rod as soon
as an object could touch the whisker:

* **No contact force** for a few steps, and no contact possible for at least a
  few more (:func:`~vibrissa.whisker._kernels.first_possible_contact`: the
  object's clearance from the whisker's rest shape, less a bound on how far the
  free whisker can move from it, must exceed a margin).
* **Linear enough**: no element is rotated from its rest direction by more than
  ``sqrt(linearity_tol)`` radians (the error of linearising a rotation grows with
  its square).
* **Within the kept modes**: the modes below ``cutoff_hz`` (well above the Hall
  sensor's band) carry all but ``energy_tol`` of the state's energy. Higher modes
  are damped within milliseconds by the shaft's material damping.

A whisker whose follicle housing turns (whisking, ``simulate(...,
base_motion=...)``) is, seen from the housing, the same linear system driven by
the Euler load of the housing's angular acceleration
(:meth:`LinearModes.housing_load`); the centrifugal and Coriolis loads are of order
``theta'^2 / omega_1^2`` and are left out, so the hand-over also needs the
housing's rate within ``sqrt(linearity_tol) omega_1``.

The modes are those of the undamped problem, mass-normalised (``K phi = w^2 M
phi``); the damping, which is not proportional (the follicle's damper differs from
the shaft's), couples them, so the kept modes are advanced as a first-order
system diagonalised once per whisker (complex eigenvalues ``lambda``).
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.linalg

from vibrissa.whisker._kernels import (
    BW,
    Damping,
    add_internal,
    max_edge_rotation_sq,
    modal_amplitudes,
    modal_state,
)
from vibrissa.whisker.rod import RodModel

__all__ = [
    "CUTOFF_HZ",
    "ENERGY_TOL",
    "LINEARITY_TOL",
    "LinearModes",
    "linear_modes",
]

#: Modes kept for free flight: all below this frequency (Hz). Twice the Nyquist
#: frequency of the fastest sensor rate used (4 kHz, chapter 5); the model's
#: material damping removes anything above within about a millisecond.
CUTOFF_HZ = 4000.0

#: Largest geometric nonlinearity (squared edge rotation from rest, rad^2; see
#: :meth:`LinearModes.nonlinearity`) at which free flight is handed to the linear
#: propagator: rotations up to 0.032 rad, where linearising their sine and cosine
#: errs by at most 0.1 %.
LINEARITY_TOL = 1e-3

#: Largest fraction of the state's energy allowed outside the kept modes at the
#: hand-over.
ENERGY_TOL = 1e-4


def _mv(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A @ b`` without BLAS.

    For these small sizes a threaded BLAS is slower (and on a busy machine much slower) than
    einsum's own single-threaded loop.
    """
    return np.einsum("ij,j->i", A, b)


def _banded_to_dense(S: np.ndarray) -> np.ndarray:
    n = S.shape[0]
    A = np.zeros((n, n))
    for off in range(-BW, BW + 1):
        rows = np.arange(max(0, -off), min(n, n - off))
        A[rows, rows + off] = S[rows, BW + off]
    return A


@dataclass(frozen=True)
class LinearModes:
    """The whisker linearised about rest, with its base fixed.

    Attributes
    ----------
    x_rest : ndarray, shape (n, 3)
        Rest positions (m).
    dofs : ndarray of int
        Flat indices (``3 * node + axis``) of the moving degrees of freedom.
    mass : ndarray, shape (len(dofs), len(dofs))
        Mass matrix over the moving degrees of freedom (kg).
    stiffness : ndarray
        Tangent stiffness ``K`` at rest over the moving degrees of freedom (N/m).
    shapes : ndarray, shape (len(dofs), m)
        Mass-normalised mode shapes of the kept modes: the transverse modes below
        ``cutoff_hz``.
    omega : ndarray, shape (m,)
        Their undamped angular frequencies (rad/s).
    eigenvalues : ndarray, shape (2 m,)
        Complex eigenvalues of the damped first-order system (1/s): ``n_pairs``
        with positive imaginary part, their conjugates in the same order, then the
        real ones (overdamped modes).
    vectors, inverse : ndarray, shape (2 m, 2 m)
        Its eigenvectors (columns; rows are the modal displacements, then the
        modal velocities) and their inverse.
    node_bound : ndarray, shape (n, 2 m)
        ``node_bound[i, k]``: the largest displacement of node ``i`` (m) per unit
        modulus of the complex amplitude ``k`` (the sum of its three components'
        moduli), so that ``node_bound @ |z|`` bounds every node's excursion.
    magnet : ndarray, shape (3, m + r)
        Displacement of node 1 (the magnet end of the follicle) per advanced
        amplitude (see :meth:`reduced`), conjugate partners folded in:
        ``Re(magnet @ reduced(z))`` is node 1's displacement.
    tangents : ndarray, shape (len(dofs) // 3, 3)
        Unit rest tangent at each moving node (of the edge arriving at it).
    edge_lengths : ndarray, shape (n - 1,)
        Rest length of each edge (m).
    n_pairs : int
        Number of complex-conjugate eigenvalue pairs.
    cutoff_hz : float
        The frequency below which modes are kept.
    """

    x_rest: np.ndarray
    dofs: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    shapes: np.ndarray
    omega: np.ndarray
    eigenvalues: np.ndarray
    vectors: np.ndarray
    inverse: np.ndarray
    node_bound: np.ndarray
    magnet: np.ndarray
    tangents: np.ndarray
    edge_lengths: np.ndarray
    n_pairs: int
    cutoff_hz: float

    @property
    def n_modes(self) -> int:
        """Number of kept (undamped) modes."""
        return int(self.omega.size)

    # -------------------------------------------------------------- state mapping
    def amplitudes(self, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, float]:
        """Complex modal amplitudes of positions ``x`` and velocities ``v`` (n, 3).

        Returns
        -------
        z : ndarray, shape (2 m,), complex
            The amplitudes of the kept modes.
        lost : float
            Fraction of the state's transverse energy (bending, follicle and
            kinetic) outside the kept modes. Motion along the rest tangent is left
            out: there it is the second-order shortening of a bent rod of fixed
            length, not an axial vibration.
        """
        inv_re, inv_im = self._inverse_parts
        z_re = np.empty(inv_re.shape[0])
        z_im = np.empty(inv_re.shape[0])
        frac = modal_amplitudes(
            self._nodes("x", x),
            self._nodes("v", v),
            self.x_rest,
            self.dofs,
            self.mass,
            self.shapes,
            self.stiffness,
            self.tangents,
            inv_re,
            inv_im,
            z_re,
            z_im,
        )
        return z_re + 1j * z_im, float(frac)

    @cached_property
    def _inverse_parts(self) -> tuple[np.ndarray, np.ndarray]:
        """Real and imaginary parts of :attr:`inverse`, contiguous, made once."""
        return (np.ascontiguousarray(self.inverse.real), np.ascontiguousarray(self.inverse.imag))

    @cached_property
    def _vector_parts(self) -> tuple[np.ndarray, np.ndarray]:
        """Real and imaginary parts of :attr:`vectors`, contiguous, made once."""
        return (np.ascontiguousarray(self.vectors.real), np.ascontiguousarray(self.vectors.imag))

    def housing_load(self) -> np.ndarray:
        """Rates of the complex amplitudes per unit angular acceleration of a turning housing.

        The housing is the follicle's; the rates are in 1/s per rad/s^2, shape (2 m,).

        Seen from the housing, which turns about ``y`` through the pivot, every node
        feels the Euler load ``-m (ŷ x r) theta''`` (``r`` its rest position from the
        pivot); mass-proportional damping, which acts on absolute velocities, adds
        ``-m (ŷ x r) alpha theta'``. The centrifugal and Coriolis loads are of order
        ``theta'^2 / omega_1^2`` against the elastic ones and are left out (the
        caller keeps the housing's rate within that bound).
        """
        r = self.x_rest - self.x_rest[0]
        g = np.column_stack([-r[:, 2], np.zeros(len(r)), r[:, 0]]).reshape(-1)[self.dofs]
        qd = _mv(self.shapes.T, _mv(self.mass, g))
        qq = np.concatenate([np.zeros_like(qd), qd])
        return _mv(self.inverse.real, qq) + 1j * _mv(self.inverse.imag, qq)

    def reduced(self, z: np.ndarray) -> np.ndarray:
        """The amplitudes that are advanced: one of each conjugate pair, then the real ones."""
        p = self.n_pairs
        return np.ascontiguousarray(np.concatenate([z[:p], z[2 * p :]]))

    def expanded(self, zr: np.ndarray) -> np.ndarray:
        """All amplitudes of a real state from :meth:`reduced` ones."""
        p = self.n_pairs
        return np.concatenate([zr[:p], np.conj(zr[:p]), zr[p:].real + 0j])

    def state(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (n, 3) of the rod for complex amplitudes ``z``.

        The linear superposition of mode shapes moves every node perpendicular to
        the rest shape, which stretches each edge by a second-order amount; the rod
        (nearly inextensible) would store that as axial strain energy and ring with
        it. So the edges keep the superposition's directions and their rest lengths,
        built out from the pivot, and relative velocities along each edge are
        removed: the rod's state agrees with the linear one to first order and
        carries no spurious axial energy. (The kept modes are all transverse; see
        :func:`linear_modes`.)
        """
        vec_re, vec_im = self._vector_parts
        z = np.asarray(z)
        if z.shape != (vec_re.shape[1],):
            raise ValueError(f"z must have shape ({vec_re.shape[1]},), got {z.shape}")
        x = np.empty_like(self.x_rest)
        v = np.empty_like(self.x_rest)
        modal_state(
            np.ascontiguousarray(z.real),
            np.ascontiguousarray(z.imag),
            vec_re,
            vec_im,
            self.x_rest,
            self.dofs,
            self.shapes,
            self.edge_lengths,
            x,
            v,
        )
        return x, v

    def nonlinearity(self, x: np.ndarray) -> float:
        """Geometric nonlinearity of shape ``x``: largest squared rotation (rad^2) of an edge.

        The rotation is measured from the edge's rest direction.

        The linearised elastic forces differ from the rod's by a relative amount of
        this order (the rotation's cosine and sine are linearised).
        """
        return float(max_edge_rotation_sq(self._nodes("x", x), self.tangents))

    def _nodes(self, name: str, a: np.ndarray) -> np.ndarray:
        """``a`` as a contiguous float array of one row per node, or ValueError.

        The check is needed because the compiled kernels do not check shapes.
        """
        out = np.ascontiguousarray(a, dtype=float)
        if out.shape != self.x_rest.shape:
            raise ValueError(f"{name} must have shape {self.x_rest.shape}, got {out.shape}")
        return out


_CACHE: weakref.WeakKeyDictionary[RodModel, LinearModes] = weakref.WeakKeyDictionary()


def linear_modes(model: RodModel, cutoff_hz: float = CUTOFF_HZ) -> LinearModes:
    """The linearised free whisker of ``model`` (computed once per model and cutoff).

    Parameters
    ----------
    model : RodModel
        The whisker.
    cutoff_hz : float
        Keep the modes below this frequency (Hz).

    Returns
    -------
    LinearModes
    """
    hit = _CACHE.get(model)
    if hit is not None and hit.cutoff_hz == cutoff_hz:
        return hit
    rod = model.rod_arrays()
    x = np.ascontiguousarray(model.x_rest, dtype=float)
    n = x.shape[0]
    zero = np.zeros_like(x)
    damping = Damping(*(float(c) for c in model.damping))
    mats = []
    for cD, cK in ((0.0, 1.0), (1.0, 0.0)):
        S = np.zeros((3 * n, 2 * BW + 1))
        add_internal(x, zero, rod, damping, np.zeros((n, 3)), S, cD, cK, True)
        mats.append(_banded_to_dense(S))
    dofs = np.array([3 * i + c for i in range(n) if model.free[i] for c in range(3)])
    K = mats[0][np.ix_(dofs, dofs)]
    K = 0.5 * (K + K.T)
    C = mats[1][np.ix_(dofs, dofs)]
    mass = np.kron(model.node_mass_matrix(), np.eye(3))[np.ix_(dofs, dofs)]
    w2, phi = scipy.linalg.eigh(K, mass)
    omega = np.sqrt(np.clip(w2, 0.0, None))
    # transverse modes only: the axial ones (the first near 3 kHz for the xy-robot
    # whisker) are not sensed by the magnet's tilt and, in a bent state, their
    # projection is the geometric shortening of the bent rod, not a vibration
    edges = np.diff(x, axis=0)
    edges /= np.linalg.norm(edges, axis=1)[:, None]
    moving = np.array([i for i in range(n) if model.free[i]])
    tangents = edges[moving - 1]
    # each mode's kinetic-energy fraction along the rest tangents (mass-normalised)
    sh = phi.reshape(-1, 3, phi.shape[1])
    axial = (tangents[:, :, None] * np.einsum("ic,ick->ik", tangents, sh)[:, None, :]).reshape(
        phi.shape
    )
    along = np.einsum("ik,ij,jk->k", axial, mass, axial)
    keep = (omega < 2 * np.pi * cutoff_hz) & (along < 0.5)
    omega, phi = omega[keep], phi[:, keep]
    m = omega.size
    Cm = phi.T @ C @ phi
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-np.diag(omega**2), -Cm]])
    lam, V = scipy.linalg.eig(A)
    # order: one of each conjugate pair (Im > 0), their conjugates in the same order,
    # then the real eigenvalues (overdamped modes); a real state has amplitudes
    # z[p + i] = conj(z[i]) and real z[2 p:], so only the first p and the real ones
    # need advancing (:meth:`LinearModes.advance_amplitudes`)
    tol = 1e-9 * np.abs(lam).max()
    upper = np.flatnonzero(lam.imag > tol)
    upper = upper[np.argsort(lam.imag[upper])]
    lower = np.array(
        [int(np.argmin(np.abs(lam - np.conj(lam[i])) + (lam.imag >= -tol) * 1e300)) for i in upper],
        dtype=int,
    )
    real = np.flatnonzero(np.abs(lam.imag) <= tol)
    order = np.concatenate([upper, lower, real])
    if np.unique(order).size != lam.size:
        raise RuntimeError("could not pair the complex eigenvalues of the free whisker")
    lam, V = lam[order], V[:, order]
    lam[2 * upper.size :] = lam[2 * upper.size :].real
    Vinv = np.linalg.inv(V)
    disp = np.zeros((3 * n, 2 * m), dtype=complex)
    disp[dofs] = phi @ V[:m]
    node_bound = np.abs(disp).reshape(n, 3, 2 * m).sum(axis=1)
    p = upper.size
    weight = np.concatenate([np.full(p, 2.0), np.ones(real.size)])
    reps = np.concatenate([np.arange(p), np.arange(2 * p, lam.size)])
    modes = LinearModes(
        x_rest=x.copy(),
        dofs=dofs,
        mass=mass,
        stiffness=K,
        shapes=phi,
        omega=omega,
        eigenvalues=lam,
        vectors=V,
        inverse=Vinv,
        node_bound=node_bound,
        magnet=np.ascontiguousarray(disp[3:6][:, reps] * weight),
        tangents=tangents,
        edge_lengths=np.linalg.norm(np.diff(x, axis=0), axis=1),
        n_pairs=int(p),
        cutoff_hz=float(cutoff_hz),
    )
    _CACHE[model] = modes
    return modes
