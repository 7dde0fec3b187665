"""The numba kernels' argument bundles and the one-module rule of their cache."""

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

from vibrissa.whisker import _kernels
from vibrissa.whisker._kernels import NO_CONTACT, POLE, ContactSpec, RodArrays
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
            assert [(k.arg, k.value.value) for k in deco.keywords] == [("cache", True)], node.name


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
