"""Real-time floor-texture accuracy on the figure-6.11 course (CrunchBot, thesis 6.5.6.1).

Trains :class:`~vibrissa.classify.realtime.FloorTextureNB` on 6.5.2's training runs
(:func:`~vibrissa.robots.crunchbot.floor_whiskers.collect_floor_training`: each texture
driven over five tiles at FWD speed) and drives the test courses, classifying the latest
200 samples of each floor whisker every 100 ms:

- two textures as in 6.5.6.1 (rough carpet and vinyl) on the figure-6.11 course;
- all three textures on the same course and on rough carpet / vinyl / smooth carpet.

Prints the accuracy per 100 ms window (both whiskers), the accuracy away from the tile
boundaries (windows wholly on one tile) and the latency of ``loglik`` (median, p99). A
measurement, not a test.

Usage: ``python scripts/floor_texture_accuracy.py [seconds_per_texture] [seed]``
"""

from __future__ import annotations

import sys
import time

import numpy as np

from vibrissa.classify.realtime import FloorTextureNB
from vibrissa.robots.crunchbot.floor_whiskers import (
    FIGURE_6_11,
    WINDOW_SAMPLES,
    collect_floor_training,
    texture_course,
)

THREE = ("vinyl", "smooth-carpet", "rough-carpet")


def report(name: str, nb: FloorTextureNB, textures: tuple[str, ...], seed: int) -> None:
    t0 = time.perf_counter()
    course = texture_course(textures, seed=seed, classifier=nb)
    wall = time.perf_counter() - t0
    truth = course.truth_at_decisions
    ends = np.searchsorted(course.time_s, course.decision_time_s - 1e-9)
    starts = ends - WINDOW_SAMPLES + 1
    whole = course.texture_true[starts] == course.texture_true[ends]
    hit = course.texture_pred == truth
    per = {w: float(np.mean(hit[:, i])) for i, w in enumerate(("left", "right"))}
    print(
        f"{name}: {course.decision_time_s.size} windows x 2 whiskers, accuracy "
        f"{course.accuracy():.3f} (left {per['left']:.3f}, right {per['right']:.3f}); "
        f"windows wholly on one tile {float(np.mean(hit[whole])):.3f}; course simulated "
        f"in {wall:.1f} s",
        flush=True,
    )
    for cls in nb.classes_:
        m = truth == cls
        if m.any():
            print(f"    on {cls}: {float(np.mean(hit[m])):.3f} of {int(m.sum())}", flush=True)


def latency(nb: FloorTextureNB, windows: np.ndarray) -> None:
    times = []
    for i in range(5000):
        w = windows[i % len(windows)]
        t0 = time.perf_counter()
        nb.loglik(w)
        times.append(time.perf_counter() - t0)
    ms = 1e3 * np.array(times)
    print(
        f"loglik latency ({len(nb.classes_)} classes): median {np.median(ms):.3f} ms, "
        f"p99 {np.percentile(ms, 99):.3f} ms",
        flush=True,
    )


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 50.0
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 0
    t0 = time.perf_counter()
    windows, labels = collect_floor_training(THREE, seconds, seed=seed + 100)
    print(f"training: {len(labels)} windows in {time.perf_counter() - t0:.1f} s", flush=True)
    two = np.isin(labels, ("rough-carpet", "vinyl"))
    nb2 = FloorTextureNB().fit(windows[two], labels[two], 2000.0)
    nb3 = FloorTextureNB().fit(windows, labels, 2000.0)
    latency(nb2, windows)
    latency(nb3, windows)
    report("two textures, figure 6.11 course", nb2, FIGURE_6_11, seed)
    report("three textures, figure 6.11 course", nb3, FIGURE_6_11, seed)
    report(
        "three textures, rough carpet / vinyl / smooth carpet",
        nb3,
        ("rough-carpet", "vinyl", "smooth-carpet"),
        seed,
    )


if __name__ == "__main__":
    main()
