"""The thesis' chapter-5 numbers (Evans 2011, 5.4).

Kappas and signed errors of tables 5.1-5.11 and figure 5.15.
"""

from __future__ import annotations

from typing import Any


def _k(angle, speed, texture, alone, table=None) -> dict[str, Any]:
    return {
        "kappa": {"angle": angle, "speed": speed, "texture": texture, "texture_alone": alone},
        "errors": table,
    }


def _t(a_mean, a_std, s_mean, s_std, t_mean, t_std) -> dict[str, Any]:
    return {
        "angle_deg": {"mean": a_mean, "std": a_std},
        "speed_mm_s": {"mean": s_mean, "std": s_std},
        "texture": {"mean": t_mean, "std": t_std},
    }


#: Thesis values (Evans 2011, 5.4). ``kappa``: simultaneous angle, speed, texture and
#: texture alone (trained per speed-angle combination, 5.3.6); ``errors``: mean and
#: "Std Err" (a standard deviation) of the signed error, tables 5.1-5.11.
THESIS_CHAPTER5: dict[str, dict[str, Any]] = {
    # 5.4.1.1, table 5.1
    "template_raw": _k(0.27, 0.25, 0.24, 0.24, _t(0.71, 15.6, -2.7, 14.22, -0.0199, 1.23)),
    # 5.4.1.2, table 5.2 ("Template" of figure 5.15)
    "template_lowpass": _k(0.30, 0.23, 0.21, 0.24, _t(0.1, 14.8, -0.61, 14.12, -0.01, 1.24)),
    # 5.4.1.3, table 5.3
    "template_highpass": _k(0.25, 0.19, 0.30, 0.16, _t(1.9, 17.9, -4.18, 16.85, -0.28, 1.27)),
    # 5.4.1.4, table 5.4
    "template_velocity": _k(0.15, 0.08, 0.21, 0.11, _t(-1.19, 20.2, -5.5, 23.9, 0.33, 1.35)),
    # 5.4.1.5, table 5.5
    "template_acceleration": _k(0.07, 0.04, 0.0, 0.05, _t(21.3, 25.6, -3.99, 29.5, 0.70, 1.51)),
    # 5.4.1.6, table 5.6 ("FFT Temp" of figure 5.15)
    "frequency": _k(0.44, 0.14, 0.46, 0.42, _t(-1.08, 13.8, -2.78, 22.4, 0.14, 1.00)),
    # 5.4.2, table 5.7: f2 -> angle, f1 -> speed, f3 -> texture ("Feat" of figure 5.15);
    # "independent of each other": angle 0.3, speed 0.25, texture f3 0.08
    "feature": _k(0.11, 0.43, 0.06, 0.08, _t(0.17, 18.6, 1.80, 12.12, 0.43, 1.10)),
    # same with f4 / f5 for texture (angle and speed as "feature")
    "feature_f4": _k(0.11, 0.43, 0.03, 0.21, _t(0.17, 18.6, 1.80, 12.12, -0.07, 1.22)),
    "feature_f5": _k(0.11, 0.43, 0.15, 0.27, _t(0.17, 18.6, 1.80, 12.12, 0.05, 1.09)),
    # 5.4.2.1: f3-f5 combined (texture only reported: kappa 0.12, mean -0.09, std 0.97)
    "feature_f345": _k(None, None, 0.12, None, _t(None, None, None, None, -0.09, 0.97)),
    # 5.4.3, table 5.8 (captioned "spectral template" in the thesis, a copy slip)
    "naive_bayes_raw": _k(0.18, 0.08, 0.11, 0.22, _t(-6.6, 24.5, -5.0, 22.6, 0.13, 1.3)),
    # 5.4.3.1, table 5.9 ("NBV" of figure 5.15)
    "naive_bayes_velocity": _k(0.39, 0.18, 0.38, 0.37, _t(-0.9, 15.5, 3.2, 18.8, 0.01, 1.08)),
    # 5.4.3.2, table 5.10
    "naive_bayes_acceleration": _k(
        0.25, 0.12, 0.27, 0.28, _t(-2.0, 19.9, -2.64, 24.45, 0.04, 1.24)
    ),
    # 5.4.5, table 5.11: texture with speed fixed 0.18, with speed and angle fixed 0.18
    # (the latter is placed under texture_alone; it is not the per-combination training)
    "combined": _k(0.26, 0.43, 0.18, 0.18, _t(-0.5, 20.1, 1.8, 12.12, 0.09, 1.31)),
}
