"""The map error of eq. 6.3, its smoothing and the random-map baseline."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.robots.crunchbot.arena import PRESETS
from vibrissa.slam.error import (
    UNEXPLORED,
    gaussian_kernel,
    map_error,
    random_map_error,
    smooth_ground_truth,
)


def _truth() -> np.ndarray:
    return smooth_ground_truth(PRESETS["slam"].occupancy_grid())


def test_ground_truth_against_itself_is_zero() -> None:
    gt = _truth()
    assert map_error(gt, gt) == 0.0
    assert map_error(np.stack([gt, gt, gt]), gt) == 0.0


def test_the_smoothing_is_a_normalised_5x5_gaussian_of_sigma_2_5() -> None:
    k = gaussian_kernel()
    assert k.shape == (5, 5) and k.sum() == pytest.approx(1.0)
    assert k[2, 2] / k[2, 3] == pytest.approx(np.exp(1 / (2 * 2.5**2)))
    impulse = np.zeros((9, 9))
    impulse[4, 4] = 1.0
    np.testing.assert_allclose(smooth_ground_truth(impulse)[2:7, 2:7], k)


def test_bernoulli_half_map_error_is_a_half_close_to_the_thesis_0_47() -> None:
    gt = _truth()
    err = random_map_error(gt, np.random.default_rng(1), n_maps=50)
    # E|B - g| = 0.5 (1 - g) + 0.5 g = 0.5 for any truth g when p = 0.5
    assert err == pytest.approx(0.5, abs=0.005)
    assert err == pytest.approx(0.47, abs=0.05)


def test_map_error_by_hand_and_unexplored_cells() -> None:
    gt = np.zeros((4, 4))
    gt[0, 0] = 1.0
    m = np.full((4, 4), UNEXPLORED)
    assert map_error(m, gt) == pytest.approx((0.7 + 15 * 0.3) / 16)


def test_bad_inputs_are_refused() -> None:
    gt = np.zeros((4, 4))
    with pytest.raises(ValueError, match="maps must be"):
        map_error(np.zeros((3, 3)), gt)
    with pytest.raises(ValueError, match="n_maps must be a positive integer"):
        random_map_error(gt, np.random.default_rng(0), n_maps=0)
    with pytest.raises(ValueError, match="size must be a positive odd integer"):
        gaussian_kernel(4)


def test_arena_mask_and_masked_error() -> None:
    from vibrissa.slam.error import arena_mask

    mask = arena_mask(50, 0.05, 0.6, 1.25)
    inside = mask[:, 25]
    # the arena (25 cells) and its one-cell wall ring on each side
    assert inside.sum() == 27 and inside[11] and inside[37] and not inside[10]
    gt = np.zeros((50, 50))
    m = np.where(mask, 1.0, 0.0)
    assert map_error(m, gt, mask) == 1.0
    assert map_error(m, gt) == pytest.approx(mask.mean())
    with pytest.raises(ValueError, match="boolean"):
        map_error(m, gt, mask.astype(int))
    with pytest.raises(ValueError, match="no cell"):
        map_error(m, gt, np.zeros((50, 50), bool))
