"""How long must window mode's lead-in be? (CrunchBot floor whiskers, issue 16.)

Drives straight over one texture at FWD speed in 0.5 s steps, once continuously and once
in window mode (only each step's last 100 ms, after a lead-in from the whisker settled at
rest) for several lead-ins, and compares the statistics of the steps' last 100 ms of each
floor whisker: RMS about the window's mean of x and y, RMS of the velocity (what the
naive Bayes histograms), and the spectral centroid. Prints one table per texture and the
wall time per 0.5 s step both ways. A measurement, not a test: timings depend on the
machine's load.

Usage: ``python scripts/floor_whisker_lead_in.py [seconds] [lead-ins...]``
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from vibrissa import signal as vsig
from vibrissa.robots.crunchbot.arena import Arena, Pose
from vibrissa.robots.crunchbot.floor_whiskers import FWD_SPEED_M_S, FloorWhiskers

FS = 2000.0
STEP = 1000
WINDOW = 200


def stats(windows: np.ndarray) -> np.ndarray:
    """Per window (k, 200, 2 whiskers, 2 channels) -> (k*2, 4) statistics."""
    w = np.moveaxis(windows, 2, 1).reshape(-1, WINDOW, 2).astype(float)
    rms = w.std(axis=1)
    vel = vsig.velocity(np.moveaxis(w, 1, 2), FS, sigma_samples=3.0).std(axis=2).mean(axis=1)
    spec = np.abs(np.fft.rfft(w - w.mean(axis=1, keepdims=True), axis=1)) ** 2
    f = np.fft.rfftfreq(WINDOW, 1 / FS)
    centroid = (spec * f[None, :, None]).sum(axis=1) / spec.sum(axis=1)
    return np.column_stack([rms, vel, centroid.mean(axis=1)])


def run(texture: str, seconds: float, lead_in: float | None) -> tuple[np.ndarray, float]:
    arena = Arena(name="one", size_m=3.0, start=Pose(0.2, 1.5, 0.0), tiles=((texture,) * 6,) * 6)
    fw = FloorWhiskers(arena, seed=3, lead_in_s=lead_in or 0.1)
    n_steps = int(seconds / 0.5)
    out, wall = [], 0.0
    for k in range(n_steps):
        t = (np.arange(STEP) + 1 + k * STEP) / FS
        pose = np.column_stack([0.2 + FWD_SPEED_M_S * t, np.full(STEP, 1.5), np.zeros(STEP)])
        t0 = time.perf_counter()
        h = fw.advance(t, pose, window_s=None if lead_in is None else 0.1)
        wall += time.perf_counter() - t0
        out.append(h[-WINDOW:])
    return stats(np.stack(out[1:])), wall / n_steps


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 8.0
    leads = [float(x) for x in sys.argv[2:]] or [0.02, 0.05, 0.1, 0.2, 0.3]
    names = ("rms_x", "rms_y", "vel_rms", "centroid_hz")
    for texture in os.environ.get("TEXTURES", "vinyl,smooth-carpet,rough-carpet").split(","):
        ref, wall = run(texture, seconds, None)
        m, se = ref.mean(0), ref.std(0) / np.sqrt(len(ref))
        print(
            f"\n{texture}: continuous {wall:.3f} s per step; "
            + ", ".join(f"{n} {a:.4g}+-{b:.2g}" for n, a, b in zip(names, m, se, strict=True))
        )
        for lead in leads:
            got, wall = run(texture, seconds, lead)
            ratio = got.mean(0) / m
            print(
                f"  lead-in {lead:.2f} s: {wall:.3f} s per step; ratio to continuous "
                + ", ".join(f"{n} {r:.3f}" for n, r in zip(names, ratio, strict=True))
            )


if __name__ == "__main__":
    main()
