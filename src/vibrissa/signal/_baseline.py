"""Baseline removal for Hall-effect sensor traces.

The Hall sensor outputs 2.5 V at rest (thesis 3.2.3); a deflection is the
departure from that level.
"""

from __future__ import annotations

import numpy as np

from vibrissa._validate import finite

__all__ = ["HALL_REST_V", "remove_baseline"]

#: Rest output of the Hall-effect sensor, V (thesis 3.2.3: half of the 5 V supply).
HALL_REST_V = 2.5


def remove_baseline(
    x: np.ndarray,
    rest_v: float | None = HALL_REST_V,
    n_pre_samples: int | None = None,
) -> np.ndarray:
    """Subtract the rest level or the pre-contact mean along the last axis.

    Parameters
    ----------
    x
        Signal(s), time last, V.
    rest_v
        Constant rest level to subtract, V (default 2.5 V, the Hall sensor's
        rest output). Ignored when ``n_pre_samples`` is given.
    n_pre_samples
        If given, subtract instead the mean of the first ``n_pre_samples``
        samples of each trace (the pre-contact part of a peak-aligned trial).

    Returns
    -------
    numpy.ndarray
        Deflection relative to rest, same shape as ``x``.
    """
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 0:
        raise ValueError("x must have at least one (time) axis, got a scalar")
    if n_pre_samples is not None:
        if (
            isinstance(n_pre_samples, bool)
            or not isinstance(n_pre_samples, int | np.integer)
            or not 1 <= n_pre_samples <= arr.shape[-1]
        ):
            raise ValueError(
                f"n_pre_samples must be an integer in [1, {arr.shape[-1]}], got {n_pre_samples!r}"
            )
        return arr - arr[..., :n_pre_samples].mean(axis=-1, keepdims=True)
    if rest_v is None:
        raise ValueError("give rest_v or n_pre_samples")
    return arr - finite("rest_v", rest_v)
