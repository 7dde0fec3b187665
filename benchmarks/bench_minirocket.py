"""Benchmark MiniRocketClassifier's predictions one trial at a time and in batches.

Usage::

    .venv/bin/python benchmarks/bench_minirocket.py [--train 200] [--batch 704]
        [--repeats 300] [--seed 0] [--out benchmarks/results/minirocket.json]

A streaming pipeline (:mod:`vibrissa.framework`) calls ``predict_proba`` once per
whisker contact, on ONE trial. The model is the default one of a 4 kHz stream
(``MiniRocketClassifier(sample_rate_hz=4000)``, ``pool`` 8), fitted on ``--train``
synthetic trials of 2 channels x 1,000 samples (random walks, three label columns
like chapter 5's angle, speed and texture). Timed on ONE core
(``os.sched_setaffinity`` and one BLAS thread), after a warm-up call:

* ``single``: ``predict_proba`` of one trial, ``--repeats`` calls (median, p99, min);
* ``few``: ``predict_proba`` of 4 trials at a time;
* ``batch``: ``predict_proba`` of ``--batch`` trials (the chapter-5 test set's size),
  best of 3.

"before" is the previous implementation (kept here as ``_Before``: the NumPy PPV
loop over kernels and dilations, scikit-learn's ``decision_function``); "after" the
current one (the compiled kernel ``classify._kernels.minirocket_ppv``). The record
also says whether the two give identical probabilities and features. Target: single
trial <= 1.5 ms, batch no slower than before.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as dt
import json
import os
import platform
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from vibrissa import __version__
from vibrissa._atomic import atomic_write_text
from vibrissa.classify import MiniRocketClassifier
from vibrissa.classify._rocket import _conv_stack, minirocket_kernels

SINGLE_TARGET_MS = 1.5
FS = 4000.0


class _Before(MiniRocketClassifier):
    """The implementation before the compiled kernel (NumPy PPV, sklearn's heads)."""

    def _ppv(self, Z):
        K = minirocket_kernels()
        n, c, _ = Z.shape
        nb = self.biases_.shape[-1]
        out = np.empty((n, len(self.dilations_), len(K), c, nb), dtype=np.float32)
        for s in range(0, n, int(self.chunk_size)):
            z = Z[s : s + int(self.chunk_size)]
            for di, d in enumerate(self.dilations_):
                G, A = _conv_stack(z, int(d))
                L = A.shape[-1]
                pairs = {}
                for ki, (a, b, cc) in enumerate(K):
                    if (a, b) not in pairs:
                        pairs = {(a, b): A + G[a] + G[b]}
                    C = pairs[(a, b)] + G[cc]
                    bias = self.biases_[di, ki]
                    out[s : s + len(z), di, ki] = (
                        np.count_nonzero(C[..., None, :] > bias[None, :, :, None], axis=-1) / L
                    )
        return out.reshape(n, -1)

    def _joint_scores(self, X):
        from scipy.special import log_softmax
        from sklearn.linear_model import LogisticRegression

        F = self._features(X)
        scores = np.zeros((X.shape[0], len(self.classes_)))
        for k, h in enumerate(self.heads_):
            if h is None:
                continue
            dec = np.asarray(h.decision_function(F), dtype=float)
            if dec.ndim == 1:
                dec = (
                    np.column_stack([np.zeros_like(dec), dec])
                    if isinstance(h, LogisticRegression)
                    else np.column_stack([-dec, dec]) / 2.0
                )
            scores += log_softmax(dec, axis=1)[:, self.target_index_[:, k]]
        return scores


def _data(n, seed):
    rng = np.random.default_rng(seed)
    X = rng.standard_normal((n, 2, 1000)).cumsum(axis=-1) * 1e-2
    y = np.column_stack(
        [rng.choice([0.0, 15.0, 30.0], n), rng.choice([50.0, 100.0], n), rng.integers(0, 4, n)]
    )
    return X, y


@contextlib.contextmanager
def _one_core():
    affinity = os.sched_getaffinity(0)
    cpu = min(affinity)
    os.sched_setaffinity(0, {cpu})
    try:
        with threadpool_limits(limits=1):
            yield cpu
    finally:
        os.sched_setaffinity(0, affinity)


def _times_ms(f, repeats):
    f()  # warm-up (compilation or cache load, first-call allocations)
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        t.append(1000.0 * (time.perf_counter() - t0))
    return np.array(t)


def _summary(t):
    return {
        "median_ms": round(float(np.median(t)), 4),
        "p99_ms": round(float(np.percentile(t, 99)), 4),
        "min_ms": round(float(t.min()), 4),
        "calls": int(t.size),
    }


def _measure(model, Xt, repeats):
    i = iter(range(10**9))
    single = _times_ms(lambda: model.predict_proba(Xt[next(i) % len(Xt)][None], FS), repeats)
    few = _times_ms(lambda: model.predict_proba(Xt[:4], FS), max(repeats // 3, 10))
    batch = _times_ms(lambda: model.predict_proba(Xt, FS), 3)
    return {
        "single": _summary(single),
        "few_4": _summary(few),
        "batch": {
            "n_trials": len(Xt),
            "best_s": round(float(batch.min()) / 1000.0, 4),
            "per_trial_ms": round(float(batch.min()) / len(Xt), 4),
        },
    }


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--train", type=int, default=200)
    ap.add_argument("--batch", type=int, default=704)
    ap.add_argument("--repeats", type=int, default=300)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="benchmarks/results/minirocket.json")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    X, y = _data(args.train, args.seed)
    Xt, _ = _data(args.batch, args.seed + 1)
    with _one_core() as cpu:
        fits, runs, models = {}, {}, {}
        for name, cls in (("before", _Before), ("after", MiniRocketClassifier)):
            t0 = time.perf_counter()
            models[name] = cls(sample_rate_hz=FS).fit(X, y, FS)
            fits[name] = round(time.perf_counter() - t0, 3)
            runs[name] = _measure(models[name], Xt, args.repeats)
            print(name, json.dumps(runs[name]))
        before, after = models["before"], models["after"]
        singles = range(min(len(Xt), 50))
        same = {
            "batch_probabilities": bool(
                np.array_equal(before.predict_proba(Xt), after.predict_proba(Xt))
            ),
            "single_probabilities": all(
                np.array_equal(before.predict_proba(Xt[i][None]), after.predict_proba(Xt[i][None]))
                for i in singles
            ),
            "features": bool(np.array_equal(before.transform(Xt), after.transform(Xt))),
            "single_features_equal_batch_rows": bool(
                np.array_equal(
                    np.concatenate([after.transform(Xt[i][None]) for i in singles]),
                    after.transform(Xt[: len(singles)]),
                )
            ),
        }
        print("identical:", same)
    single_ms = runs["after"]["single"]["median_ms"]
    out = {
        "machine": {
            "cores": os.cpu_count(),
            "cpu_used": cpu,
            "python": platform.python_version(),
            "platform": platform.platform(),
        },
        "load_average_at_start": round(load, 2),
        "command": "benchmarks/bench_minirocket.py "
        + " ".join(f"--{k.replace('_', '-')} {v}" for k, v in vars(args).items() if k != "out"),
        "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        "vibrissa_version": __version__,
        "model": {
            "estimator": "MiniRocketClassifier(sample_rate_hz=4000)",
            "pool": int(after.pool_),
            "dilations": [int(d) for d in after.dilations_],
            "n_features": int(after.feature_mean_.size),
            "train_trials": args.train,
            "trial_shape": [2, 1000],
        },
        "fit_seconds": fits,
        "targets": {"single_median_ms": SINGLE_TARGET_MS, "batch": "no slower than before"},
        "runs": runs,
        "speedup": {
            "single_median": round(runs["before"]["single"]["median_ms"] / single_ms, 1),
            "batch": round(runs["before"]["batch"]["best_s"] / runs["after"]["batch"]["best_s"], 1),
        },
        "identical_to_before": same,
        "meets_single_target": single_ms <= SINGLE_TARGET_MS,
        "batch_no_slower": runs["after"]["batch"]["best_s"] <= runs["before"]["batch"]["best_s"],
    }
    atomic_write_text(Path(args.out), json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
