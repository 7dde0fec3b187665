"""Sequential evidence accumulation over repeated contacts (beyond the thesis, 7.1.2).

A rat touches a surface several times. If contacts are independent given the
surface, the posterior over a target (e.g. texture) after ``n`` contacts, with a
flat prior, is proportional to the product of the single-contact posteriors::

    log P(t | x_1 ... x_n) = sum_i log P(t | x_i) + const

:func:`accumulate_evidence` sums the per-contact log posteriors and stops at the
first contact where the normalised posterior of the best class reaches
``threshold`` (a sequential decision, Lepora et al. 2012);
:class:`SequentialEvidenceClassifier` wraps any probabilistic classifier of
joint classes, marginalises its posterior onto one target column and classifies
sequences of trials.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.special import log_softmax, logsumexp
from sklearn.base import BaseEstimator, ClassifierMixin, clone
from sklearn.utils.validation import check_is_fitted

from vibrissa.classify._base import (
    SampleRateMixin,
    check_sample_rate,
    fitted_sample_rate,
    sample_rate_fit_params,
)

__all__ = ["SequentialEvidenceClassifier", "accumulate_evidence", "draw_sequences"]


def accumulate_evidence(
    log_proba: np.ndarray, threshold: float = 0.99
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sum per-contact log posteriors until the posterior passes ``threshold``.

    Parameters
    ----------
    log_proba : ndarray of shape (n_sequences, n_contacts, n_classes)
        Log posterior (or log-likelihood) of each class for each contact.
    threshold : float, default=0.99
        Stop at the first contact at which the best class' normalised posterior
        is ``>= threshold``; values ``>= 1`` never stop early (all contacts used).

    Returns
    -------
    decision : ndarray of shape (n_sequences,)
        Index of the winning class.
    n_used : ndarray of shape (n_sequences,)
        Contacts used (1 ... n_contacts).
    posterior : ndarray of shape (n_sequences, n_classes)
        Normalised posterior at the stopping contact.
    """
    lp = np.asarray(log_proba, dtype=float)
    if lp.ndim != 3 or lp.shape[1] < 1 or lp.shape[2] < 1:
        raise ValueError(
            f"log_proba must have shape (n_sequences, n_contacts, n_classes), got {lp.shape}"
        )
    if np.isnan(lp).any():
        raise ValueError("log_proba contains NaN")
    thr = float(threshold)
    if not 0.0 < thr:
        raise ValueError(f"threshold must be positive, got {threshold!r}")
    post = log_softmax(np.cumsum(lp, axis=1), axis=2)  # (n, k, c)
    best = post.max(axis=2)
    passed = best >= np.log(thr) if thr < 1 else np.zeros_like(best, dtype=bool)
    passed[:, -1] = True
    stop = np.argmax(passed, axis=1)
    final = post[np.arange(lp.shape[0]), stop]
    return np.argmax(final, axis=1), stop + 1, np.exp(final)


def draw_sequences(labels: Any, n_contacts: int, seed: int | np.random.Generator = 0) -> np.ndarray:
    """Sequences of trials with the same label, one starting at each trial.

    Sequence ``i`` starts with trial ``i`` and continues with ``n_contacts - 1``
    other trials of the same label drawn at random (without replacement while the
    class has enough trials, then with).

    Parameters
    ----------
    labels : array-like of shape (n_trials,)
    n_contacts : int
    seed : int or numpy.random.Generator

    Returns
    -------
    ndarray of shape (n_trials, n_contacts)
        Trial indices.
    """
    lab = np.asarray(labels)
    if (
        isinstance(n_contacts, bool)
        or not isinstance(n_contacts, int | np.integer)
        or n_contacts < 1
    ):
        raise ValueError(f"n_contacts must be a positive integer, got {n_contacts!r}")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    out = np.empty((lab.shape[0], int(n_contacts)), dtype=np.intp)
    for i in range(lab.shape[0]):
        others = np.flatnonzero(lab == lab[i])
        others = others[others != i]
        k = int(n_contacts) - 1
        if k == 0:
            rest = np.empty(0, dtype=np.intp)
        elif others.size == 0:
            rest = np.full(k, i)
        else:
            rest = rng.choice(others, size=k, replace=others.size < k)
        out[i] = np.concatenate([[i], rest])
    return out


class SequentialEvidenceClassifier(SampleRateMixin, ClassifierMixin, BaseEstimator):
    """Accumulate one target's posterior over repeated contacts with the same surface.

    Parameters
    ----------
    estimator : estimator
        Probabilistic classifier of joint label rows (``predict_proba``).
    target_column : int or None, default=2
        Column of ``y`` accumulated (2: texture code); ``None``: the whole label
        (1-D ``y``, or the joint rows of a 2-D ``y``).
    threshold : float, default=0.99
        Posterior at which a sequence stops (see :func:`accumulate_evidence`).
    min_probability : float, default=1e-3
        Floor of each contact's marginal posterior, so that one over-confident
        contact (naive Bayes posteriors are nearly one-hot) cannot veto a class.

    Attributes
    ----------
    estimator_ : estimator
    classes_ : ndarray
        Values of the target column (the joint label rows when ``target_column`` is
        ``None`` and ``y`` is 2-D).
    class_index_ : ndarray of shape (n_joint_classes,)
        Target value index of each of ``estimator_.classes_``.
    n_features_in_ : int
        That of ``estimator_`` (when it has one).
    sample_rate_hz_ : float or None
        The rate ``estimator_`` was fitted at, Hz (it has no rate of its own: data at
        another rate than its estimator's are refused).
    """

    def __init__(
        self,
        estimator: Any,
        target_column: int | None = 2,
        threshold: float = 0.99,
        min_probability: float = 1e-3,
    ) -> None:
        self.estimator = estimator
        self.target_column = target_column
        self.threshold = threshold
        self.min_probability = min_probability

    def _rate_parts(self) -> list[tuple[str, Any]]:
        return [("estimator", self.estimator)]

    def _check_rate(self, sample_rate_hz: float) -> None:
        super()._check_rate(sample_rate_hz)
        if not hasattr(self, "estimator_"):
            return
        try:
            check_sample_rate(self.estimator_, sample_rate_hz)
        except ValueError as exc:
            raise ValueError(f"{type(self).__name__}'s estimator_: {exc}") from None

    def fit(
        self, X: Any, y: Any, sample_rate_hz: float | None = None
    ) -> SequentialEvidenceClassifier:
        """Fit the wrapped classifier on single contacts.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        y : array-like of shape (n_trials, n_targets) or (n_trials,)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz, passed on to ``estimator`` (each step of a
            Pipeline); refused when ``estimator`` is built for another.

        Returns
        -------
        self
        """
        rate = self._fit_rate(sample_rate_hz)
        params = sample_rate_fit_params(self.estimator, rate)
        return self._adopt(clone(self.estimator).fit(X, y, **params), rate)

    @classmethod
    def from_fitted(
        cls,
        estimator: Any,
        target_column: int | None = 2,
        threshold: float = 0.99,
        min_probability: float = 1e-3,
    ) -> SequentialEvidenceClassifier:
        """Wrap an already fitted classifier without refitting it.

        Parameters
        ----------
        estimator : estimator
            Fitted probabilistic classifier of joint label rows (used as is, not copied).
        target_column, threshold, min_probability
            As in the constructor.

        Returns
        -------
        SequentialEvidenceClassifier
            Fitted.
        """
        check_is_fitted(estimator)
        return cls(estimator, target_column, threshold, min_probability)._adopt(estimator)

    def _adopt(
        self, fitted: Any, sample_rate_hz: float | None = None
    ) -> SequentialEvidenceClassifier:
        if not 0 < float(self.min_probability) < 1:
            raise ValueError(f"min_probability must lie in (0, 1), got {self.min_probability!r}")
        self.estimator_ = fitted
        self.sample_rate_hz_ = (
            fitted_sample_rate(fitted) if sample_rate_hz is None else sample_rate_hz
        )
        jc = np.asarray(self.estimator_.classes_)
        if self.target_column is None and jc.ndim == 2:
            # no target column chosen: accumulate the joint classes themselves
            self.classes_, self.class_index_ = jc, np.arange(len(jc))
        else:
            col = jc if jc.ndim == 1 else jc[:, int(self.target_column)]
            self.classes_, inv = np.unique(col, return_inverse=True)
            self.class_index_ = np.asarray(inv).ravel()
        n_in = getattr(fitted, "n_features_in_", None)
        if n_in is not None:
            self.n_features_in_ = n_in
        names = getattr(fitted, "feature_names_in_", None)
        if names is not None:
            self.feature_names_in_ = names
        return self

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        # y may be joint label rows (n_trials, n_targets); one column is accumulated
        tags.target_tags.multi_output = True
        tags.target_tags.single_output = True
        return tags

    def contact_log_proba(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Floored log marginal posterior of the target for each single contact.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_classes)
            Normalised (rows are log-probabilities).
        """
        self._check_predict_rate(sample_rate_hz)
        p = np.asarray(self.estimator_.predict_proba(X), dtype=float)
        m = np.zeros((p.shape[0], len(self.classes_)))
        np.add.at(m.T, self.class_index_, p.T)
        lm = np.log(np.maximum(m, float(self.min_probability)))
        return lm - logsumexp(lm, axis=1, keepdims=True)

    def predict_proba(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Single-contact marginal posterior of the target (floored, normalised).

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_classes)
        """
        return np.exp(self.contact_log_proba(X, sample_rate_hz))

    def predict(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Target value of each single contact.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials,)
        """
        lp = self.contact_log_proba(X, sample_rate_hz)  # checks that the classifier is fitted
        return self.classes_[np.argmax(lp, axis=1)]

    def score(
        self, X: Any, y: Any, sample_weight: Any = None, sample_rate_hz: float | None = None
    ) -> float:
        """Accuracy of the single-contact predictions of the target (values ``y``).

        As :meth:`sklearn.base.ClassifierMixin.score`; ``sample_rate_hz`` (optional),
        the rate of ``X`` in Hz, is refused when not ``sample_rate_hz_``.
        """
        self._check_predict_rate(sample_rate_hz)
        return super().score(X, y, sample_weight=sample_weight)

    def predict_sequences(
        self,
        X: Any,
        sequences: Any,
        n_contacts: int | None = None,
        sample_rate_hz: float | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Classify sequences of contacts with the same (unknown) target value.

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
            The contacts.
        sequences : array-like of int, shape (n_sequences, max_contacts)
            Indices into ``X`` of each sequence's contacts, in order.
        n_contacts : int, optional
            Use only the first ``n_contacts`` of each sequence.
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        predictions : ndarray of shape (n_sequences,)
        n_used : ndarray of shape (n_sequences,)
            Contacts used before the posterior passed ``threshold``.
        """
        lp = self.contact_log_proba(X, sample_rate_hz)
        return self.predict_sequences_from_log_proba(lp, sequences, n_contacts)

    def predict_sequences_from_log_proba(
        self, log_proba: np.ndarray, sequences: Any, n_contacts: int | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`predict_sequences`, from precomputed :meth:`contact_log_proba`."""
        seq = np.asarray(sequences)
        if seq.ndim != 2 or seq.dtype.kind not in "iu":
            raise ValueError("sequences must be a 2-D integer array (n_sequences, n_contacts)")
        if seq.size and (seq.min() < 0 or seq.max() >= log_proba.shape[0]):
            raise ValueError("sequences index trials outside X")
        if n_contacts is not None:
            seq = seq[:, : int(n_contacts)]
        dec, used, _ = accumulate_evidence(log_proba[seq], self.threshold)
        return self.classes_[dec], used
