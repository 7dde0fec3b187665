"""Whisker geometry, presets and bad-input handling."""

import math

import numpy as np
import pytest

from vibrissa.whisker.geometry import PRESETS, WhiskerGeometry, preset, preset_names


def test_presets_match_the_thesis_dimensions():
    xy = preset("xy-robot")
    assert (xy.length_mm, xy.base_radius_mm, xy.tip_radius_mm) == (185.0, 1.0, 0.25)
    assert 2.3 <= xy.youngs_modulus_gpa <= 2.4
    sb = preset("scratchbot")
    assert (sb.length_mm, sb.base_radius_mm, sb.tip_radius_mm) == (200.0, 1.0, 1.0)
    assert {p.length_mm for k, p in PRESETS.items() if k.startswith("biotact")} == {80, 112, 158}
    cb = preset("crunchbot")
    assert cb.length_mm == 140.0  # 140 mm of the 160 mm whisker lie outside the follicle
    assert cb.tip_radius_mm == pytest.approx(0.15)
    # the free part starts 20 mm up a linear 1.45 -> 0.3 mm diameter taper
    assert cb.base_radius_mm == pytest.approx(0.725 - 0.575 * 20 / 160)
    for p in PRESETS.values():
        assert p.source, f"preset {p.name} must cite its source"


def test_unknown_preset_lists_valid_names():
    with pytest.raises(ValueError, match="xy-robot"):
        preset("no-such-whisker")
    assert "crunchbot" in preset_names()


def test_derived_quantities():
    g = WhiskerGeometry(length_mm=100, base_radius_mm=1, tip_radius_mm=1, youngs_modulus_gpa=2)
    assert g.bending_stiffness_base_nm2 == pytest.approx(2e9 * math.pi * 1e-12 / 4)
    assert g.mass_kg == pytest.approx(g.density_kg_m3 * math.pi * 1e-6 * 0.1)
    assert g.radius_m(0.05) == pytest.approx(1e-3)
    assert WhiskerGeometry.from_dict(g.to_dict()) == g


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("length_mm", -1.0, "length_mm"),
        ("length_mm", 0.0, "length_mm"),
        ("length_mm", float("nan"), "length_mm"),
        ("base_radius_mm", 0.0, "base_radius_mm"),
        ("tip_radius_mm", 2.0, "tip_radius_mm"),
        ("youngs_modulus_gpa", 0.0, "youngs_modulus_gpa"),
        ("youngs_modulus_gpa", -2.0, "youngs_modulus_gpa"),
        ("density_kg_m3", float("inf"), "density_kg_m3"),
        ("damping_ratio", 1.5, "damping_ratio"),
        ("follicle_stiffness_nm_per_rad", 0.0, "follicle_stiffness"),
    ],
)
def test_bad_parameters_raise_naming_the_parameter(field, value, match):
    with pytest.raises(ValueError, match=match):
        WhiskerGeometry(**{field: value})


def test_non_numeric_parameter_is_rejected():
    with pytest.raises(TypeError, match="length_mm"):
        WhiskerGeometry(length_mm="long")  # type: ignore[arg-type]


def test_unknown_dict_key_is_rejected():
    with pytest.raises(ValueError, match="unknown"):
        WhiskerGeometry.from_dict({"length_mm": 100, "colour": "black"})


def test_radius_is_linear_taper():
    g = preset("xy-robot")
    s = np.linspace(0, g.length_m, 5)
    r = g.radius_m(s)
    assert np.allclose(np.diff(r, 2), 0)
    assert r[0] == pytest.approx(1e-3) and r[-1] == pytest.approx(0.25e-3)


@pytest.mark.parametrize(
    ("field", "value", "why"),
    [
        ("youngs_modulus_gpa", 1e-300, "soft rubber to diamond"),
        ("youngs_modulus_gpa", 1e300, "soft rubber to diamond"),
        ("density_kg_m3", 1e-300, "aerogel to osmium"),
        ("density_kg_m3", 1e300, "aerogel to osmium"),
        ("tip_radius_mm", 1e-7, "finer than any whisker's tip"),
    ],
)
def test_material_and_radii_lie_in_the_range_of_real_solids(field, value, why):
    """Issue 13: such values gave overflow warnings, LAPACK errors and tracebacks."""
    with pytest.raises(ValueError, match=f"{field} must lie in .*{why}"):
        preset("xy-robot").replace(**{field: value})
