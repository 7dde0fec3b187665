"""The numba kernels' argument bundles and the one-module rule of their cache."""

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.whisker import _kernels
from vibrissa.whisker._kernels import NO_CONTACT, POLE, ContactSpec, RodArrays, interp_into
from vibrissa.whisker.rod import RodModel, pole_contact_spec
from vibrissa.whisker.simulate import (
    PoleContact,
    SurfaceContact,
    Trajectory,
    free_vibration,
    simulate,
)
from vibrissa.whisker.surfaces import Surface

KERNELS_FILE = Path(_kernels.__file__)
#: Small helpers of the rod's and the contacts' loops that numba inlines into their
#: callers (no call, no reference counting of the arrays they take).
INLINED = {"_proj_into", "_matvec", "_pvec", "_bend_self_into", "band_add_block"}


@pytest.fixture(scope="module")
def model():
    return RodModel(n_elements=8)


def test_kernel_module_imports_nothing_from_the_project():
    # numba's cache checks only a kernel's own file: a callee in another file could go stale
    tree = ast.parse(KERNELS_FILE.read_text())
    modules = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            modules.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            modules.add((node.module or "").split(".")[0] if node.level == 0 else ".")
    assert modules <= {"__future__", "typing", "numpy", "numba"}


def test_every_kernel_is_cached_and_defined_in_the_kernel_module():
    dispatchers = [obj for obj in vars(_kernels).values() if hasattr(obj, "py_func")]
    assert len(dispatchers) > 20
    for d in dispatchers:
        assert Path(inspect.getfile(d.py_func)) == KERNELS_FILE
    for node in ast.walk(ast.parse(KERNELS_FILE.read_text())):
        if isinstance(node, ast.FunctionDef) and node.decorator_list:
            deco = node.decorator_list[0]
            assert isinstance(deco, ast.Call) and deco.func.id == "njit", node.name
            keywords = [(k.arg, k.value.value) for k in deco.keywords]
            # the entry points run on threads too (CrunchBot's whiskers side by side)
            allowed = (
                [("cache", True), ("nogil", True)]
                if node.name in ("run_dynamics", "modal_advance", "rcp_loop")
                else [("cache", True), ("inline", "always")]
                if node.name in INLINED
                else [("cache", True)]
            )
            assert keywords == allowed, node.name


def test_no_kernel_copies_an_array_into_a_slice():
    # ``dst[:, :] = src`` carries a broadcasting check whose error message makes numba
    # compile string formatting: ~5 s of every cold compile (kernels use _copy1/_copy2)
    def has_slice(index: ast.expr) -> bool:
        parts = index.elts if isinstance(index, ast.Tuple) else [index]
        return any(isinstance(p, ast.Slice) for p in parts)

    offenders = []
    for node in ast.walk(ast.parse(KERNELS_FILE.read_text())):
        if isinstance(node, ast.Assign) and not isinstance(node.value, ast.Constant):
            for target in node.targets:
                if isinstance(target, ast.Subscript) and has_slice(target.slice):
                    offenders.append(f"line {node.lineno}: {ast.unparse(node)}")
    assert not offenders, offenders


def test_rod_arrays_are_the_models_own_arrays(model):
    rod = model.rod_arrays()
    assert isinstance(rod, RodArrays)
    for name in ("free", "kb", "axis", "L0", "EA", "mass", "radius", "s_rest"):
        assert getattr(rod, name) is getattr(model, name)
        assert getattr(rod, name).flags.c_contiguous
    assert rod.free.dtype == np.bool_
    assert rod.kb.dtype == rod.mass.dtype == np.float64
    assert type(rod.kf) is float and rod.kf == model.kf


def test_pole_contact_spec_has_fixed_types():
    spec = pole_contact_spec([5e-4, 2e4, 0.5, 0.3, 2e-6])
    assert isinstance(spec, ContactSpec)
    assert spec.kind == POLE and type(spec.kind) is int
    assert spec.params.dtype == np.float64 and spec.params.shape == (5,)
    assert pole_contact_spec(np.zeros(5), NO_CONTACT).kind == NO_CONTACT
    assert type(spec.du) is float and type(spec.first_node) is int


def test_plane_stiffness_leaves_the_model_untouched(model):
    kb = model.kb
    before = kb.copy()
    model.modal_damping(0.0, 1e-4, 1e-3)
    assert model.kb is kb
    np.testing.assert_array_equal(model.kb, before)


def test_pole_surface_and_free_runs_share_one_compiled_solver(model):
    # one type signature for every contact kind: nothing recompiles per call site
    simulate(model, PoleContact(), Trajectory.linear((-2.0, 30.0), (50.0, 0.0), 0.01), 0.01)
    sc = SurfaceContact(Surface(np.zeros((4, 4)), 1e-4, 0.3, "flat"), angle_deg=45)
    tip = np.array([0.0, 0.0, model.geometry.length_m]) - sc.frame()[0] * 1e-3
    traj = Trajectory.linear((tip[0] * 1e3, tip[2] * 1e3), (10.0, 0.0), 0.01)
    simulate(model, sc, traj, 0.01, rho_inf=1, tol_m=1e-8, max_iterations=30)
    free_vibration(model, 1.0, 0.01, record_every=5)
    assert len(_kernels.run_dynamics.signatures) == 1
    assert len(_kernels.solve_static.signatures) == 1


def _dense(S):
    n = S.shape[0]
    bw = _kernels.BW
    out = np.zeros((n, n))
    for r in range(n):
        for c in range(max(0, r - bw), min(n, r + bw + 1)):
            out[r, c] = S[r, bw + c - r]
    return out


def test_the_stretching_springs_iteration_matrix_is_their_exact_derivative():
    # A fast, bent, stretched shaft with material damping: the damping force
    # beta EA/L0 (t . dv) t turns with the edge, which the iteration matrix must
    # include (without it, a whisker whipping at metres per second made Newton
    # stall or fail near its thin tip, where the true stiffness is tiny)
    model = RodModel(n_elements=8)
    rod = model.rod_arrays()._replace(kb=np.zeros_like(model.kb), kf=0.0)
    damping = _kernels.Damping(0.0, 1e-3, 0.0)
    rng = np.random.default_rng(3)
    n = rod.mass.shape[0]
    x = np.zeros((n, 3))
    x[:, 2] = np.r_[0.0, np.cumsum(rod.L0)]
    x[2:, 0] = 0.2 * (x[2:, 2] - x[1, 2]) ** 2 / x[-1, 2]  # bent
    x[1:] += 2e-4 * rng.standard_normal((n - 1, 3))  # and stretched unevenly
    v = 3.0 * rng.standard_normal((n, 3))
    v[0] = 0.0

    def forces(xx, vv):
        F = np.zeros((n, 3))
        S = np.zeros((3 * n, 2 * _kernels.BW + 1))
        _kernels.add_internal(xx, vv, rod, damping, F, S, 0.0, 0.0, False)
        return F.ravel()

    def matrix(cD, cK):
        F = np.zeros((n, 3))
        S = np.zeros((3 * n, 2 * _kernels.BW + 1))
        _kernels.add_internal(x, v, rod, damping, F, S, cD, cK, True)
        return _dense(S)

    K = np.zeros((3 * n, 3 * n))
    D = np.zeros((3 * n, 3 * n))
    for j in range(3 * n):
        e = np.zeros(3 * n)
        h = 1e-9
        e[j] = h
        K[:, j] = -(forces(x + e.reshape(n, 3), v) - forces(x - e.reshape(n, 3), v)) / (2 * h)
        e[j] = 1e-3
        D[:, j] = -(forces(x, v + e.reshape(n, 3)) - forces(x, v - e.reshape(n, 3))) / 2e-3
    moving = np.repeat(rod.free, 3)
    for got, want in ((matrix(0.0, 1.0), K), (matrix(1.0, 0.0), D)):
        err = np.abs(got - want)[np.ix_(moving, moving)].max()
        assert err <= 1e-6 * np.abs(want).max(), err


def _flat_plane(first_node: int = 1) -> ContactSpec:
    # a flat wall through the origin, its normal +x toward the whisker
    frame = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    return ContactSpec(
        _kernels.PLANE,
        np.array([0.0, 2e4, 0.5, 0.3, 2e-6]),
        frame,
        np.zeros((4, 4)),
        1e-3,
        1e-3,
        first_node,
    )


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    relief_mm=st.floats(0.0, 3.0),
    height_mm=st.floats(-1.0, 6.0),
    first_node=st.integers(1, 8),
    jac=st.booleans(),
)
def test_a_plane_evaluated_only_under_nodes_within_its_relief_is_the_full_evaluation(
    model, seed, relief_mm, height_mm, first_node, jac
):
    # add_plane and _plane_entry_fraction skip the surface under nodes farther from the
    # plane than its highest point (ContactSpec.h_max): forces, iteration matrix, contact
    # output, anchors and the update's safe fraction must be the bytes of the evaluation
    # under every node (h_max = inf)
    rng = np.random.default_rng(seed)
    rod = model.rod_arrays()
    n = model.n_nodes
    heights = rng.uniform(0.0, relief_mm * 1e-3, (16, 16)) - 0.5 * relief_mm * 1e-3
    theta = np.deg2rad(rng.uniform(0.0, 60.0))
    nrm = np.array([np.cos(theta), 0.0, -np.sin(theta)])  # toward the whisker
    tu = np.array([np.sin(theta), 0.0, np.cos(theta)])
    frame = np.array([nrm, tu, [0.0, 1.0, 0.0]])
    params = np.array([0.0, 2e4, 0.5, 0.6, 2e-6])
    spec = ContactSpec(_kernels.PLANE, params, frame, heights, 2e-4, 2e-4, first_node, np.inf)
    culled = spec._replace(h_max=float(heights.max()))
    # a bent whisker whose tip region lies about height_mm off the plane's mean level
    x = model.x_rest.copy()
    x[:, 0] += 1e-3 * rng.normal(0.0, 0.3, n).cumsum()
    tip = x[-1]
    origin = tip - nrm * (height_mm * 1e-3 + rod.radius[-1]) + rng.normal(0.0, 2e-4, 3)
    plane = np.concatenate([origin, rng.normal(0.0, 1e-2, 3)])
    v = rng.normal(0.0, 0.05, (n, 3))
    dx = rng.normal(0.0, 1e-3, 3 * n)
    anchors0 = np.zeros((n, 6))
    anchors0[:, 0:2] = rng.normal(0.0, 1e-4, (n, 2))
    anchors0[:, 2] = rng.integers(0, 2, n)
    anchors0[:, 5] = 7.0  # overwritten for every node tested
    outs = []
    for c in (spec, culled):
        F = np.zeros((n, 3))
        S = np.zeros((3 * n, 2 * _kernels.BW + 1))
        info = np.zeros(12)
        anchors = anchors0.copy()
        _kernels.add_plane(x, v, rod, c, plane, anchors, F, S, 0.3, 0.7, jac, info)
        frac = _kernels._plane_entry_fraction(x, dx, c, plane, rod.radius, 1.0 / 3.0)
        outs.append((F, S, info, anchors, np.array([frac])))
    for full, fast in zip(*outs, strict=True):
        np.testing.assert_array_equal(fast, full)


def test_an_update_carrying_a_node_into_a_plane_stops_it_at_the_surface():
    radius = np.full(3, 1e-4)
    xa = np.zeros((3, 3))
    xa[:, 0] = [5e-3, 3e-3, 1.1e-3]  # gaps 4.9, 2.9 and 1.0 mm outside the wall
    dx = np.zeros(9)
    dx[3 * 2] = -3e-3  # the full update moves node 2's alpha point by (1 - af) * 3 mm in
    tr = np.zeros(6)
    af = 1.0 / 3.0
    frac = _kernels._plane_entry_fraction(xa, dx, _flat_plane(), tr, radius, af)
    assert frac == pytest.approx(1.0e-3 / ((1.0 - af) * 3e-3))
    # the node ends on the surface
    assert xa[2, 0] + frac * (1.0 - af) * dx[6] - radius[2] == pytest.approx(0.0, abs=1e-12)
    # moving away, or staying outside, or starting inside the smoothing zone: no limit
    for step in (+3e-3, -0.5e-3):
        dx[6] = step
        assert _kernels._plane_entry_fraction(xa, dx, _flat_plane(), tr, radius, af) == 1.0
    xa[2, 0] = radius[2] + 1e-6
    dx[6] = -3e-3
    assert _kernels._plane_entry_fraction(xa, dx, _flat_plane(), tr, radius, af) == 1.0
    # nodes before first_node, and other contact kinds, are never limited
    xa[2, 0] = 1.1e-3
    assert _kernels._plane_entry_fraction(xa, dx, _flat_plane(3), tr, radius, af) == 1.0
    pole = _flat_plane()._replace(kind=POLE)
    assert _kernels._plane_entry_fraction(xa, dx, pole, tr, radius, af) == 1.0


def _random_band_system(n_rows: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """A diagonally dominant band matrix (band storage and dense) of half bandwidth BW."""
    rng = np.random.default_rng(seed)
    bw = _kernels.BW
    band = np.zeros((n_rows, 2 * bw + 1))
    dense = np.zeros((n_rows, n_rows))
    for i in range(n_rows):
        for j in range(max(0, i - bw), min(n_rows, i + bw + 1)):
            value = rng.standard_normal() + (4.0 * bw if i == j else 0.0)
            band[i, bw + j - i] = value
            dense[i, j] = value
    return band, dense


@pytest.mark.parametrize("n_rows", [3, 8, 9, 17, 48, 90])
def test_band_factor_and_backsolve_solve_the_dense_system(n_rows):
    # the full-band rows take unrolled paths, the first and last BW rows the general
    # loops: sizes below, at and above the bandwidth exercise both
    band, dense = _random_band_system(n_rows, seed=n_rows)
    rhs = np.random.default_rng(1).standard_normal(n_rows)
    x = rhs.copy()
    assert _kernels.band_solve(band, x)
    np.testing.assert_allclose(x, np.linalg.solve(dense, rhs), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("steps", [300, 600])
def test_newton_stops_within_its_tolerance_of_the_converged_step(steps):
    # one step of the standard contact, the whisker pressed on the pole: Newton
    # stopped by its contraction estimate lands within tol of the same step solved to
    # 1e-13. (Later in the push a step can end stuck or slipping depending on the last
    # nanometre, and two tolerances may differ by micrometres there.)
    from vibrissa.whisker import preset
    from vibrissa.whisker.benchmark import standard_trajectory

    m = RodModel(preset("xy-robot"))
    c = PoleContact(radius_mm=0.5, friction=0.3)
    tr = standard_trajectory(m)
    dt = 2.5e-4
    run = simulate(m, c, tr, steps * dt, dt, linear_free_flight=False, max_stride=1)
    assert run.contact_force_n[-1] > 0
    ends = []
    for tol in (1e-8, 1e-13):
        res = simulate(
            m,
            c,
            tr,
            (steps + 1) * dt,
            dt,
            initial_state=run.final_state.copy(),
            record_every=1,
            linear_free_flight=False,
            max_stride=1,
            tol_m=tol,
        )
        ends.append(res.states_m[-1])
    assert np.abs(ends[0] - ends[1]).max() <= 1e-8


def _first_touch_brute_force(
    kind, params, frame, h_max, traj, x_rest, radius, bound, margin, first_node
):
    """Every row and every segment or node: the definition first_possible_contact
    skips its way through."""
    n = x_rest.shape[0]
    for t in range(traj.shape[0]):
        if kind == POLE:
            for j in range(1, n - 1):
                a = x_rest[j, [0, 2]]
                b = x_rest[j + 1, [0, 2]] - a
                p = traj[t, 0:2]
                u = min(1.0, max(0.0, float((p - a) @ b / (b @ b))))
                clear = (
                    np.hypot(*(a + u * b - p))
                    - params[0]
                    - max(radius[j], radius[j + 1])
                    - max(bound[j], bound[j + 1])
                )
                if clear <= margin:
                    return t
        else:
            for i in range(first_node, n):
                zc = frame[0] @ (x_rest[i] - traj[t, 0:3])
                if zc - h_max - radius[i] - bound[i] <= margin:
                    return t
    return traj.shape[0]


@pytest.mark.parametrize("kind", [POLE, _kernels.PLANE])
@pytest.mark.parametrize("seed", range(6))
def test_first_possible_contact_skips_only_rows_that_cannot_touch(kind, seed):
    rng = np.random.default_rng(seed)
    n = 12
    x_rest = np.zeros((n, 3))
    x_rest[1:, 2] = np.linspace(0.0, 0.1, n - 1)  # a straight shaft along z, 100 mm
    radius = np.linspace(5e-4, 1e-4, n)
    bound = np.linspace(0.0, 4e-3, n) * rng.uniform(0.2, 2.0)
    # an object wandering toward the shaft in random steps, sometimes standing still
    steps = rng.normal(0.0, 2e-4, (4000, 3)) * (rng.uniform(size=(4000, 1)) < 0.7)
    steps[:, 0] -= rng.uniform(1.2e-5, 3e-5)  # drifting toward the shaft at x = 0
    traj = np.zeros((4000, 6))
    if kind == POLE:
        traj[:, 0] = 0.03 + np.cumsum(steps[:, 0])
        traj[:, 1] = 0.06 + np.cumsum(steps[:, 2])
        params = np.array([5e-4, 0.0, 0.0, 0.0, 0.0])
    else:
        traj[:, 0:3] = np.array([0.03, 0.0, 0.0]) + np.cumsum(steps, axis=0)
        params = np.zeros(5)
    frame = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    args = (kind, params, frame, 1e-4, traj, x_rest, radius, bound, 5e-4, 2)
    expected = _first_touch_brute_force(*args)
    assert 0 < expected < traj.shape[0]  # the walk reaches the shaft, late
    assert _kernels.first_possible_contact(*args) == expected


@settings(max_examples=200, deadline=None)
@given(
    knots=st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=2, max_size=40, unique=True),
    values=st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=40, max_size=40),
    points=st.lists(st.floats(-2e3, 2e3, allow_nan=False), min_size=1, max_size=60),
    ordered=st.booleans(),
)
def test_interp_into_is_numpy_interp_bit_for_bit(knots, values, points, ordered):
    """The trajectory's one-pass interpolation gives np.interp's bytes, knots and ends
    included, for increasing and for unordered sample times."""
    xp = np.sort(np.array(knots))
    fp = np.array(values[: xp.size])
    x = np.concatenate([np.array(points), xp, xp[[0, -1]]])
    if ordered:
        x = np.sort(x)
    out = np.empty_like(x)
    interp_into(x, xp, fp, out)
    np.testing.assert_array_equal(out, np.interp(x, xp, fp))
