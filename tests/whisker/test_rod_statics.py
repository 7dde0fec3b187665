"""Statics of the rod model against Euler-Bernoulli beam theory and the elastica."""

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_bvp

from vibrissa.whisker.geometry import WhiskerGeometry, preset
from vibrissa.whisker.rod import RodModel

UNIFORM = WhiskerGeometry(length_mm=185, base_radius_mm=1, tip_radius_mm=1, name="uniform")
TAPERED = preset("xy-robot")


def compliance(g: WhiskerGeometry, a_mm: float) -> float:
    """Deflection per unit force at a, for a load at a (m/N): int_0^a (a-s)^2 / EI(s) ds."""
    a = a_mm * 1e-3
    E = g.youngs_modulus_gpa * 1e9

    def ei(s):
        return E * math.pi * g.radius_m(s) ** 4 / 4

    return quad(lambda s: (a - s) ** 2 / ei(s), 0, a)[0]


@pytest.fixture(scope="module")
def uniform():
    return RodModel(UNIFORM, rigid_follicle=True)


@pytest.fixture(scope="module")
def tapered():
    return RodModel(TAPERED, rigid_follicle=True)


@pytest.mark.parametrize("at_mm", [60.0, 120.0, 185.0])
def test_uniform_small_load_matches_euler_bernoulli(uniform, at_mm):
    F = 1e-4
    r = uniform.static_force(F, at_mm)
    a = at_mm * 1e-3
    expected = F * a**3 / (3 * UNIFORM.bending_stiffness_base_nm2) * 1e3
    assert r.deflection_mm == pytest.approx(expected, rel=0.02)
    assert r.base_moment_nm == pytest.approx(F * a, rel=0.02)
    assert r.tan_x == 0.0  # clamped: the magnet cannot rotate


@pytest.mark.parametrize("at_mm", [80.0, 150.0, 185.0])
def test_tapered_small_load_matches_euler_bernoulli(tapered, at_mm):
    F = 1e-4
    r = tapered.static_force(F, at_mm)
    expected = F * compliance(TAPERED, at_mm) * 1e3
    assert r.deflection_mm == pytest.approx(expected, rel=0.02)
    assert r.base_moment_nm == pytest.approx(F * at_mm * 1e-3, rel=0.02)


def elastica_tip(alpha: float) -> tuple[float, float]:
    """Tip deflection and shortening (over L) of a cantilever under a fixed-direction
    tip load with F L^2 / EI = alpha: theta'' = -alpha cos(theta), theta(0)=0, theta'(1)=0."""
    s = np.linspace(0, 1, 200)
    sol = solve_bvp(
        lambda s, y: np.vstack([y[1], -alpha * np.cos(y[0])]),
        lambda ya, yb: np.array([ya[0], yb[1]]),
        s,
        np.zeros((2, s.size)),
        tol=1e-10,
    )
    ss = np.linspace(0, 1, 4001)
    th = sol.sol(ss)[0]
    return float(np.trapezoid(np.sin(th), ss)), float(1 - np.trapezoid(np.cos(th), ss))


@pytest.mark.parametrize("alpha", [0.5, 1.0, 2.0, 3.0])
def test_large_deflection_matches_the_elastica(uniform, alpha):
    EI = UNIFORM.bending_stiffness_base_nm2
    L = UNIFORM.length_m
    v, u = elastica_tip(alpha)
    r = uniform.static_force(alpha * EI / L**2, UNIFORM.length_mm)
    assert r.deflection_mm / UNIFORM.length_mm == pytest.approx(v, rel=0.02)
    assert r.axial_shortening_mm / UNIFORM.length_mm == pytest.approx(u, rel=0.02)
    # a linear model would predict alpha/3: the answer must be the nonlinear one
    if alpha >= 2:
        assert r.deflection_mm / UNIFORM.length_mm < 0.8 * alpha / 3


def test_force_direction_y_bends_in_y(tapered):
    r = tapered.static_force(1e-4, 150, direction=(0, 1))
    x = r.positions_m
    assert abs(x[:, 0]).max() < 1e-12
    assert x[-1, 1] > 0


@pytest.mark.parametrize(("g", "at_mm"), [(UNIFORM, 150.0), (TAPERED, 150.0), (TAPERED, 80.0)])
def test_small_frictionless_push_matches_beam_theory(g, at_mm):
    model = RodModel(g, rigid_follicle=True)
    D = 1.0
    res = model.push(at_mm, D, friction=0.0, pole_radius_mm=0.05)
    force = D * 1e-3 / compliance(g, at_mm)
    assert res.base_force_n == pytest.approx(force, rel=0.02)
    assert res.base_moment_nm == pytest.approx(force * at_mm * 1e-3, rel=0.02)
    assert res.contact_arc_length_mm == pytest.approx(at_mm, abs=0.1)
    assert not res.slipped_off


def test_frictionless_push_slides_toward_the_tip_and_off(tapered):
    near = tapered.push(150, 20, friction=0.0)
    far = tapered.push(150, 40, friction=0.0)
    assert 150 < near.contact_arc_length_mm < far.contact_arc_length_mm
    off = tapered.push(180, 60, friction=0.0)
    assert off.slipped_off
    assert off.base_moment_nm < 1e-6


@pytest.mark.parametrize(("mu", "sticks"), [(1.0, True), (0.7, True), (0.3, False), (0.0, False)])
def test_friction_holds_the_contact_inside_the_friction_cone(tapered, mu, sticks):
    # pole moves at 30 deg from +x toward +y (along its own axis); the whisker bends as
    # easily in y as in x, so the contact sticks iff tan(30 deg) = 0.577 < mu
    res = tapered.push(150, 0.5, friction=mu, direction_deg=30)
    follow = res.contact_y_mm / res.pole_y_mm
    ratio = res.friction_force_n / res.normal_force_n
    assert ratio <= mu * 1.01 + 1e-9
    if sticks:
        assert follow > 0.9
        assert ratio < mu
    else:
        assert follow < 0.75
        assert ratio == pytest.approx(mu, abs=0.02)


def test_compliant_follicle_rotates_and_adds_deflection():
    free = RodModel(TAPERED)
    clamped = RodModel(TAPERED, rigid_follicle=True)
    F = 1e-4
    a = free.static_force(F, 150)
    b = clamped.static_force(F, 150)
    assert a.tan_x > 0 and b.tan_x == 0
    # the follicle turns about its pivot, follicle_depth below the base, against k_f:
    # psi = F (a + d) / k_f, adding psi (a + d) of deflection at the load
    arm_mm = 150 + TAPERED.follicle_depth_mm
    psi = F * arm_mm * 1e-3 / TAPERED.follicle_stiffness_nm_per_rad
    assert a.base_angle_deg == pytest.approx(math.degrees(psi), rel=0.02)
    assert a.deflection_mm - b.deflection_mm == pytest.approx(psi * arm_mm, rel=0.02)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"force_n": 1e-3, "at_mm": 190.0}, "at_mm"),
        ({"force_n": 1e-3, "at_mm": 0.0}, "at_mm"),
        ({"force_n": float("nan"), "at_mm": 100.0}, "force_n"),
        ({"force_n": 1e-3, "at_mm": float("nan")}, "at_mm"),
    ],
)
def test_static_bad_input(tapered, kwargs, match):
    with pytest.raises(ValueError, match=match):
        tapered.static_force(**kwargs)


def test_push_bad_input(tapered):
    with pytest.raises(ValueError, match="at_mm"):
        tapered.push(200, 1)
    with pytest.raises(ValueError, match="displacement_mm"):
        tapered.push(100, -1)
    with pytest.raises(ValueError, match="friction"):
        tapered.push(100, 1, friction=-0.1)
    with pytest.raises(ValueError, match="n_elements"):
        RodModel(TAPERED, n_elements=2)
    with pytest.raises(ValueError, match="mass must be one of"):
        RodModel(TAPERED, mass="heavy")


@pytest.mark.parametrize(
    ("at_mm", "radius_mm", "displacement_mm"),
    [
        (180.0, 170.0, 60.0),
        (180.0, 150.0, 80.0),
        (170.0, 120.0, 100.0),
    ],
)
def test_push_refuses_a_pole_the_whisker_would_wrap_around(
    tapered, at_mm, radius_mm, displacement_mm
):
    """Issue 13, finding 8: a pole large for the push, though smaller than the contact's
    distance, touches the shaft a second time (the whisker wraps around it); the push
    failed to converge and now names the cause."""
    with pytest.raises(ValueError, match="would wrap around a pole this large"):
        tapered.push(at_mm, displacement_mm, pole_radius_mm=radius_mm)


@pytest.mark.parametrize("radius_mm", [0.5, 10.0, 100.0])
def test_push_with_a_pole_that_fits_bends_the_whisker(tapered, radius_mm):
    """Where a push is accepted its results agree: a deflected whisker has a base moment,
    and the contact stays on the shaft."""
    res = tapered.push(150, 60, pole_radius_mm=radius_mm)
    assert res.base_moment_nm > 1e-3
    assert 0.0 < res.contact_arc_length_mm <= 185.0


def test_a_pole_reaching_past_the_base_is_refused():
    """Issue 13, finding 8: a 1 km pole gave a base moment of 0 with the Hall at 4.75 V."""
    model = RodModel(TAPERED, 28)
    with pytest.raises(ValueError, match=r"pole_radius_mm \(150\) must be smaller than at_mm"):
        model.push(150, 60, pole_radius_mm=150)
    assert model.push(150, 60, pole_radius_mm=100).base_moment_nm > 0


def test_a_static_load_beyond_reach_says_how_far_the_solver_got():
    from vibrissa.whisker.rod import SimulationError

    with pytest.raises(SimulationError, match=r"did not converge beyond [\d.e+-]+ N of force_n"):
        RodModel(TAPERED, 28).static_force(1000.0, 100.0)
