"""Natural frequencies of the linearised rod and discretisation convergence."""

import math

import numpy as np
import pytest

from vibrissa.whisker.geometry import PRESETS, WhiskerGeometry
from vibrissa.whisker.rod import DEFAULT_N_ELEMENTS, RodModel

BETA_L = np.array([1.8751, 4.6941, 7.8548])


def test_uniform_cantilever_frequencies_match_analytic():
    g = WhiskerGeometry(length_mm=185, base_radius_mm=1, tip_radius_mm=1)
    model = RodModel(g, rigid_follicle=True)
    rho_a = g.density_kg_m3 * math.pi * (1e-3) ** 2
    analytic = (
        BETA_L**2 / (2 * math.pi * g.length_m**2) * math.sqrt(g.bending_stiffness_base_nm2 / rho_a)
    )
    np.testing.assert_allclose(model.natural_frequencies_hz[:3], analytic, rtol=0.02)


@pytest.mark.parametrize("name", ["xy-robot", "crunchbot", "biotact-g1-80"])
@pytest.mark.parametrize("rigid", [False, True])
def test_default_discretisation_is_converged_to_two_percent(name, rigid):
    g = PRESETS[name]
    coarse = RodModel(g, DEFAULT_N_ELEMENTS, rigid_follicle=rigid).natural_frequencies_hz[:3]
    fine = RodModel(g, 8 * DEFAULT_N_ELEMENTS, rigid_follicle=rigid).natural_frequencies_hz[:3]
    np.testing.assert_allclose(coarse, fine, rtol=0.02)


def test_compliant_follicle_lowers_frequencies():
    g = PRESETS["xy-robot"]
    free = RodModel(g).natural_frequencies_hz[:3]
    clamped = RodModel(g, rigid_follicle=True).natural_frequencies_hz[:3]
    assert np.all(free < clamped)


def test_damping_design_hits_the_configured_first_mode_damping():
    for name in ["xy-robot", "scratchbot", "crunchbot"]:
        model = RodModel(PRESETS[name])
        zeta, _ = model.modal_damping(*model.damping)
        assert zeta[0] == pytest.approx(PRESETS[name].damping_ratio, rel=1e-3)
    rigid = RodModel(PRESETS["xy-robot"], rigid_follicle=True)
    zeta, _ = rigid.modal_damping(*rigid.damping)
    assert zeta[0] == pytest.approx(0.05, rel=1e-3)


def test_a_first_mode_overdamped_by_the_material_is_refused():
    """Issue 13: a light, stiff, clamped whisker had no oscillating first mode (IndexError)."""
    g = PRESETS["xy-robot"].replace(
        youngs_modulus_gpa=1200, density_kg_m3=1, base_radius_mm=0.5, tip_radius_mm=0.001
    )
    with pytest.raises(ValueError, match="overdamped by the shaft's own material damping"):
        _ = RodModel(g, rigid_follicle=True).damping
