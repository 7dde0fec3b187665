"""A train/test split by recorded set, shared by the XY-robot experiments (chapters 4, 5)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Split"]


@dataclass(frozen=True)
class Split:
    """Which recorded sets train and test, and their trial indices.

    Attributes
    ----------
    train_set, test_set
        Values of the ``set`` coordinate.
    train_index, test_index : numpy.ndarray
        Sorted trial positions of each set.
    seed : int or None
        Seed that drew the assignment (``None`` when given explicitly).
    """

    train_set: Any
    test_set: Any
    train_index: np.ndarray
    test_index: np.ndarray
    seed: int | None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (set values, trial counts, seed; no indices)."""
        return {
            "train_set": self.train_set,
            "test_set": self.test_set,
            "n_train": int(self.train_index.shape[0]),
            "n_test": int(self.test_index.shape[0]),
            "seed": self.seed,
        }
