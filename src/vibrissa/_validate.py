"""Small checks for user-supplied parameters, raising errors that name them."""

from __future__ import annotations

import math
from numbers import Real

import numpy as np


def finite(name: str, value: float) -> float:
    """Return ``value`` as float, or raise ``ValueError`` naming ``name`` if not finite."""
    if isinstance(value, bool) or not isinstance(value, Real | np.floating | np.integer):
        raise TypeError(f"{name} must be a real number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def positive(name: str, value: float) -> float:
    """Return ``value`` as float, or raise ``ValueError`` if it is not finite and > 0."""
    v = finite(name, value)
    if v <= 0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    return v


def non_negative(name: str, value: float) -> float:
    """Return ``value`` as float, or raise ``ValueError`` if it is not finite and >= 0."""
    v = finite(name, value)
    if v < 0:
        raise ValueError(f"{name} must be non-negative, got {value!r}")
    return v


def in_range(name: str, value: float, low: float, high: float, unit: str = "") -> float:
    """Return ``value`` as float, or raise ``ValueError`` if outside ``[low, high]``."""
    v = finite(name, value)
    if not low <= v <= high:
        u = f" {unit}" if unit else ""
        raise ValueError(f"{name} must lie in [{low}, {high}]{u}, got {value!r}")
    return v


def finite_array(name: str, values: np.ndarray) -> np.ndarray:
    """Return ``values`` as a float array, or raise ``ValueError`` if any entry is NaN/inf."""
    arr = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(arr)):
        bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr)))
        raise ValueError(f"{name} contains {bad} NaN or infinite value(s)")
    return arr
