"""Benchmark the streaming tactile pipeline (``vibrissa.framework``) on a BIOTACT G1 head.

Usage::

    .venv/bin/python benchmarks/bench_framework.py [--seconds 60] [--chunk 20]
        [--whiskers 24] [--rate 2000] [--seed 0] [--out benchmarks/results/framework.json]

A synthetic G1 stream (24 whiskers x 2 Hall channels at 2 kHz: rest 2.5 V, Gaussian
noise of 5 mV and class-shaped contact bumps, about 2 contacts per whisker per second,
half of them tip contacts on one surface) is fed to ``TactilePipeline`` in chunks of
``--chunk`` samples on ONE core (``os.sched_setaffinity`` and one BLAS thread). The
default models are fitted first on a small synthetic training stream: the where model
(``default_where_estimator``) at 1 kHz, the rate of chapter 4, and the what model at
the stream's rate. Recorded: headroom = data seconds / wall seconds (target >= 10), the
wall time of the ``feed`` calls that emit reports (p50, p99, max; target p99 <= 10 ms)
and, because the default what estimator (MiniRocket) costs about 10 ms per contact, the
same for alternative what estimators, each with its single-contact accuracy (angle and
texture both right) on held-out synthetic tip contacts.
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
from vibrissa.classify import MiniRocketClassifier, StationaryNaiveBayes
from vibrissa.framework import (
    TactilePipeline,
    contact_windows,
    default_what_estimator,
    default_where_estimator,
    fit_what,
    fit_where,
)

HEADROOM_TARGET = 10.0
P99_TARGET_MS = 10.0
REST_V = 2.5
#: (radial_distance_mm, speed_mm_s) -> (bump amplitude V, duration s)
SHAPES = {(30.0, 50.0): (1.0, 0.2), (30.0, 100.0): (1.0, 0.12),
          (60.0, 50.0): (0.4, 0.2), (60.0, 100.0): (0.4, 0.12)}  # fmt: skip
ANGLE_RATIO = {0.0: 0.1, 30.0: 0.7}
TEXTURE_V = {0.0: 0.0, 3.0: 0.06}


def _stream(seconds, fs, n_whiskers, seed, surface=None):
    """Samples ``(n, n_whiskers, 2)`` and events ``(whisker, onset k, class)``.

    ``surface``: tip contacts all of that ``(angle, texture)`` (a live surface), else
    every class at random (a training set).
    """
    rng = np.random.default_rng(seed)
    n = int(round(seconds * fs))
    x = REST_V + 0.005 * rng.standard_normal((n, n_whiskers, 2))
    events = []
    for w in range(n_whiskers):
        t = 0.2 + rng.exponential(0.28)
        while t < seconds - 0.8:
            radial = float(rng.choice([30.0, 60.0]))
            speed = float(rng.choice([50.0, 100.0]))
            angle, texture = (
                surface
                if surface is not None and radial == 60.0
                else (float(rng.choice([0.0, 30.0])), float(rng.choice([0.0, 3.0])))
            )
            amp, dur = SHAPES[(radial, speed)]
            tt = np.arange(int(round(dur * fs))) / fs
            env = np.sin(np.pi * tt / dur)
            b = amp * env + TEXTURE_V[texture] * env * np.sin(
                2 * np.pi * 150 * tt + rng.uniform(0, 2 * np.pi)
            )
            k = int(round(t * fs))
            x[k : k + len(b), w, 0] += b
            x[k : k + len(b), w, 1] += ANGLE_RATIO[angle] * b
            events.append((w, k, (radial, speed, angle, texture)))
            t += dur + 0.06 + rng.exponential(0.28)
    return x, events


def _labelled(x, events, fs):
    contacts = contact_windows(x, fs)
    by_whisker: dict[int, list] = {}
    for w, k, c in events:
        by_whisker.setdefault(w, []).append((k, c))
    labels = []
    for c in contacts:
        k, cls = min(by_whisker[c.whisker], key=lambda e: abs(e[0] - c.onset_index))
        labels.append(cls)
    return np.stack([c.window for c in contacts]), np.array(labels)


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


def _run(pipe, x, chunk):
    """Feed ``x`` in chunks; wall seconds, latencies (ms) of emitting feeds, reports."""
    lat, reports = [], []
    t0 = time.perf_counter()
    for a in range(0, len(x), chunk):
        t1 = time.perf_counter()
        out = pipe.feed(x[a : a + chunk])
        if out:
            lat.append(1000 * (time.perf_counter() - t1))
            reports += out
    reports += pipe.flush()
    return time.perf_counter() - t0, np.array(lat), reports


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--chunk", type=int, default=20)
    ap.add_argument("--whiskers", type=int, default=24)
    ap.add_argument("--rate", type=float, default=2000.0)
    ap.add_argument("--train-seconds", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="benchmarks/results/framework.json")
    args = ap.parse_args()
    fs = args.rate
    load = os.getloadavg()[0]
    with _one_core() as cpu:
        t0 = time.perf_counter()
        W, y = _labelled(*_stream(args.train_seconds, fs, 8, args.seed + 1), fs)
        Wh, yh = _labelled(*_stream(args.train_seconds, fs, 8, args.seed + 2), fs)
        where = fit_where(default_where_estimator(1000.0), W, y[:, :2], fs, 1000.0, 55.0)
        tip, tip_h = y[:, 0] == 60.0, yh[:, 0] == 60.0
        what_y, what_yh = y[tip][:, [2, 1, 3]], yh[tip_h][:, [2, 1, 3]]
        train_s = time.perf_counter() - t0
        where_acc = float(
            np.mean(where.classes[np.argmax(where.predict_proba(Wh, fs), 1), 0] == yh[:, 0])
        )
        x, events = _stream(args.seconds, fs, args.whiskers, args.seed, surface=(30.0, 3.0))
        candidates = {
            "minirocket (default)": default_what_estimator(fs),
            "minirocket n_dilations=2": MiniRocketClassifier(
                pool=default_what_estimator(fs).pool, n_dilations=2, sample_rate_hz=fs
            ),
            "naive_bayes_velocity": StationaryNaiveBayes(signal="velocity", sample_rate_hz=fs),
            "none (where only)": None,
        }
        runs = {}
        for name, est in candidates.items():
            what = None
            acc = None
            if est is not None:
                what = fit_what(est, W[tip], what_y, fs, fs)
                pred = what.classes[np.argmax(what.predict_proba(Wh[tip_h], fs), 1)]
                acc = float(np.mean((pred[:, [0, 2]] == what_yh[:, [0, 2]]).all(axis=1)))
            pipe = TactilePipeline(fs, args.whiskers, 2, where=where, what=what)
            wall, lat, reports = _run(pipe, x, args.chunk)
            decisions = [r.decision for r in reports if r.decision]
            headroom = args.seconds / wall
            p50, p99, mx = (float(np.percentile(lat, q)) for q in (50, 99, 100))
            runs[name] = {
                "wall_seconds": round(wall, 3),
                "headroom": round(headroom, 2),
                "latency_ms": {"p50": round(p50, 3), "p99": round(p99, 3), "max": round(mx, 3)},
                "n_emitting_feeds": int(lat.size),
                "n_reports": len(reports),
                "n_tip_reports": sum(r.tip for r in reports),
                "n_decisions": len(decisions),
                "decisions_right": sum(
                    (d["angle_deg"], d["texture"]) == (30.0, "p80") for d in decisions
                ),
                "single_contact_what_accuracy": None if acc is None else round(acc, 3),
                "meets_headroom_target": headroom >= HEADROOM_TARGET,
                "meets_p99_target": p99 <= P99_TARGET_MS,
            }
            print(name, json.dumps(runs[name]))
    machine = {
        "cores": os.cpu_count(),
        "cpu_used": cpu,
        "python": platform.python_version(),
        "platform": platform.platform(),
    }
    out = {
        "machine": machine,
        "load_average_at_start": round(load, 2),
        "command": "benchmarks/bench_framework.py "
        + " ".join(f"--{k.replace('_', '-')} {v}" for k, v in vars(args).items() if k != "out"),
        "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        "vibrissa_version": __version__,
        "stream": {
            "whiskers": args.whiskers,
            "channels": 2,
            "sample_rate_hz": fs,
            "seconds": args.seconds,
            "chunk_samples": args.chunk,
            "n_contacts": len(events),
            "contacts_per_whisker_per_s": round(len(events) / args.whiskers / args.seconds, 2),
        },
        "training": {
            "seconds": round(train_s, 2),
            "n_contacts": int(len(W)),
            "n_tip_contacts": int(tip.sum()),
            "where_model_rate_hz": 1000.0,
            "where_tip_or_shaft_accuracy_held_out": round(where_acc, 3),
        },
        "targets": {"headroom": HEADROOM_TARGET, "p99_ms": P99_TARGET_MS},
        "runs": runs,
    }
    atomic_write_text(Path(args.out), json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
