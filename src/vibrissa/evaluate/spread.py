"""Results over several seeds: the mean of each figure and its spread.

A chapter-6 experiment repeats its session with several seeds and reports each figure
as the mean over the seeds, with the spread beside it. :func:`seed_spread` takes the
per-seed results (nested dicts and lists of the same shape) and gives two trees:

* the **mean tree**: the same shape, every number the mean over the seeds that gave a
  finite value (``None`` if none did); everything else as the first seed has it;
* the **spread tree**: the same paths, every number replaced by ``{"mean", "std",
  "min", "max", "n", "values"}`` (``std`` with one degree of freedom, ``values`` in seed
  order, a seed without a finite value as ``None``).

The results file stores the mean tree as its figures and the spread tree under the key
``spread``, so ``floor_texture.mean_correct.clockwise`` is the mean and
``floor_texture.spread.mean_correct.clockwise.values`` the per-seed values; the claims
ledger (:mod:`vibrissa.thesis.claims`) reads both.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["SPREAD_KEY", "seed_spread", "spread_leaf"]

#: Where a results file keeps the spread tree.
SPREAD_KEY = "spread"


def _number(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool)


def _finite(x: Any) -> float | None:
    if x is None or not _number(x):
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def spread_leaf(values: Sequence[Any]) -> dict[str, Any]:
    """``{"mean", "std", "min", "max", "n", "values"}`` of per-seed numbers.

    Parameters
    ----------
    values
        One number per seed; ``None``, NaN and infinities count as missing.

    Returns
    -------
    dict
        ``n`` finite values; ``mean``/``min``/``max`` ``None`` when ``n`` is 0 and ``std``
        ``None`` when ``n`` < 2.
    """
    vals = [_finite(x) for x in values]
    ok = [x for x in vals if x is not None]
    n = len(ok)
    mean = sum(ok) / n if n else None
    std = (
        math.sqrt(sum((x - mean) ** 2 for x in ok) / (n - 1))
        if n > 1 and mean is not None
        else None
    )
    return {
        "mean": mean,
        "std": std,
        "min": min(ok) if n else None,
        "max": max(ok) if n else None,
        "n": n,
        "values": vals,
    }


def seed_spread(per_seed: Sequence[Any]) -> tuple[Any, Any]:
    """The mean tree and the spread tree of per-seed results.

    Parameters
    ----------
    per_seed
        One result per seed, all of the same shape (dicts with the same keys, lists of the
        same length); a key or item missing in some seeds is treated as missing there.

    Returns
    -------
    mean_tree, spread_tree
        See the module's note; ``spread_tree`` holds only the numeric paths.

    Raises
    ------
    ValueError
        If ``per_seed`` is empty.
    """
    if len(per_seed) == 0:
        raise ValueError("per_seed must hold the results of at least one seed")
    first = per_seed[0]
    if isinstance(first, Mapping):
        mean: dict[str, Any] = {}
        spread: dict[str, Any] = {}
        for key in first:
            items = [r.get(key) if isinstance(r, Mapping) else None for r in per_seed]
            m, s = seed_spread(items)
            mean[key] = m
            if s is not None:
                spread[key] = s
        return mean, (spread or None)
    if isinstance(first, list | tuple):
        same = all(isinstance(r, list | tuple) and len(r) == len(first) for r in per_seed)
        if not same:
            return first, None
        pairs = [seed_spread([r[i] for r in per_seed]) for i in range(len(first))]
        spreads = [s for _, s in pairs]
        return [m for m, _ in pairs], (spreads if any(s is not None for s in spreads) else None)
    if _number(first) or first is None and any(_number(r) for r in per_seed):
        leaf = spread_leaf(per_seed)
        return leaf["mean"], leaf
    return first, None
