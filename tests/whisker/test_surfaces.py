"""Texture height fields and the tip's view of them."""

import numpy as np
import pytest

from vibrissa.whisker.surfaces import TEXTURES, Surface, make_surface, texture_names


def test_presets_follow_the_grit_standard():
    assert texture_names() == ["aluminium", "p600", "p180", "p80"]
    assert TEXTURES["p80"].grain_diameter_um == pytest.approx(201)
    assert TEXTURES["p180"].grain_diameter_um == pytest.approx(82)
    assert TEXTURES["p600"].grain_diameter_um == pytest.approx(25.8)


def test_coarser_paper_is_rougher_and_deterministic():
    rough = {t: make_surface(t, seed=1).heights_m.std() for t in texture_names()}
    assert rough["aluminium"] < rough["p600"] < rough["p180"] < rough["p80"]
    a = make_surface("p180", seed=3).heights_m
    b = make_surface("p180", seed=3).heights_m
    assert np.array_equal(a, b)
    assert not np.array_equal(a, make_surface("p180", seed=4).heights_m)


def test_tip_envelope_bridges_grains_smaller_than_the_tip():
    tip = 0.25e-3
    for t in ["p600", "p80"]:
        s = make_surface(t, seed=0)
        env = s.for_tip(tip)
        assert np.all(env >= s.heights_m - 1e-15)  # the envelope lies on or above
    fine = make_surface("p600", seed=0)
    coarse = make_surface("p80", seed=0)
    # relative roughness seen by the tip is reduced far more for grains << tip
    ratio_fine = fine.for_tip(tip).std() / fine.heights_m.std()
    ratio_coarse = coarse.for_tip(tip).std() / coarse.heights_m.std()
    assert ratio_fine < ratio_coarse


def test_envelope_of_a_single_bump_is_a_parabola():
    h = np.zeros((200, 3))
    h[100, :] = 1e-5
    s = Surface(h, 1e-5, 0.3)
    env = s.for_tip(1e-3)
    d = (np.arange(200) - 100) * 1e-5
    expected = np.maximum(1e-5 - d**2 / 2e-3, 0.0)
    np.testing.assert_allclose(env[:, 1], expected, atol=1e-12)


def test_bad_surfaces_are_rejected():
    with pytest.raises(ValueError, match="unknown texture"):
        make_surface("p120")
    with pytest.raises(ValueError, match="NaN"):
        Surface(np.full((3, 3), np.nan), 1e-5, 0.3)
    with pytest.raises(ValueError, match="2-D"):
        Surface(np.zeros(5), 1e-5, 0.3)
    with pytest.raises(ValueError, match="spacing_m"):
        Surface(np.zeros((3, 3)), 0.0, 0.3)


def test_tip_keeps_more_relief_of_coarser_grains():
    """5.5: grains smaller than the tip are bridged; the larger the grain, the more the
    tip feels (measured: 48 %, 66 %, 82 % of the RMS relief for P600, P180, P80)."""
    tip = 0.25e-3  # every paper's grain is smaller than the 0.5 mm tip
    kept = []
    for t in ["p600", "p180", "p80"]:
        s = make_surface(t, seed=0)
        assert TEXTURES[t].grain_diameter_um * 1e-6 < 2 * tip
        kept.append(s.for_tip(tip).std() / s.heights_m.std())
    assert kept[0] < kept[1] < kept[2] < 1.0
    surfaces = [make_surface(t, seed=0) for t in ["aluminium", "p600", "p180", "p80"]]
    slopes = [(np.diff(s.for_tip(tip), axis=0) / s.spacing_m).std() for s in surfaces]
    assert slopes == sorted(slopes)
