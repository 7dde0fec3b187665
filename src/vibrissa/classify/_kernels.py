"""Numba kernels of the classifiers.

They compute the L1 template distances, the static beam's grid search, the naive Bayes
histograms and MiniRocket's PPV features.

The kernels give the same numbers, bit for bit, as the NumPy/SciPy code they
replaced, so the classifiers' predictions do not change:

- :func:`l1_distances` sums ``|a_j - b_j|`` over ``j`` in order, starting from 0,
  which is how :func:`scipy.spatial.distance.cdist` (``"cityblock"``) sums; it adds
  a block of features for two test rows at a time into their rows of sums, the
  templates along the inner (vectorised) loop, each in its own accumulator.
- :func:`beam_grid_errors` evaluates the static beam's radius ``r(q)`` with the same
  floating-point operations as :meth:`StaticBeamClassifier._grid_search
  <vibrissa.classify.StaticBeamClassifier>`, but not for every training trial: ``r``
  falls as the base moment grows, so with the trials sorted by moment the nearest
  class changes at ~100 positions, found by an analytic first guess and checked
  exactly, and the absolute errors of each run of trials are differences of prefix
  sums. The sums add the same terms in another order; the caller re-evaluates the
  grid points near the minimum the original way (exact when the class values are
  integers, e.g. whole millimetres, and a bound on the difference otherwise).
- :func:`histogram_counts` counts each trial's values per bin, with the naive
  Bayes' bin arithmetic, without the index arrays of ``numpy.bincount`` (a value
  more than 2**63 bins beyond the range now lands in the end bin it lies beyond;
  NumPy's integer conversion had put it in bin 0).
- :func:`minirocket_ppv` computes :class:`~vibrissa.classify.MiniRocketClassifier`'s
  convolutions with the float32 operations, in the order, of its NumPy code (the
  shared sum ``-(x_0 + x_1 + ... + x_8)``, then ``+ 3 x_a``, ``+ 3 x_b``, ``+ 3 x_c``)
  and counts the values above each bias, one trial at a time: a trial's features do
  not depend on the other trials of the call.

Why every kernel lives in this one module: see :mod:`vibrissa.whisker._kernels`
(numba's on-disk cache checks only the file of the function it compiled).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["beam_grid_errors", "histogram_counts", "l1_distances", "minirocket_ppv"]

#: Features per block of :func:`l1_distances` (the block of templates stays in L2 cache).
_FEATURES = 64
#: Templates per block of :func:`l1_distances` (two rows of sums stay in L1 cache).
_TEMPLATES = 512


@njit(cache=True, nogil=True)
def l1_distances(F, TT, out):  # pragma: no cover - compiled
    """``out[i, t] = sum_j |F[i, j] - TT[j, t]|``, summed over ``j`` in order from 0.0.

    Parameters
    ----------
    F : float64 array of shape (n, d)
        Test rows.
    TT : float64 array of shape (d, m), C-contiguous
        The templates, transposed.
    out : float64 array of shape (n, m), C-contiguous
        Filled in place.
    """
    n, d = F.shape
    m = TT.shape[1]
    out[:, :] = 0.0
    for t0 in range(0, m, _TEMPLATES):
        w = min(m, t0 + _TEMPLATES) - t0
        for j0 in range(0, d, _FEATURES):
            j1 = min(d, j0 + _FEATURES)
            i = 0
            while i + 1 < n:  # two test rows share each load of the templates
                o1 = out[i, t0 : t0 + w]
                o2 = out[i + 1, t0 : t0 + w]
                for j in range(j0, j1):
                    a1 = F[i, j]
                    a2 = F[i + 1, j]
                    row = TT[j, t0 : t0 + w]
                    for t in range(w):
                        r = row[t]
                        o1[t] += abs(a1 - r)
                        o2[t] += abs(a2 - r)
                i += 2
            if i < n:
                o1 = out[i, t0 : t0 + w]
                for j in range(j0, j1):
                    a1 = F[i, j]
                    row = TT[j, t0 : t0 + w]
                    for t in range(w):
                        o1[t] += abs(a1 - row[t])


@njit(cache=True, nogil=True)
def _radius(c, two_l, m):  # pragma: no cover - compiled
    # the operations of StaticBeamClassifier._grid_search, in its order
    return two_l / (1.0 + np.sqrt(1.0 + 4.0 * (c * m)))


@njit(cache=True, nogil=True)
def _first_at_or_below(c, two_l, m_sorted, thr, g):  # pragma: no cover - compiled
    """First position ``p`` with ``r(m_sorted[p]) <= thr``, walking from the guess ``g``."""
    n = m_sorted.size
    if g < n and _radius(c, two_l, m_sorted[g]) <= thr:
        while g > 0 and _radius(c, two_l, m_sorted[g - 1]) <= thr:
            g -= 1
    else:
        while g < n and not _radius(c, two_l, m_sorted[g]) <= thr:
            g += 1
    return g


@njit(cache=True, nogil=True)
def beam_grid_errors(
    kappa, length_mm, length_m2, m_sorted, mid, G, lookup, scale, out
):  # pragma: no cover - compiled
    """Mean absolute error of the snapped radius at every grid point ``(kappa[i], length[j])``.

    Parameters
    ----------
    kappa : float64 array of shape (K,)
        ``moment_scale / (C d)`` of the grid points (positive).
    length_mm, length_m2 : float64 arrays of shape (J,)
        Whisker lengths, mm, and ``(length_mm * 1e-3) ** 2`` as the caller computes it.
    m_sorted : float64 array of shape (n,)
        Base moments of the training trials, sorted ascending (non-negative, finite).
    mid : float64 array of shape (C - 1,)
        Midpoints between consecutive radial-distance classes.
    G : float64 array of shape (n + 1, C)
        ``G[p, k]``: sum of ``|class_k - true radius|`` over the first ``p`` trials of
        ``m_sorted``'s order.
    lookup : int64 array of shape (B + 1,)
        ``lookup[b]``: first position of ``m_sorted`` at or above
        ``m_sorted[0] + b / scale`` (a bucket index into the sorted moments).
    scale : float
        Buckets per unit moment (0 when all moments are equal and ``B`` is 1).
    out : float64 array of shape (K, J)
        Filled with the errors.
    """
    n = m_sorted.size
    C = mid.size + 1
    n_buckets = lookup.size - 1
    m0 = m_sorted[0]
    bound = np.empty(C + 1, dtype=np.int64)
    for i in range(kappa.size):
        for j in range(length_mm.size):
            c = kappa[i] * length_m2[j]
            two_l = 2.0 * length_mm[j]
            r_hi = _radius(c, two_l, m0)
            r_lo = _radius(c, two_l, m_sorted[n - 1])
            # bound[k]: first trial whose class is below k (class k = bound[k+1]..bound[k])
            bound[0] = n
            bound[C] = 0
            g = n
            for k in range(1, C):
                thr = mid[k - 1]
                if thr < r_lo:
                    bound[k] = n
                    continue
                if thr >= r_hi:
                    bound[k] = 0
                    continue
                # r(m) = thr at m = ((2L/thr - 1)^2 - 1) / (4 c): a guess, checked exactly
                u = two_l / thr - 1.0
                x = (u * u - 1.0) / (4.0 * c)
                fb = (x - m0) * scale
                if not x > m0:
                    guess = 0
                elif not fb < n_buckets:
                    guess = n
                else:
                    lo = lookup[int(fb)]
                    guess = lo + np.searchsorted(m_sorted[lo : lookup[int(fb) + 1]], x)
                g = _first_at_or_below(c, two_l, m_sorted, thr, min(guess, g))
                bound[k] = g
            total = 0.0
            for k in range(C):
                if bound[k] != bound[k + 1]:
                    total += G[bound[k], k] - G[bound[k + 1], k]
            out[i, j] = total / n


@njit(cache=True, nogil=True)
def histogram_counts(S, lo, width, n_bins, out):  # pragma: no cover - compiled
    """Per-trial histogram counts of every channel, added into ``out``.

    The bin of a value is ``floor((value - lo[ch]) / width[ch])`` (the operations of
    :class:`~vibrissa.classify.StationaryNaiveBayes` before this kernel), values
    beyond either end counted in the end bins.

    Parameters
    ----------
    S : float64 array of shape (n, channels, time)
        Finite values.
    lo, width : float64 arrays of shape (channels,)
        Lower edge and bin width of each channel.
    n_bins : int
        Bins per channel.
    out : float64 array of shape (n, channels * n_bins)
        Zeros on entry; ``out[i, ch * n_bins + k]`` counts trial ``i``'s values of
        channel ``ch`` in bin ``k``.
    """
    n, n_ch, n_t = S.shape
    top = n_bins - 1
    for i in range(n):
        for ch in range(n_ch):
            base = ch * n_bins
            low = lo[ch]
            w = width[ch]
            for t in range(n_t):
                f = np.floor((S[i, ch, t] - low) / w)
                if f <= 0.0:
                    k = 0
                elif f >= top:
                    k = top
                else:
                    k = int(f)
                out[i, base + k] += 1.0


@njit(cache=True, nogil=True)
def minirocket_ppv(Z, dilations, triples, biases, out):  # pragma: no cover - compiled
    """MiniRocket's proportions of positive values (PPV) of pooled trials.

    For trial ``i``, channel ``ch``, dilation ``d = dilations[di]`` and kernel ``k``
    (weight 2 at the taps ``triples[k]``, -1 elsewhere), the convolution at ``s`` is
    ``((A[s] + 3 x[s + a d]) + 3 x[s + b d]) + 3 x[s + c d]`` with
    ``A[s] = -(x[s] + x[s + d] + ... + x[s + 8 d])`` (summed from the first tap on),
    every operation in float32, for ``s`` in ``0 .. L - 1``, ``L = t - 8 d``.

    Parameters
    ----------
    Z : float32 array of shape (n, c, t), C-contiguous
        Pooled, centred trials.
    dilations : int64 array of shape (nd,)
        Dilations, each at most ``(t - 1) // 8``.
    triples : int64 array of shape (nk, 3)
        Taps of weight 2 of each kernel, ascending; kernels that share the first two
        taps adjacent (the order of :func:`itertools.combinations`).
    biases : float32 array of shape (nd, nk, c, nb)
        Biases of each dilation, kernel and channel.
    out : float32 array of shape (n, nd, nk, c, nb)
        Filled with ``count(conv > bias) / L``.
    """
    n, n_ch, t = Z.shape
    nd = dilations.size
    nk = triples.shape[0]
    nb = biases.shape[3]
    three = np.float32(3.0)
    A = np.empty(t, dtype=np.float32)
    P = np.empty(t, dtype=np.float32)
    G = np.empty((9, t), dtype=np.float32)
    for i in range(n):
        for ch in range(n_ch):
            x = Z[i, ch]
            for di in range(nd):
                d = dilations[di]
                L = t - 8 * d
                for s in range(L):
                    A[s] = x[s]
                for j in range(1, 9):
                    o = j * d
                    for s in range(L):
                        A[s] += x[s + o]
                for s in range(L):
                    A[s] = -A[s]
                for j in range(9):
                    o = j * d
                    g = G[j]
                    for s in range(L):
                        g[s] = three * x[s + o]
                pa = -1
                pb = -1
                for k in range(nk):
                    a = triples[k, 0]
                    b = triples[k, 1]
                    if a != pa or b != pb:
                        ga = G[a]
                        gb = G[b]
                        for s in range(L):
                            P[s] = (A[s] + ga[s]) + gb[s]
                        pa = a
                        pb = b
                    gc = G[triples[k, 2]]
                    for q in range(nb):
                        bias = biases[di, k, ch, q]
                        count = 0
                        for s in range(L):
                            if P[s] + gc[s] > bias:
                                count += 1
                        out[i, di, k, ch, q] = count / L
