"""Typed, JSON-ready reports of the framework: one :class:`ContactReport` per contact.

Every report has ``to_dict()`` (plain JSON types: dict keys are strings) and
``from_dict()``, which round-trip exactly: ``R.from_dict(r.to_dict()) == r``, also
after ``json.loads(json.dumps(...))`` (float dict keys are written with ``repr``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "ContactReport",
    "SurfaceEvidence",
    "WhatEstimate",
    "WhereEstimate",
    "marginal",
    "marginal_interval",
]


def marginal(values: Any, proba: Any) -> tuple[np.ndarray, np.ndarray]:
    """Marginal posterior over the distinct ``values`` of the joint classes.

    Parameters
    ----------
    values : array-like of shape (n_classes,)
        The target's value in each joint class.
    proba : array-like of shape (n_classes,)
        Posterior of each joint class.

    Returns
    -------
    distinct : ndarray
        Sorted distinct values.
    mass : ndarray
        Posterior mass of each.
    """
    distinct, inv = np.unique(np.asarray(values), return_inverse=True)
    mass = np.zeros(distinct.shape[0])
    np.add.at(mass, np.asarray(inv).ravel(), np.asarray(proba, dtype=float))
    return distinct, mass


def marginal_interval(
    values: np.ndarray, mass: np.ndarray, low: float = 0.05, high: float = 0.95
) -> tuple[float, float, float]:
    """Mean and the ``low``-``high`` interval of a discrete marginal (sorted ``values``).

    The interval ends are the smallest values at which the marginal CDF reaches
    ``low`` and ``high``.

    Returns
    -------
    mean, lower, upper : float
    """
    m = np.asarray(mass, dtype=float)
    m = m / m.sum()
    cdf = np.cumsum(m)
    v = np.asarray(values, dtype=float)
    tol = 1e-12
    lo = v[min(int(np.searchsorted(cdf, low - tol)), v.size - 1)]
    hi = v[min(int(np.searchsorted(cdf, high - tol)), v.size - 1)]
    return float(np.dot(m, v)), float(lo), float(hi)


def _floats(d: dict[Any, float]) -> dict[str, float]:
    return {repr(float(k)): float(v) for k, v in d.items()}


def _unfloats(d: dict[str, float]) -> dict[float, float]:
    return {float(k): float(v) for k, v in d.items()}


def _opt_pair(v: Any) -> tuple[float, float] | None:
    return None if v is None else (float(v[0]), float(v[1]))


@dataclass(frozen=True)
class WhereEstimate:
    """Where a contact was on the whisker (and how fast): one contact's where-model output.

    Attributes
    ----------
    radial_distance_mm : float
        Mean of the marginal posterior of radial distance.
    radial_interval_mm : tuple of float
        Its 5-95 % interval (from the marginal CDF over the class values).
    speed_mm_s, speed_interval_mm_s : float, tuple or None
        The same for speed (``None`` when the model has no speed).
    p_tip : float
        Posterior mass of the "tip" classes.
    """

    radial_distance_mm: float
    radial_interval_mm: tuple[float, float]
    speed_mm_s: float | None
    speed_interval_mm_s: tuple[float, float] | None
    p_tip: float

    def to_dict(self) -> dict[str, Any]:
        """The estimate as JSON-ready data."""
        return {
            "radial_distance_mm": float(self.radial_distance_mm),
            "radial_interval_mm": [float(v) for v in self.radial_interval_mm],
            "speed_mm_s": None if self.speed_mm_s is None else float(self.speed_mm_s),
            "speed_interval_mm_s": None
            if self.speed_interval_mm_s is None
            else [float(v) for v in self.speed_interval_mm_s],
            "p_tip": float(self.p_tip),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> WhereEstimate:
        """The estimate from :meth:`to_dict`'s output."""
        return cls(
            radial_distance_mm=float(d["radial_distance_mm"]),
            radial_interval_mm=_opt_pair(d["radial_interval_mm"]),  # type: ignore[arg-type]
            speed_mm_s=None if d["speed_mm_s"] is None else float(d["speed_mm_s"]),
            speed_interval_mm_s=_opt_pair(d["speed_interval_mm_s"]),
            p_tip=float(d["p_tip"]),
        )


@dataclass(frozen=True)
class WhatEstimate:
    """Surface angle and texture from one tip contact alone.

    Attributes
    ----------
    angle_posterior : dict of float to float
        Marginal posterior of each angle (degrees).
    texture_posterior : dict of str to float
        Marginal posterior of each texture name.
    """

    angle_posterior: dict[float, float]
    texture_posterior: dict[str, float]

    def to_dict(self) -> dict[str, Any]:
        """The estimate as JSON-ready data."""
        return {
            "angle_posterior": _floats(self.angle_posterior),
            "texture_posterior": {str(k): float(v) for k, v in self.texture_posterior.items()},
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> WhatEstimate:
        """The estimate from :meth:`to_dict`'s output."""
        return cls(
            angle_posterior=_unfloats(d["angle_posterior"]),
            texture_posterior={str(k): float(v) for k, v in d["texture_posterior"].items()},
        )


@dataclass(frozen=True)
class SurfaceEvidence:
    """The evidence about the current surface after a contact (every whisker's tip contacts).

    Attributes
    ----------
    surface_id : int
    n_contacts : int
        Tip contacts accumulated.
    whiskers : tuple of int
        Whiskers that contributed, sorted.
    angle_deg : float
        Angle of the most probable joint class.
    texture : str
        Texture of the most probable joint class.
    probability : float
        Its posterior.
    decided : bool
        ``probability`` has reached the decision threshold.
    angle_posterior : dict of float to float
    texture_posterior : dict of str to float
        Marginals of the accumulated posterior.
    """

    surface_id: int
    n_contacts: int
    whiskers: tuple[int, ...]
    angle_deg: float
    texture: str
    probability: float
    decided: bool
    angle_posterior: dict[float, float]
    texture_posterior: dict[str, float]

    def to_dict(self) -> dict[str, Any]:
        """The evidence as JSON-ready data."""
        return {
            "surface_id": int(self.surface_id),
            "n_contacts": int(self.n_contacts),
            "whiskers": [int(w) for w in self.whiskers],
            "angle_deg": float(self.angle_deg),
            "texture": str(self.texture),
            "probability": float(self.probability),
            "decided": bool(self.decided),
            "angle_posterior": _floats(self.angle_posterior),
            "texture_posterior": {str(k): float(v) for k, v in self.texture_posterior.items()},
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> SurfaceEvidence:
        """The evidence from :meth:`to_dict`'s output."""
        return cls(
            surface_id=int(d["surface_id"]),
            n_contacts=int(d["n_contacts"]),
            whiskers=tuple(int(w) for w in d["whiskers"]),
            angle_deg=float(d["angle_deg"]),
            texture=str(d["texture"]),
            probability=float(d["probability"]),
            decided=bool(d["decided"]),
            angle_posterior=_unfloats(d["angle_posterior"]),
            texture_posterior={str(k): float(v) for k, v in d["texture_posterior"].items()},
        )


@dataclass(frozen=True)
class ContactReport:
    """Everything the pipeline concluded from one contact.

    Attributes
    ----------
    whisker : int
    onset_s, end_s : float
        Stream times of onset and end, s.
    peak_departure : float
        Largest departure from rest (signal units).
    tip : bool
        Classified as a tip contact (``p_tip >= tip_probability``).
    p_tip : float
        Posterior probability of a tip contact (1.0 without a where model).
    where : WhereEstimate or None
    what : WhatEstimate or None
        This contact alone (tip contacts with a what model).
    evidence : SurfaceEvidence or None
        The current surface's accumulated evidence after this contact (tip contacts
        with a what model).
    surface_id : int
        The surface the contact was attributed to.
    decision : dict or None
        ``{"angle_deg", "texture", "probability", "n_contacts", "whiskers"}`` when the
        evidence has decided.
    truncated : bool
        The contact's window was incomplete (stream end or break).
    """

    whisker: int
    onset_s: float
    end_s: float
    peak_departure: float
    tip: bool
    p_tip: float
    where: WhereEstimate | None
    what: WhatEstimate | None
    evidence: SurfaceEvidence | None
    surface_id: int
    decision: dict[str, Any] | None
    truncated: bool

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready data."""
        return {
            "whisker": int(self.whisker),
            "onset_s": float(self.onset_s),
            "end_s": float(self.end_s),
            "peak_departure": float(self.peak_departure),
            "tip": bool(self.tip),
            "p_tip": float(self.p_tip),
            "where": None if self.where is None else self.where.to_dict(),
            "what": None if self.what is None else self.what.to_dict(),
            "evidence": None if self.evidence is None else self.evidence.to_dict(),
            "surface_id": int(self.surface_id),
            "decision": None if self.decision is None else _decision(self.decision),
            "truncated": bool(self.truncated),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> ContactReport:
        """The report from :meth:`to_dict`'s output."""
        return cls(
            whisker=int(d["whisker"]),
            onset_s=float(d["onset_s"]),
            end_s=float(d["end_s"]),
            peak_departure=float(d["peak_departure"]),
            tip=bool(d["tip"]),
            p_tip=float(d["p_tip"]),
            where=None if d["where"] is None else WhereEstimate.from_dict(d["where"]),
            what=None if d["what"] is None else WhatEstimate.from_dict(d["what"]),
            evidence=None if d["evidence"] is None else SurfaceEvidence.from_dict(d["evidence"]),
            surface_id=int(d["surface_id"]),
            decision=None if d["decision"] is None else _decision(d["decision"]),
            truncated=bool(d["truncated"]),
        )


def _decision(d: dict[str, Any]) -> dict[str, Any]:
    """A decision dict in plain JSON types (``whiskers`` a list)."""
    return {
        "angle_deg": float(d["angle_deg"]),
        "texture": str(d["texture"]),
        "probability": float(d["probability"]),
        "n_contacts": int(d["n_contacts"]),
        "whiskers": [int(w) for w in d["whiskers"]],
    }
