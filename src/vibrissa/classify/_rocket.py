"""A compact MiniRocket-style reference classifier (beyond the thesis, 7.1.2).

Random-convolution features after Dempster, Schmidt and Webb (2021, MiniRocket):
the 84 kernels of length 9 with weights ``-1`` everywhere and ``2`` at three
positions, applied at exponentially spaced dilations to each channel; each
(kernel, dilation, channel) gives ``n_biases`` features, the proportion of
positive values (PPV) of the convolution output above biases drawn from the
quantiles of the output on a random training trial. A linear head is fitted per
target column (angle, speed, texture) and the joint score of a class is the sum
of each target's log posterior:

* ``head="logistic"`` (default): multinomial logistic regression
  (:class:`sklearn.linear_model.LogisticRegression`, L2 penalty ``C``) - calibrated
  posteriors, which evidence accumulation over contacts needs;
* ``head="ridge"``: the ridge classifier of the MiniRocket paper
  (:class:`sklearn.linear_model.RidgeClassifierCV`, leave-one-out choice of the
  penalty), posteriors the log-softmax of its decision values (uncalibrated).

The default ``C`` was chosen by 3-fold cross-validation of the log loss on the
*training* run of the full chapter-5 grid, over C = 0.001 ... 0.1 (the smallest C
within reach of the best loss, which is also the fastest to fit); the kappas it gives
are in each ``vibrissa reproduce angle-texture`` report, not here, so they cannot go
stale.

With weights ``-1`` and ``2`` the convolution is ``-sum_j x_j + 3 (x_a + x_b +
x_c)``, so the shared sum is computed once per dilation and every kernel costs
three additions (two of them shared through pair sums). Trials are first
block-averaged by ``pool`` (4 kHz -> 500 Hz by default), which bounds the cost on
the 704-trial chapter-5 test set. The features of the fitted model are computed by
a compiled kernel (:func:`vibrissa.classify._kernels.minirocket_ppv`) one trial at
a time, with the float32 operations of the NumPy code it replaced (which the fit
still uses for the biases), so a trial's features are the same, bit for bit, alone
or in a batch, and one trial costs well under a millisecond (a streaming pipeline
classifies each contact as it ends); the linear heads' decision values are
computed in float64 without scikit-learn's per-call validation (so a trial's
posteriors do not depend on the batch it is in, on any CPU) and their log-softmax
without SciPy's array-API dispatch, with the same operations.
"""

from __future__ import annotations

from itertools import combinations
from typing import Any

import numpy as np
from sklearn.base import TransformerMixin
from sklearn.linear_model import LogisticRegression, RidgeClassifierCV

from vibrissa.classify import _kernels
from vibrissa.classify._base import TrialClassifier

__all__ = ["MiniRocketClassifier", "minirocket_kernels"]


def minirocket_kernels() -> np.ndarray:
    """The 84 index triples (positions of weight 2 among 9 taps) of MiniRocket.

    Returns
    -------
    ndarray of shape (84, 3)
    """
    return np.array(list(combinations(range(9), 3)), dtype=np.intp)


def _pool(X: np.ndarray, pool: int) -> np.ndarray:
    """Block-average by ``pool``, centre each trial; zero-pad to the 9 kernel taps."""
    n, c, t = X.shape
    m = t // pool
    Z = X[..., : m * pool].reshape(n, c, m, pool).mean(axis=-1)
    Z -= Z.mean(axis=-1, keepdims=True)
    if m < 9:
        Z = np.concatenate([Z, np.zeros((n, c, 9 - m))], axis=-1)
    return Z.astype(np.float32)


def effective_pool(pool: int, n_timepoints: int) -> int:
    """``pool``, reduced for short trials so that at least 9 pooled samples remain.

    Trials shorter than 9 samples are zero-padded (after centring) to 9 by
    :func:`_pool`; neither changes anything for trials of ``9 * pool`` samples or more.
    """
    return max(1, min(int(pool), n_timepoints // 9))


#: The 84 index triples as the feature kernel takes them (int64, C-contiguous).
_TRIPLES = np.ascontiguousarray(minirocket_kernels(), dtype=np.int64)


def _decision_values(head: Any, F: np.ndarray) -> np.ndarray:
    """``head.decision_function(F)`` of a fitted linear head, in float64, without its checks.

    scikit-learn's ``LinearClassifierMixin.decision_function`` (``F @ coef_.T +
    intercept_``, one column raveled), with the float32 features of
    :meth:`MiniRocketClassifier._features` and the heads' float32 coefficients (a head
    fitted on float32 features keeps them) widened to float64 first. In float32 the
    product is a BLAS ``sgemm`` whose blocking depends on the number of rows and on the
    CPU's kernel: a trial's probabilities then changed in the seventh digit with the
    batch it came in (2.7e-7 on an AMD EPYC, where scikit-learn's subset-invariance
    check failed). In float64 the widened values are exact and only the accumulation
    order remains, at 1e-16.
    """
    coef = np.asarray(head.coef_, dtype=np.float64)
    scores = np.asarray(F, dtype=np.float64) @ (coef.T if coef.ndim == 2 else coef)
    scores = scores + np.asarray(head.intercept_, dtype=np.float64)
    return scores.reshape(-1) if scores.ndim > 1 and scores.shape[1] == 1 else scores


def _log_softmax_rows(x: np.ndarray) -> np.ndarray:
    """``scipy.special.log_softmax(x, axis=1)`` of a 2-D float array, with its operations.

    SciPy's array-API dispatch costs ~20 microseconds a call, three calls per
    prediction; the result is the same bit for bit.
    """
    x_max = np.max(x, axis=1, keepdims=True)
    x_max[~np.isfinite(x_max)] = 0
    tmp = x - x_max
    with np.errstate(divide="ignore"):
        return tmp - np.log(np.sum(np.exp(tmp), axis=1, keepdims=True))


def _conv_stack(Z: np.ndarray, d: int) -> tuple[np.ndarray, np.ndarray]:
    """Shifted copies ``G_j = 3 x(t + j d)`` and ``A = -sum_j x(t + j d)`` (valid part)."""
    L = Z.shape[-1] - 8 * d
    S = np.stack([Z[..., j * d : j * d + L] for j in range(9)])
    return 3.0 * S, -S.sum(axis=0)


class MiniRocketClassifier(TransformerMixin, TrialClassifier):
    """MiniRocket-style random-convolution features + per-target linear classifiers.

    A classifier that is also a transformer (as scikit-learn's
    ``LinearDiscriminantAnalysis`` is): :meth:`transform` gives the standardised
    features its linear heads see, ``fit_transform(X, y)`` fits and returns them.

    Parameters
    ----------
    pool : int, default=8
        Block-average factor applied first (time resolution of the kernels).
    n_dilations : int, default=6
        Dilations ``2^0 ... `` up to the longest that fits the pooled trial.
    n_biases : int, default=2
        Biases (quantiles of one training trial's output) per kernel, dilation and
        channel.
    head : {"logistic", "ridge"}, default="logistic"
        Linear classifier fitted per target (see the module docstring).
    C : float, default=0.01
        Inverse L2 penalty of the logistic head (features are standardised).
    alphas : tuple of float, default=logspace(-2, 4, 7)
        Ridge penalties tried by leave-one-out cross-validation (``head="ridge"``).
    random_state : int, default=0
        Seed of the bias draws.
    chunk_size : int, default=128
        Trials per call of the compiled feature kernel (the features do not depend
        on it).
    sample_rate_hz : float or None, default=None
        Sample rate of the trials, Hz. The features do not use it (``pool`` and the
        dilations count samples); when given, data at another rate are refused, and
        ``fit`` records the rate it is given (``sample_rate_hz_``).

    Attributes
    ----------
    pool_ : int
        The block-average factor used: ``pool``, or less for trials shorter than
        ``9 * pool`` samples (which are then zero-padded to 9 samples).
    dilations_ : ndarray of int
    biases_ : ndarray of shape (n_dilations, 84, n_channels, n_biases)
    feature_mean_, feature_scale_ : ndarray
        Standardisation of the PPV features.
    heads_ : list of LogisticRegression or RidgeClassifierCV
        One per target column (``None`` for a column with a single value).
    target_index_ : ndarray of shape (n_classes, n_targets)
        Index of each joint class' value in each head's ``classes_``.
    classes_, n_channels_, n_timepoints_, n_features_in_
    """

    def __init__(
        self,
        pool: int = 8,
        n_dilations: int = 6,
        n_biases: int = 2,
        head: str = "logistic",
        C: float = 0.01,
        alphas: tuple[float, ...] = (1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4),
        random_state: int = 0,
        chunk_size: int = 128,
        sample_rate_hz: float | None = None,
    ) -> None:
        self.pool = pool
        self.n_dilations = n_dilations
        self.n_biases = n_biases
        self.head = head
        self.C = C
        self.alphas = alphas
        self.random_state = random_state
        self.chunk_size = chunk_size
        self.sample_rate_hz = sample_rate_hz

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.classifier_tags.poor_score = True
        tags.transformer_tags.preserves_dtype = []  # features are float32 (PPV proportions)
        return tags

    def _check_params(self) -> None:
        for name in ("pool", "n_dilations", "n_biases", "chunk_size"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
                raise ValueError(f"{name} must be a positive integer, got {v!r}")
        if self.head not in ("logistic", "ridge"):
            raise ValueError(f"head must be 'logistic' or 'ridge', got {self.head!r}")
        c = self.C
        if (
            isinstance(c, bool)
            or not isinstance(c, int | float | np.number)
            or not np.isfinite(c)
            or c <= 0
        ):
            raise ValueError(f"C must be a positive finite number, got {c!r}")

    def _ppv(self, Z: np.ndarray) -> np.ndarray:
        """PPV features of pooled trials ``Z`` (n, c, t), shape (n, n_features)."""
        Z = np.ascontiguousarray(Z, dtype=np.float32)
        n, c, _ = Z.shape
        dilations = np.ascontiguousarray(self.dilations_, dtype=np.int64)
        biases = np.ascontiguousarray(self.biases_, dtype=np.float32)
        out = np.empty((n, len(dilations), len(_TRIPLES), c, biases.shape[-1]), dtype=np.float32)
        step = int(self.chunk_size)
        for s in range(0, n, step):
            _kernels.minirocket_ppv(Z[s : s + step], dilations, _TRIPLES, biases, out[s : s + step])
        return out.reshape(n, -1)

    def _features(self, X: np.ndarray) -> np.ndarray:
        F = self._ppv(_pool(X, self.pool_))
        return (F - self.feature_mean_) / self.feature_scale_

    def _fit(self, X: np.ndarray, y: object, y_idx: np.ndarray) -> None:
        self._check_params()
        self.pool_ = effective_pool(int(self.pool), X.shape[-1])
        Z = _pool(X, self.pool_)
        t = Z.shape[-1]
        max_exp = np.log2(max((t - 1) / 8.0, 1.0))
        self.dilations_ = np.unique(
            np.floor(2.0 ** np.linspace(0, max_exp, int(self.n_dilations))).astype(int)
        )
        rng = np.random.default_rng(self.random_state)
        K = minirocket_kernels()
        nd, c, nb = len(self.dilations_), Z.shape[1], int(self.n_biases)
        q = (np.arange(nb) + rng.uniform(0.2, 0.8, size=nb)) / nb
        self.biases_ = np.empty((nd, len(K), c, nb), dtype=np.float32)
        examples = rng.integers(0, Z.shape[0], size=(nd, len(K)))
        for di, d in enumerate(self.dilations_):
            G, A = _conv_stack(Z[examples[di]], int(d))  # one example per kernel
            for ki, (a, b, cc) in enumerate(K):
                C = A[ki] + G[a, ki] + G[b, ki] + G[cc, ki]  # (c, L)
                self.biases_[di, ki] = np.quantile(C, q, axis=-1).T
        self.feature_mean_ = np.zeros(1, dtype=np.float32)
        self.feature_scale_ = np.ones(1, dtype=np.float32)
        F = self._ppv(Z)
        self.feature_mean_ = F.mean(axis=0)
        sd = F.std(axis=0)
        self.feature_scale_ = np.where(sd > 0, sd, 1.0).astype(np.float32)
        F = (F - self.feature_mean_) / self.feature_scale_
        cls = self.classes_ if self.classes_.ndim == 2 else self.classes_[:, None]
        self.heads_, idx = [], []
        for k in range(cls.shape[1]):
            col = cls[:, k]
            values, inv = np.unique(col, return_inverse=True)
            if len(values) == 1:
                self.heads_.append(None)
                idx.append(np.zeros(len(col), dtype=np.intp))
                continue
            if self.head == "ridge":
                h = RidgeClassifierCV(alphas=np.asarray(self.alphas, dtype=float))
            else:
                h = LogisticRegression(C=float(self.C), max_iter=2000)
            h.fit(F, inv.ravel()[y_idx])
            self.heads_.append(h)
            idx.append(np.asarray(inv).ravel())
        self.target_index_ = np.column_stack(idx)

    def _joint_scores(self, X: np.ndarray) -> np.ndarray:
        F = self._features(X)
        scores = np.zeros((X.shape[0], len(self.classes_)))
        for k, h in enumerate(self.heads_):
            if h is None:
                continue
            # log-softmax of the decision values: the logistic head's log posterior
            # without the underflow of log(predict_proba)
            dec = np.asarray(_decision_values(h, F), dtype=float)
            if dec.ndim == 1:  # binary: decision value of class 1
                dec = (
                    np.column_stack([np.zeros_like(dec), dec])
                    if isinstance(h, LogisticRegression)
                    else np.column_stack([-dec, dec]) / 2.0
                )
            lp = _log_softmax_rows(dec)
            scores += lp[:, self.target_index_[:, k]]
        return scores

    def transform(self, X: Any, sample_rate_hz: float | None = None) -> np.ndarray:
        """Standardised PPV features of trials (the input of the linear heads).

        Parameters
        ----------
        X : array-like of shape (n_trials, n_channels, n_timepoints)
        sample_rate_hz : float, optional
            Sample rate of ``X``, Hz; refused when not ``sample_rate_hz_``.

        Returns
        -------
        ndarray of shape (n_trials, n_features)
        """
        return self._features(self._fitted_input(X, sample_rate_hz))
