"""Nearest-template classification on low-pass filtered signals (thesis 4.3.3, eq. 4.4)."""

from __future__ import annotations

from typing import Literal

import numpy as np

from vibrissa import signal as vsig
from vibrissa.classify import _kernels
from vibrissa.classify._base import TrialClassifier

__all__ = ["TimeTemplateClassifier", "nearest_template_l1", "nearest_template_scores"]


def _check_positive_int(name: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def _check_distance(distance: object) -> str:
    if distance not in ("sse", "l1"):
        raise ValueError(f"distance must be 'sse' or 'l1', got {distance!r}")
    return str(distance)


def _check_templates(templates: object) -> str:
    if templates not in ("all", "mean"):
        raise ValueError(f"templates must be 'all' or 'mean', got {templates!r}")
    return str(templates)


def build_templates(
    F: np.ndarray, y_idx: np.ndarray, n_classes: int, templates: str
) -> tuple[np.ndarray, np.ndarray]:
    """Templates and their class index: every trial (``"all"``) or per-class means."""
    if templates == "all":
        return F.copy(), y_idx.copy()
    counts = np.bincount(y_idx, minlength=n_classes).astype(float)
    sums = np.zeros((n_classes, F.shape[1]))
    np.add.at(sums, y_idx, F)
    return sums / counts[:, None], np.arange(n_classes)


def _grouped_by_class(
    T: np.ndarray, t_class: np.ndarray, n_classes: int
) -> tuple[np.ndarray, np.ndarray]:
    """Templates sorted by class and the first row of each class (for ``reduceat``)."""
    order = np.argsort(t_class, kind="stable")
    starts = np.searchsorted(t_class[order], np.arange(n_classes))
    return np.ascontiguousarray(T[order]), starts


def nearest_template_scores(
    F: np.ndarray,
    T: np.ndarray,
    t_class: np.ndarray,
    n_classes: int,
    chunk_size: int = 512,
) -> np.ndarray:
    """Smallest sum of squared errors (eq. 4.4) from each row of ``F`` to each class.

    ``SSE(a, b) = |a|^2 + |b|^2 - 2 a.b`` is evaluated as one matrix product per
    chunk of ``chunk_size`` rows of ``F``, so memory stays at
    ``chunk_size x n_templates`` floats.

    Parameters
    ----------
    F : ndarray of shape (n, d)
        Inputs (flattened, preprocessed trials).
    T : ndarray of shape (m, d)
        Templates.
    t_class : ndarray of shape (m,)
        Class index of each template; every class in ``range(n_classes)`` must occur.
    n_classes : int
    chunk_size : int

    Returns
    -------
    ndarray of shape (n, n_classes)
        Minimum SSE over each class' templates.
    """
    T, starts = _grouped_by_class(T, t_class, n_classes)
    t_sq = np.einsum("ij,ij->i", T, T)
    out = np.empty((F.shape[0], n_classes))
    for s in range(0, F.shape[0], chunk_size):
        a = F[s : s + chunk_size]
        d = np.einsum("ij,ij->i", a, a)[:, None] + t_sq[None, :] - 2.0 * (a @ T.T)
        np.maximum(d, 0.0, out=d)
        out[s : s + chunk_size] = (
            d if len(T) == n_classes else np.minimum.reduceat(d, starts, axis=1)
        )
    return out


def nearest_template_l1(
    F: np.ndarray,
    T: np.ndarray,
    t_class: np.ndarray,
    n_classes: int,
    chunk_size: int = 512,
) -> np.ndarray:
    """Smallest sum of absolute errors from each row of ``F`` to each class' templates.

    The thesis author's template code compared signals by ``sum(abs(T - I))``
    (where the text's eq. 4.4 squares the errors). Each distance is summed over the
    features in order, as :func:`scipy.spatial.distance.cdist` (``cityblock``) sums
    (the same numbers, by a compiled kernel several times faster), in chunks of
    ``chunk_size`` rows, so memory stays at ``chunk_size x n_templates`` floats.

    Parameters and return value as :func:`nearest_template_scores`.
    """
    T, starts = _grouped_by_class(T, t_class, n_classes)
    TT = np.ascontiguousarray(T.T, dtype=np.float64)
    F = np.ascontiguousarray(F, dtype=np.float64)
    out = np.empty((F.shape[0], n_classes))
    d = np.empty((min(chunk_size, F.shape[0]), T.shape[0]))
    for s in range(0, F.shape[0], chunk_size):
        a = F[s : s + chunk_size]
        _kernels.l1_distances(a, TT, d[: a.shape[0]])
        out[s : s + chunk_size] = (
            d[: a.shape[0]]
            if len(T) == n_classes
            else np.minimum.reduceat(d[: a.shape[0]], starts, axis=1)
        )
    return out


class NearestTemplate(TrialClassifier):
    """Nearest template on a per-trial feature vector (shared by time and spectral templates)."""

    def _features(self, X: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        _check_templates(self.templates)
        _check_distance(self.distance)
        _check_positive_int("chunk_size", self.chunk_size)
        F = self._features(X)
        self.center_ = F.mean(axis=0)
        F = F - self.center_
        # Normaliser of the scores: the distance per feature relative to the training
        # spread (variance for SSE, mean absolute deviation for L1).
        spread = float(np.mean(F * F)) if self.distance == "sse" else float(np.mean(np.abs(F)))
        self.sse_scale_ = F.shape[1] * (spread if spread > 0 else 1.0)
        self.templates_, self.template_class_ = build_templates(
            F, y_idx, len(self.classes_), self.templates
        )

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        F = self._features(X) - self.center_
        nearest = nearest_template_scores if self.distance == "sse" else nearest_template_l1
        dist = nearest(
            F, self.templates_, self.template_class_, len(self.classes_), self.chunk_size
        )
        return -dist / self.sse_scale_


class TimeTemplateClassifier(NearestTemplate):
    """Template classifier on low-pass filtered signals (thesis 4.3.3, eq. 4.4).

    Each input trial is low-pass filtered (zero-phase Butterworth) and compared
    with every stored template by the sum of squared errors over all samples and
    channels (eq. 4.4); the template with the smallest error wins and its joint
    label (e.g. radial distance and speed) is the prediction.

    Parameters
    ----------
    sample_rate_hz : float, default=1000.0
        Sampling rate of the trials, Hz (1 kHz in chapter 4).
    cutoff_hz : float or None, default=100.0
        Low-pass cut-off, Hz; ``None`` compares raw signals. The thesis found
        low-pass filtering best but does not give the cut-off; 100 Hz keeps the
        contact and the first whisker modes of the simulated whisker.
    filter_order : int, default=4
        Butterworth order of the low-pass filter.
    templates : {"all", "mean"}, default="all"
        ``"all"`` stores every training trial as a template (nearest neighbour,
        as in the thesis); ``"mean"`` stores one mean template per joint class.
    distance : {"sse", "l1"}, default="sse"
        Sum of squared errors (the text's eq. 4.4) or sum of absolute errors (what
        the thesis author's code computed; see ``docs/methods.md``).
    chunk_size : int, default=512
        Test trials compared per matrix product (bounds memory).

    Attributes
    ----------
    classes_ : ndarray of shape (n_classes,) or (n_classes, n_targets)
        Distinct label rows.
    templates_ : ndarray of shape (n_templates, n_channels * n_timepoints)
        Filtered, centred templates.
    template_class_ : ndarray of shape (n_templates,)
        Index into ``classes_`` of each template.
    center_ : ndarray of shape (n_channels * n_timepoints,)
        Mean filtered training trial, subtracted from inputs and templates (the SSE
        does not change; it keeps ``|a|^2 + |b|^2 - 2 a.b`` numerically accurate).
    sse_scale_ : float
        Divisor of the distance in the scores (``n_features x`` mean training
        variance for SSE, mean absolute deviation for L1).
    n_channels_, n_timepoints_, n_features_in_ : int

    Notes
    -----
    ``predict_proba`` is ``softmax(-SSE / sse_scale_)`` over classes (the best
    template of each class): monotone in the template distance and consistent with
    :meth:`predict`, but not a calibrated probability.
    """

    def __init__(
        self,
        sample_rate_hz: float = 1000.0,
        cutoff_hz: float | None = 100.0,
        filter_order: int = 4,
        templates: Literal["all", "mean"] = "all",
        chunk_size: int = 512,
        distance: Literal["sse", "l1"] = "sse",
    ) -> None:
        self.sample_rate_hz = sample_rate_hz
        self.cutoff_hz = cutoff_hz
        self.filter_order = filter_order
        self.templates = templates
        self.chunk_size = chunk_size
        self.distance = distance

    def _features(self, X: np.ndarray) -> np.ndarray:
        if self.cutoff_hz is not None:
            X = vsig.lowpass(X, self.cutoff_hz, self.sample_rate_hz, order=self.filter_order)
        return X.reshape(X.shape[0], -1)
