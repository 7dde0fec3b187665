"""Measurements quoted in docs/methods.md, on the full chapter-4 dataset.

Usage::

    .venv/bin/vibrissa reproduce radial-distance          # makes the dataset
    .venv/bin/python scripts/methods_measurements.py \
        vibrissa-out/radial-distance/data/radial-distance-*.nc

Prints one line per measurement: the frequency method's window against the
contact, what the ring-down in that window carries, the frequency method on
other windows, the feature method with and without the author's training rules,
and naive Bayes under the histogram settings discussed in the thesis-methods
issue. Split: train set 3 (or sets 2-4 where stated), test set 1, as the author.
"""

from __future__ import annotations

import sys
import warnings

import numpy as np
from sklearn.pipeline import Pipeline

from vibrissa.classify import (
    FeatureRegressionClassifier,
    FrequencyTemplateClassifier,
    RecordingWindow,
    StationaryNaiveBayes,
    onset_window,
    peak_window,
)
from vibrissa.classify._feature import contact_features
from vibrissa.data import load_dataset
from vibrissa.evaluate.protocol import dataset_arrays, fit_and_score

FS = 1000.0


def main(path: str) -> None:
    warnings.simplefilter("ignore", RuntimeWarning)
    ds = load_dataset(path)
    X, y = dataset_arrays(ds)
    sets = np.asarray(ds["set"].values)
    one, pooled, test = sets == 3, np.isin(sets, [2, 3, 4]), sets == 1

    def run(label: str, est, train=one) -> None:
        r = fit_and_score(label, est, X[train], y[train], X[test], y[test])
        sp = r["speed_mm_s"]
        print(f"{label}: radius std {r['radius_mm']['std']:.2f} mm"
              + (f", speed std {sp['std']:.2f} mm/s" if sp else ""))

    onset = onset_window(FS).fit(X).alignment_index(X)
    peak = np.argmax(np.abs(X[:, 0] - 2.5), axis=1)
    print(f"onset to peak: median {np.median(peak - onset):.0f} ms, "
          f"5-95 % {np.percentile(peak - onset, 5):.0f}-{np.percentile(peak - onset, 95):.0f} ms")
    print(f"contact duration: median {np.median(ds['contact_duration_s'].values):.3f} s")
    tail = onset_window(FS, start_at_1khz=500, n_at_1khz=250).fit(X).transform(X)[:, 0]
    tail = tail - tail.mean(axis=1, keepdims=True)
    f = np.fft.rfftfreq(250, 1 / FS)
    dom = f[np.argmax(np.abs(np.fft.rfft(tail, axis=1))[:, 1:], axis=1) + 1]
    rms = tail.std(axis=1)
    noise = np.median(X[:, 0, :50].std(axis=1))
    print(f"Hall noise before contact: {noise * 1e3:.2f} mV rms")
    for lo in (80, 130):
        m = (y[:, 0] >= lo) & (y[:, 0] < lo + 50)
        print(f"frequency window, radii {lo}-{lo + 50} mm: dominant {np.median(dom[m]):.0f} Hz, "
              f"ring {np.median(rms[m]) * 1e3:.1f} mV rms")
    for lo in (36, 180):
        m = (y[:, 1] >= lo) & (y[:, 1] < lo + 36)
        ring_mv = np.median(rms[m]) * 1e3
        print(f"frequency window, speeds {lo}-{lo + 36} mm/s: ring {ring_mv:.1f} mV rms")

    l1 = dict(sample_rate_hz=FS, cutoff_hz=None, spectrum="abs_real", one_sided=False,
              zero_dc=True, distance="l1")
    for label, start, n in (("author's samples 501-750", 500, 250),
                            ("samples 1-250", 0, 250), ("all 750 samples", 0, 750)):
        run(f"frequency, {label} of the onset window",
            Pipeline([("w", onset_window(FS, start_at_1khz=start, n_at_1khz=n)),
                      ("c", FrequencyTemplateClassifier(**l1))]))
    run("frequency, text reading (|X| of +/-325 ms peak window, both channels, SSE)",
        Pipeline([("w", peak_window(FS)), ("c", FrequencyTemplateClassifier(sample_rate_hz=FS))]))
    run("frequency, text reading without DC and low-pass",
        Pipeline([("w", peak_window(FS)), ("c", FrequencyTemplateClassifier(
            sample_rate_hz=FS, cutoff_hz=None, zero_dc=True))]))

    W = onset_window(FS).fit(X).transform(X)
    widths = contact_features(W, FS, 0.05, 0, 2.5, "peak")[:, 1]
    print(f"feature f2 (width above 0.05 V): median {np.median(widths):.3f} s, "
          f"{np.mean(widths < 0.35) * 100:.0f} % below the author's 0.35 s floor")
    for label, kw in (("author's rules (span 5, floor 0.35 s)",
                       dict(duration_smoothing_span=5, min_duration_s=0.35)),
                      ("no smoothing, no floor", {})):
        for deg in (4, 5):
            run(f"feature, degree {deg}, {label}",
                Pipeline([("w", onset_window(FS)), ("c", FeatureRegressionClassifier(
                    sample_rate_hz=FS, degree=deg, duration_mode="peak", **kw))]))

    vel = onset_window(FS, signal="velocity")
    eps = float(np.finfo(float).eps)
    for label, kw in (
        ("author's (500 bins over +/-100 V/s, sigma 1 bin cut at 10)",
         dict(n_bins=500, value_range=(-100.0, 100.0), smoothing_sigma=1.0,
              smoothing_radius_bins=10, likelihood_floor=eps)),
        ("text reading (100 bins over the full range, sigma 5 bins)",
         dict(n_bins=100, value_range=None, smoothing_sigma=5.0)),
        ("100 bins over the full range, no smoothing",
         dict(n_bins=100, value_range=None, smoothing_sigma=0.0)),
        ("estimator default (100 bins over the central 99 %, sigma 1 bin)", {}),
    ):
        run(f"naive Bayes velocity, {label}, sets 2-4",
            Pipeline([("w", vel), ("nb", StationaryNaiveBayes(signal="raw", sample_rate_hz=FS,
                                                               **kw))]), train=pooled)
    run("naive Bayes velocity, author's, x and y channels, sets 2-4",
        Pipeline([("w", RecordingWindow(signal="velocity", channels=None)),
                  ("nb", StationaryNaiveBayes(signal="raw", n_bins=500,
                                              value_range=(-100.0, 100.0), smoothing_sigma=1.0,
                                              smoothing_radius_bins=10,
                                              likelihood_floor=eps))]), train=pooled)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
