"""Independent random streams of a session, derived from its seed.

Every random draw of a generated session comes from a stream
``numpy.random.SeedSequence(seed, spawn_key=key)``: the same scheme as
``SeedSequence.spawn`` but addressable, so that trial ``i`` gets its stream
without creating the streams of trials ``0 .. i-1``, whichever process runs it.
Keys start with a purpose, so streams of different purposes never coincide:

========================  ===============================  ==========================
purpose                   key                              draws
========================  ===============================  ==========================
:data:`TRIALS`            ``(TRIALS, trial_index)``        latency, positioning, noise
:data:`ORDER`             ``(ORDER,)``                     interleaving of the grid
:data:`SURFACES`          ``(SURFACES, texture_index)``    the grains of each sheet
:data:`IDENTIFY`          ``(IDENTIFY, group, k)``         trials of ``vibrissa identify``
========================  ===============================  ==========================

``texture_index`` is the texture's position in
:data:`vibrissa.whisker.surfaces.TEXTURES`, so two textures can never share a
sheet's stream.
"""

from __future__ import annotations

import numpy as np

__all__ = ["IDENTIFY", "ORDER", "SURFACES", "TRIALS", "stream", "trial_stream"]

TRIALS = 0
ORDER = 1
SURFACES = 2
IDENTIFY = 3


def stream(seed: int, *key: int) -> np.random.SeedSequence:
    """The stream with spawn key ``key`` of the session seeded ``seed``.

    Raises
    ------
    ValueError
        If ``seed`` or a key element is negative (SeedSequence takes non-negative
        integers).
    """
    if int(seed) < 0 or any(int(k) < 0 for k in key):
        raise ValueError(f"seed and stream keys must be non-negative, got {seed}, {key}")
    return np.random.SeedSequence(int(seed), spawn_key=tuple(int(k) for k in key))


def trial_stream(seed: int, group: int, index: int) -> np.random.SeedSequence:
    """Stream of trial ``index`` of an identification group ``group`` (see module doc)."""
    return stream(seed, IDENTIFY, group, index)
