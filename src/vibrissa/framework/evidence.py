"""Evidence about one surface accumulated over contacts and whiskers (thesis 2.5, 7.1.2).

Each tip contact gives a posterior over joint surface classes ``(angle_deg,
texture_code)``. With contacts independent given the surface and a flat prior, the
posterior after ``n`` contacts is proportional to the product of the single-contact
posteriors; each is first floored at ``min_probability`` and renormalised, so one
over-confident contact (naive Bayes posteriors are nearly one-hot) cannot veto a
class. This is the rule of :func:`vibrissa.classify.accumulate_evidence` (Lepora et
al. 2012), one contact at a time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.special import logsumexp, softmax

from vibrissa._validate import in_range, positive

__all__ = ["EvidenceAccumulator", "floored_log_posterior"]


def floored_log_posterior(proba: Any, min_probability: float) -> np.ndarray:
    """Log of posteriors floored at ``min_probability`` and renormalised (last axis).

    Parameters
    ----------
    proba : array-like of shape (..., n_classes)
    min_probability : float

    Returns
    -------
    ndarray
        Same shape; ``logsumexp`` over the last axis is 0.
    """
    p = np.asarray(proba, dtype=float)
    lp = np.log(np.maximum(p, float(min_probability)))
    return lp - logsumexp(lp, axis=-1, keepdims=True)


class EvidenceAccumulator:
    """Running log posterior over joint surface classes, contact by contact.

    Parameters
    ----------
    classes : array-like of shape (n_classes, n_targets)
        The joint classes, e.g. ``(angle_deg, texture_code)`` rows.
    threshold : float, default=0.99
        The accumulator has decided once the best class' posterior is ``>=`` this.
    min_probability : float, default=1e-3
        Floor of each contact's posterior, in ``(0, 1)``.
    """

    def __init__(self, classes: Any, threshold: float = 0.99, min_probability: float = 1e-3):
        c = np.asarray(classes)
        if c.ndim == 1:
            c = c[:, None]
        if c.ndim != 2 or c.shape[0] < 1:
            raise ValueError(f"classes must have shape (n_classes, n_targets), got {c.shape}")
        self.classes = c
        self.threshold = positive("threshold", threshold)
        self.min_probability = in_range("min_probability", min_probability, 0.0, 1.0)
        if not 0.0 < self.min_probability < 1.0:
            raise ValueError(f"min_probability must lie in (0, 1), got {min_probability!r}")
        self.reset()

    def reset(self) -> None:
        """Forget every contact (a new surface)."""
        self._log_sum = np.zeros(self.classes.shape[0])
        self.n_contacts = 0
        self.whiskers: set[int] = set()

    def add(self, proba_row: Any, whisker: int) -> None:
        """Add one contact's posterior over :attr:`classes`.

        Parameters
        ----------
        proba_row : array-like of shape (n_classes,)
            Non-negative, finite (normalised or not: it is floored and renormalised).
        whisker : int
            The whisker that made the contact.
        """
        p = np.asarray(proba_row, dtype=float)
        if p.shape != (self.classes.shape[0],):
            raise ValueError(f"proba_row must have shape ({self.classes.shape[0]},), got {p.shape}")
        if not np.all(np.isfinite(p)) or np.any(p < 0):
            raise ValueError("proba_row must hold finite non-negative probabilities")
        self._log_sum = self._log_sum + floored_log_posterior(p, self.min_probability)
        self.n_contacts += 1
        self.whiskers.add(int(whisker))

    def posterior(self) -> np.ndarray:
        """Normalised posterior over :attr:`classes` (uniform before any contact)."""
        return softmax(self._log_sum)

    def best(self) -> tuple[np.ndarray, float]:
        """The most probable class row and its posterior."""
        post = self.posterior()
        i = int(np.argmax(post))
        return self.classes[i], float(post[i])

    @property
    def decided(self) -> bool:
        """Whether the best posterior has reached :attr:`threshold` (never before a contact)."""
        return self.n_contacts > 0 and self.best()[1] >= self.threshold
