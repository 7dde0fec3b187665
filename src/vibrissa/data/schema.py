"""Schema facts every layer needs: texture codes and the ``whisker`` attribute.

These are facts of the data, not of the simulator: classifiers and evaluations
read them from a dataset whether it was simulated or imported, so they live here
and ``classify`` / ``evaluate`` never import :mod:`vibrissa.whisker`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["TEXTURE_CODES", "decode_texture", "encode_texture", "parse_whisker"]

#: Texture name -> integer code in label rows, smooth to coarse: the chapter-5
#: surfaces (thesis 5.2) in order of grain size (aluminium, then P600, P180, P80
#: sandpaper). ``vibrissa.whisker.surfaces.TEXTURES`` defines the same names; a test
#: checks that their grain sizes give this order.
TEXTURE_CODES: dict[str, int] = {"aluminium": 0, "p600": 1, "p180": 2, "p80": 3}


def encode_texture(names: Any) -> np.ndarray:
    """Integer codes (:data:`TEXTURE_CODES`) of texture names.

    Parameters
    ----------
    names : array-like of str

    Returns
    -------
    ndarray of int

    Raises
    ------
    ValueError
        Naming the unknown textures.
    """
    arr = np.asarray(names).astype(str)
    unknown = sorted(set(arr.ravel().tolist()) - set(TEXTURE_CODES))
    if unknown:
        raise ValueError(f"unknown texture(s) {unknown}; known: {list(TEXTURE_CODES)}")
    if not arr.size:
        return np.zeros(arr.shape, dtype=int)
    return np.vectorize(TEXTURE_CODES.__getitem__, otypes=[int])(arr)


def decode_texture(codes: Any) -> np.ndarray:
    """Texture names of integer codes (inverse of :func:`encode_texture`).

    Parameters
    ----------
    codes : array-like of int (floats holding integers are accepted)

    Returns
    -------
    ndarray of str
    """
    names = np.array(list(TEXTURE_CODES))
    c = np.asarray(codes, dtype=float)
    if not np.all((c == np.round(c)) & (c >= 0) & (c < len(names))):
        raise ValueError(f"texture codes must be integers in [0, {len(names) - 1}]")
    return names[c.astype(int)]


def parse_whisker(value: Any, *, name: str = "whisker") -> dict[str, Any]:
    """The ``whisker`` attribute of a dataset as a dict.

    Parameters
    ----------
    value : str, mapping or None
        The attribute: JSON text (as stored in NetCDF) or an already parsed mapping.
    name : str
        What to call the value in error messages.

    Returns
    -------
    dict
        ``{}`` for ``None`` or an empty string.

    Raises
    ------
    ValueError
        When the text is not valid JSON or does not hold an object.
    """
    if value is None or (isinstance(value, str) and not value.strip()):
        return {}
    if isinstance(value, Mapping):
        return dict(value)
    if not isinstance(value, str):
        raise ValueError(f"{name} must be a JSON string or a mapping, got {type(value).__name__}")
    try:
        out = json.loads(value)
    except ValueError as exc:
        raise ValueError(f"{name} is not valid JSON: {exc}") from None
    if not isinstance(out, dict):
        raise ValueError(f"{name} must hold a JSON object, got {type(out).__name__}")
    return out
