"""Measurements quoted in docs/methods.md, on the full chapter-4 dataset.

Usage::

    .venv/bin/vibrissa reproduce radial-distance          # makes the dataset
    .venv/bin/python scripts/methods_measurements.py \\
        vibrissa-out/radial-distance/data/radial-distance-*.nc [--json docs/runs/methods.json]

Prints one line per measurement: the frequency method's window against the
contact, what the ring-down in that window carries, the frequency method on
other windows, the feature method with and without the author's training rules,
and naive Bayes under the histogram settings discussed in the thesis-methods
issue. Split: train set 3 (or sets 2-4 where stated), test set 1, as the author.
With ``--json OUT`` it also writes the measurements as a run file for
``scripts/render_docs.py`` (keys as in :func:`measure`).
"""

from __future__ import annotations

import argparse
import shlex
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from sklearn.pipeline import Pipeline

from vibrissa.classify import (
    FeatureRegressionClassifier,
    FrequencyTemplateClassifier,
    RecordingWindow,
    StationaryNaiveBayes,
    contact_features,
    onset_window,
    peak_window,
)
from vibrissa.data import load_dataset
from vibrissa.thesis.radial_distance.evaluation import dataset_arrays, fit_and_score

sys.path.insert(0, str(Path(__file__).resolve().parent))
from render_docs import run_meta, write_run

FS = 1000.0


def measure(path: str) -> dict[str, Any]:
    """Every measurement, printed as it is made; returns them as nested dicts.

    Units are in the key names (``_ms``, ``_s``, ``_mv``, ``_hz``, ``_mm``,
    ``_mm_s``, ``_v_s``, ``_percent``). A classifier's entry is
    ``{"radius_std_mm", "speed_std_mm_s"}`` (std of the signed error on test set 1).
    """
    warnings.simplefilter("ignore", RuntimeWarning)
    ds = load_dataset(path)
    X, y = dataset_arrays(ds)
    sets = np.asarray(ds["set"].values)
    one, pooled, test = sets == 3, np.isin(sets, [2, 3, 4]), sets == 1
    out: dict[str, Any] = {"n_trials": int(X.shape[0])}

    def run(label: str, est, train=one) -> dict[str, float | None]:
        r = fit_and_score(label, est, X[train], y[train], X[test], y[test])
        sp = r["speed_mm_s"]
        print(
            f"{label}: radius std {r['radius_mm']['std']:.2f} mm"
            + (f", speed std {sp['std']:.2f} mm/s" if sp else "")
        )
        return {
            "radius_std_mm": float(r["radius_mm"]["std"]),
            "speed_std_mm_s": float(sp["std"]) if sp else None,
        }

    radii, speeds = np.unique(y[test, 0]), np.unique(y[test, 1])
    mixup = speeds.min() - y[test, 1]
    out["grid"] = {
        "frequency_mixup_speed_error_mm_s": {
            "mean": float(mixup.mean()),
            "std": float(mixup.std()),
        },
        "constant_guess_radius_std_mm": float(radii.std()),
        "uniform_guess_radius_std_mm": float(np.sqrt(2.0) * radii.std()),
    }
    print(
        "speed error of always the slowest template: "
        f"mean {mixup.mean():.1f}, std {mixup.std():.1f} mm/s; radius std of a constant "
        f"guess {radii.std():.1f} mm, of a uniform random guess "
        f"{np.sqrt(2.0) * radii.std():.1f} mm"
    )

    onset = onset_window(FS).fit(X).alignment_index(X)
    peak = np.argmax(np.abs(X[:, 0] - 2.5), axis=1)
    lag = peak - onset
    out["onset_to_peak_ms"] = {
        "median": float(np.median(lag)),
        "p5": float(np.percentile(lag, 5)),
        "p95": float(np.percentile(lag, 95)),
    }
    print(
        f"onset to peak: median {np.median(lag):.0f} ms, "
        f"5-95 % {np.percentile(lag, 5):.0f}-{np.percentile(lag, 95):.0f} ms"
    )
    duration = float(np.median(ds["contact_duration_s"].values))
    out["contact_duration_s"] = {"median": duration}
    print(f"contact duration: median {duration:.3f} s")
    tail = onset_window(FS, start_at_1khz=500, n_at_1khz=250).fit(X).transform(X)[:, 0]
    tail = tail - tail.mean(axis=1, keepdims=True)
    f = np.fft.rfftfreq(250, 1 / FS)
    dom = f[np.argmax(np.abs(np.fft.rfft(tail, axis=1))[:, 1:], axis=1) + 1]
    rms = tail.std(axis=1)
    noise = float(np.median(X[:, 0, :50].std(axis=1)))
    print(f"Hall noise before contact: {noise * 1e3:.2f} mV rms")
    window: dict[str, Any] = {
        "bin_hz": float(f[1]),
        "hall_noise_mv_rms": noise * 1e3,
        "dominant_hz": {},
        "ring_mv_rms": {},
    }
    for lo in (80, 130):
        m = (y[:, 0] >= lo) & (y[:, 0] < lo + 50)
        key = f"radius_{lo}_{lo + 50}"
        window["dominant_hz"][key] = float(np.median(dom[m]))
        window["ring_mv_rms"][key] = float(np.median(rms[m]) * 1e3)
        print(
            f"frequency window, radii {lo}-{lo + 50} mm: dominant {np.median(dom[m]):.0f} Hz, "
            f"ring {np.median(rms[m]) * 1e3:.1f} mV rms"
        )
    for lo in (36, 180):
        m = (y[:, 1] >= lo) & (y[:, 1] < lo + 36)
        ring_mv = float(np.median(rms[m]) * 1e3)
        window["ring_mv_rms"][f"speed_{lo}_{lo + 36}"] = ring_mv
        print(f"frequency window, speeds {lo}-{lo + 36} mm/s: ring {ring_mv:.1f} mV rms")
    out["frequency_window"] = window

    l1 = dict(
        sample_rate_hz=FS,
        cutoff_hz=None,
        spectrum="abs_real",
        one_sided=False,
        zero_dc=True,
        distance="l1",
    )
    freq: dict[str, Any] = {}
    for key, label, start, n in (
        ("author_samples_501_750", "author's samples 501-750", 500, 250),
        ("samples_1_250", "samples 1-250", 0, 250),
        ("samples_1_750", "all 750 samples", 0, 750),
    ):
        freq[key] = run(
            f"frequency, {label} of the onset window",
            Pipeline(
                [
                    ("w", onset_window(FS, start_at_1khz=start, n_at_1khz=n)),
                    ("c", FrequencyTemplateClassifier(**l1)),
                ]
            ),
        )
    freq["text_reading"] = run(
        "frequency, text reading (|X| of +/-325 ms peak window, both channels, SSE)",
        Pipeline([("w", peak_window(FS)), ("c", FrequencyTemplateClassifier(sample_rate_hz=FS))]),
    )
    freq["text_reading_no_dc"] = run(
        "frequency, text reading without DC and low-pass",
        Pipeline(
            [
                ("w", peak_window(FS)),
                ("c", FrequencyTemplateClassifier(sample_rate_hz=FS, cutoff_hz=None, zero_dc=True)),
            ]
        ),
    )
    out["frequency"] = freq

    W = onset_window(FS).fit(X).transform(X)
    widths = contact_features(W, FS, 0.05, 0, 2.5, "peak")[:, 1]
    feature: dict[str, Any] = {
        "width_median_s": float(np.median(widths)),
        "below_floor_percent": float(np.mean(widths < 0.35) * 100),
    }
    print(
        f"feature f2 (width above 0.05 V): median {np.median(widths):.3f} s, "
        f"{np.mean(widths < 0.35) * 100:.0f} % below the author's 0.35 s floor"
    )
    for key, label, kw in (
        (
            "author_rules",
            "author's rules (span 5, floor 0.35 s)",
            dict(duration_smoothing_span=5, min_duration_s=0.35),
        ),
        ("no_rules", "no smoothing, no floor", {}),
    ):
        feature[key] = {}
        for deg in (4, 5):
            feature[key][f"degree_{deg}"] = run(
                f"feature, degree {deg}, {label}",
                Pipeline(
                    [
                        ("w", onset_window(FS)),
                        (
                            "c",
                            FeatureRegressionClassifier(
                                sample_rate_hz=FS, degree=deg, duration_mode="peak", **kw
                            ),
                        ),
                    ]
                ),
            )
    out["feature"] = feature

    vel = onset_window(FS, signal="velocity")
    v = vel.fit(X).transform(X[pooled])[:, 0].ravel()
    nb: dict[str, Any] = {
        "full_range_bin_v_s": float(np.ptp(v) / 100),
        "abs_velocity_p95_v_s": float(np.percentile(np.abs(v), 95)),
    }
    print(
        f"velocity (x, onset window, sets 2-4): 100 bins over the full range are "
        f"{np.ptp(v) / 100:.2f} V/s wide; 95 % of |v| below "
        f"{np.percentile(np.abs(v), 95):.2f} V/s"
    )
    eps = float(np.finfo(float).eps)
    for key, label, kw in (
        (
            "author",
            "author's (500 bins over +/-100 V/s, sigma 1 bin cut at 10)",
            dict(
                n_bins=500,
                value_range=(-100.0, 100.0),
                smoothing_sigma=1.0,
                smoothing_radius_bins=10,
                likelihood_floor=eps,
            ),
        ),
        (
            "text_reading",
            "text reading (100 bins over the full range, sigma 5 bins)",
            dict(n_bins=100, value_range=None, smoothing_sigma=5.0),
        ),
        (
            "full_range_no_smoothing",
            "100 bins over the full range, no smoothing",
            dict(n_bins=100, value_range=None, smoothing_sigma=0.0),
        ),
        (
            "estimator_default",
            "estimator default (100 bins over the central 99 %, sigma 1 bin)",
            {},
        ),
    ):
        nb[key] = run(
            f"naive Bayes velocity, {label}, sets 2-4",
            Pipeline(
                [("w", vel), ("nb", StationaryNaiveBayes(signal="raw", sample_rate_hz=FS, **kw))]
            ),
            train=pooled,
        )
    nb["author_xy"] = run(
        "naive Bayes velocity, author's, x and y channels, sets 2-4",
        Pipeline(
            [
                ("w", RecordingWindow(signal="velocity", channels=None)),
                (
                    "nb",
                    StationaryNaiveBayes(
                        signal="raw",
                        n_bins=500,
                        value_range=(-100.0, 100.0),
                        smoothing_sigma=1.0,
                        smoothing_radius_bins=10,
                        likelihood_floor=eps,
                    ),
                ),
            ]
        ),
        train=pooled,
    )
    nb["text_reading_peak_window_set_3"] = run(
        "naive Bayes velocity, text reading on the +/-325 ms peak window (both channels), set 3",
        Pipeline(
            [
                ("w", peak_window(FS)),
                (
                    "nb",
                    StationaryNaiveBayes(
                        signal="velocity",
                        sample_rate_hz=FS,
                        n_bins=100,
                        value_range=None,
                        smoothing_sigma=5.0,
                    ),
                ),
            ]
        ),
    )
    out["naive_bayes"] = nb
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", help="the full chapter-4 dataset (.nc)")
    ap.add_argument(
        "--json",
        metavar="OUT",
        default=None,
        help="also write the measurements as a run file (docs/runs/methods.json)",
    )
    args = ap.parse_args(argv)
    values = measure(args.dataset)
    if args.json:
        cmd = ".venv/bin/python scripts/methods_measurements.py " + " ".join(
            shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:])
        )
        write_run(args.json, {"meta": run_meta(cmd, args.dataset), **values})


if __name__ == "__main__":
    main()
