"""Synthetic whisker-like trials for the classifier tests."""

from __future__ import annotations

import numpy as np
import pytest

FS = 1000.0
WHISKER = {
    "length_mm": 185.0,
    "base_radius_mm": 1.0,
    "tip_radius_mm": 0.25,
    "youngs_modulus_gpa": 2.35,
    "follicle_stiffness_nm_per_rad": 0.1,
    "hall_gain_v": 12.0,
    "hall_offset_v": 2.5,
}


def make_trials(
    radii=(80.0, 110.0, 140.0, 170.0),
    speeds=(40.0, 100.0, 160.0),
    reps: int = 3,
    n_timepoints: int = 201,
    noise_v: float = 0.002,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Peak-centred deflection pulses: amplitude falls with radius, width with speed."""
    rng = np.random.default_rng(seed)
    t = np.arange(n_timepoints) - n_timepoints // 2
    X, y = [], []
    for _ in range(reps):
        for r in radii:
            for v in speeds:
                amp = 0.01 * (200.0 - r) * np.sqrt(v / 100.0)
                width = 1500.0 / v
                pulse = np.exp(-0.5 * (t / width) ** 2)
                x = 2.5 + amp * pulse
                yy = 2.5 + 0.1 * amp * pulse * np.sin(t / 5.0)
                X.append(np.stack([x, yy]))
                y.append((r, v))
    X = np.asarray(X) + noise_v * rng.standard_normal((len(X), 2, n_timepoints))
    return X, np.asarray(y)


@pytest.fixture(scope="session")
def trials() -> tuple[np.ndarray, np.ndarray]:
    return make_trials()


@pytest.fixture(scope="session")
def trial_factory():
    """The :func:`make_trials` generator, for tests that need other grids."""
    return make_trials


@pytest.fixture(scope="session")
def whisker() -> dict:
    return dict(WHISKER)
