"""The package's import graph keeps the layer rule of docs/architecture.md, has no cycle, and
keeps its private names private.

- ``signal``, ``data``, ``classify``, ``evaluate`` and ``slam`` never import the simulator
  (``whisker``, ``robots``, ``experiments``): they must work the same on recordings a
  user imports;
- the thesis' experiments (``vibrissa.thesis.<experiment>``) by role: ``evaluation``,
  ``report``, ``figures`` and ``values`` never import the simulator either (so an
  imported recording runs through every evaluation); ``protocol`` (and ``viewer``) may;
  only ``experiment`` imports the orchestration layer (its registry); no experiment
  package imports another one, and nothing below them imports ``vibrissa.thesis``;
- nothing imports the orchestration layer (``reproduce``) or the CLI, except the CLI
  (and the orchestration layer itself, and each experiment's ``experiment`` module);
- no import cycle anywhere, counting the imports inside functions too;
- numba is imported only by ``_kernels`` modules (compiled code in one place per package);
- no module imports a private name (one leading underscore) from another module,
  neither with ``from m import _name`` nor as ``m._name``; a private *module* may be
  imported by the package that owns it (``from vibrissa.whisker import _kernels`` in
  ``vibrissa.whisker.rod``), as scikit-learn and aeon do.
"""

from __future__ import annotations

import ast
import copy
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "vibrissa"
SIMULATOR = {"whisker", "robots", "experiments"}
RECORDING_LAYERS = {"signal", "data", "classify", "evaluate", "slam", "framework"}
#: The top: orchestration, the command line and its console entry point (``__main__``).
TOP = {"reproduce", "cli", "__main__"}
#: Roles of an experiment package's modules that must run on imported recordings.
RECORDING_ROLES = {"evaluation", "report", "figures", "values"}
#: Layers that sit below the thesis' experiments and never import them.
BELOW_THESIS = SIMULATOR | RECORDING_LAYERS


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _modules() -> dict[str, ast.Module]:
    return {_module_name(p): ast.parse(p.read_text(), str(p)) for p in sorted(SRC.rglob("*.py"))}


def _is_package(mod: str) -> bool:
    return (SRC.parent / mod.replace(".", "/") / "__init__.py").exists()


def _imports(mod: str, tree: ast.Module) -> list[tuple[str, list[str], int]]:
    """(imported module, names, line) of every vibrissa import of ``mod``, relative resolved."""
    out = []
    pkg = mod if _is_package(mod) else mod.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = pkg.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            if base == "vibrissa" or base.startswith("vibrissa."):
                out.append((base, [a.name for a in node.names], node.lineno))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("vibrissa"):
                    out.append((a.name, [], node.lineno))
    return out


def _layer(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else ""


def _role(mod: str) -> tuple[str | None, str | None]:
    """(experiment, role) of a module of ``vibrissa.thesis``; ``(None, None)`` elsewhere."""
    parts = mod.split(".")
    if len(parts) < 3 or parts[1] != "thesis":
        return None, None
    return parts[2], (parts[3] if len(parts) > 3 else "__init__")


def layer_violations(modules: dict[str, ast.Module]) -> list[str]:
    """Every import that breaks the layer rule, as ``module:line -> target``."""
    bad = []
    for mod, tree in modules.items():
        own = _layer(mod)
        experiment, role = _role(mod)
        for target, names, line in _imports(mod, tree):
            targets = {target} | {f"{target}.{n}" for n in names}
            layers = {_layer(t) for t in targets if _layer(t)}
            if target == "vibrissa":
                layers = {n for n in names if (SRC / n).exists() or (SRC / f"{n}.py").exists()}
            if own in RECORDING_LAYERS and layers & SIMULATOR:
                bad.append(f"{mod}:{line} -> {target} (simulator)")
            if role in RECORDING_ROLES and layers & SIMULATOR:
                bad.append(f"{mod}:{line} -> {target} (simulator, from a {role} module)")
            if (
                own not in TOP
                and layers & TOP
                and not (role == "experiment" and layers & TOP == {"reproduce"})
            ):
                bad.append(f"{mod}:{line} -> {target} (orchestration/CLI)")
            if own == "reproduce" and "cli" in layers:
                bad.append(f"{mod}:{line} -> {target} (CLI)")
            if own in BELOW_THESIS and "thesis" in layers:
                bad.append(f"{mod}:{line} -> {target} (a thesis experiment)")
            others = {_role(t)[0] for t in targets} - {None, experiment}
            if experiment is not None and others:
                bad.append(f"{mod}:{line} -> {target} (another experiment)")
    return bad


def _resolve(target: str, names: list[str], modules: dict[str, ast.Module]) -> set[str]:
    """The modules an import statement loads: each name that is a submodule, else the target."""
    out = {f"{target}.{n}" for n in names if f"{target}.{n}" in modules}
    if not names or len(out) < len(names):
        out.add(target)
    return {m for m in out if m in modules}


class _DropTypeCheckingBlocks(ast.NodeTransformer):
    """Removes ``if TYPE_CHECKING:`` blocks: their imports never run."""

    def visit_If(self, node: ast.If) -> ast.AST | None:
        test = node.test
        name = (
            test.id
            if isinstance(test, ast.Name)
            else (test.attr if isinstance(test, ast.Attribute) else None)
        )
        return None if name == "TYPE_CHECKING" else self.generic_visit(node)


def import_cycles(modules: dict[str, ast.Module]) -> list[list[str]]:
    """Every cycle of the import graph (its strongly connected components of two or more
    modules), imports inside functions included, those for type checkers only
    (``if TYPE_CHECKING:``) not."""
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for mod, tree in modules.items():
        runtime = _DropTypeCheckingBlocks().visit(copy.deepcopy(tree))
        for target, names, _ in _imports(mod, runtime):
            graph[mod] |= _resolve(target, names, modules) - {mod}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's algorithm, iterative enough for this graph's depth
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return cycles


def numba_outside_kernels(modules: dict[str, ast.Module]) -> list[str]:
    """Every module other than a ``_kernels`` module that imports numba."""
    bad = []
    for mod, tree in modules.items():
        if mod.rpartition(".")[2] == "_kernels":
            continue
        for node in ast.walk(tree):
            names = (
                [a.name for a in node.names]
                if isinstance(node, ast.Import)
                else [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else []
            )
            if any(n == "numba" or n.startswith("numba.") for n in names):
                bad.append(f"{mod}:{node.lineno}")
    return bad


def private_violations(modules: dict[str, ast.Module]) -> list[str]:
    """Every private name imported from another module, as ``module:line name``."""
    bad = []
    for mod, tree in modules.items():
        aliases: dict[str, str] = {}
        for target, names, line in _imports(mod, tree):
            for n in names:
                full = f"{target}.{n}"
                if not _private(n):
                    if (SRC.parent / full.replace(".", "/")).with_suffix(
                        ".py"
                    ).exists() or _is_package(full):
                        aliases[n] = full
                    continue
                # a private submodule imported by the package that owns it is allowed
                is_module = (SRC.parent / full.replace(".", "/")).with_suffix(".py").exists()
                owner = mod if _is_package(mod) else mod.rpartition(".")[0]
                if is_module and (owner == target or owner.startswith(target + ".")):
                    aliases[n] = full
                    continue
                if target == mod:
                    continue
                bad.append(f"{mod}:{line} {full}")
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and _private(node.attr)
            ):
                bad.append(f"{mod}:{node.lineno} {aliases[node.value.id]}.{node.attr}")
    return bad


def test_layer_rule() -> None:
    assert layer_violations(_modules()) == []


def test_no_private_names_across_modules() -> None:
    assert private_violations(_modules()) == []


def test_no_import_cycles() -> None:
    assert import_cycles(_modules()) == []


def test_numba_only_in_kernels() -> None:
    assert numba_outside_kernels(_modules()) == []


def test_every_experiment_package_has_its_experiment_module() -> None:
    """Each package of ``vibrissa.thesis`` registers one experiment from ``experiment.py``."""
    packages = [p for p in (SRC / "thesis").iterdir() if (p / "__init__.py").exists()]
    assert packages
    for p in packages:
        assert (p / "experiment.py").exists(), p


def test_cycle_check_catches_a_planted_cycle() -> None:
    """Two modules importing each other, one of them inside a function, are a cycle."""
    mods = {
        "vibrissa.evaluate.planted_a": ast.parse("from vibrissa.evaluate import planted_b\n"),
        "vibrissa.evaluate.planted_b": ast.parse(
            "def f():\n    from vibrissa.evaluate.planted_a import x\n"
        ),
        "vibrissa.evaluate": ast.parse(""),
    }
    assert import_cycles(mods) == [["vibrissa.evaluate.planted_a", "vibrissa.evaluate.planted_b"]]
    mods["vibrissa.evaluate.planted_b"] = ast.parse(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
        "    from vibrissa.evaluate.planted_a import x\n"
    )
    assert import_cycles(mods) == []


def test_numba_check_catches_a_planted_import() -> None:
    mods = {
        "vibrissa.signal._planted": ast.parse("import numba\n"),
        "vibrissa.signal._kernels": ast.parse("from numba import njit\n"),
    }
    assert numba_outside_kernels(mods) == ["vibrissa.signal._planted:1"]


@pytest.mark.parametrize(
    ("module", "source"),
    [
        ("vibrissa.thesis.planted.evaluation", "from vibrissa.robots import whisking\n"),
        ("vibrissa.thesis.planted.report", "import vibrissa.whisker.rod\n"),
        ("vibrissa.thesis.planted.figures", "from vibrissa.experiments import streams\n"),
        ("vibrissa.thesis.planted.values", "from vibrissa import experiments\n"),
        ("vibrissa.thesis.planted.report", "from vibrissa.reproduce.registry import register\n"),
        ("vibrissa.thesis.planted.protocol", "from vibrissa.reproduce import registry\n"),
        ("vibrissa.thesis.planted.evaluation", "from vibrissa.thesis.other.values import X\n"),
        ("vibrissa.evaluate.planted", "from vibrissa.thesis.planted import values\n"),
        ("vibrissa.robots.planted", "import vibrissa.thesis.planted.protocol\n"),
        ("vibrissa.thesis.planted.experiment", "from vibrissa.cli import main\n"),
    ],
)
def test_role_rule_catches_violations(module: str, source: str) -> None:
    """The role rule fails on a planted bad import of a thesis module (or into one)."""
    assert layer_violations({module: ast.parse(source)}), (module, source)


@pytest.mark.parametrize(
    ("module", "source"),
    [
        ("vibrissa.thesis.planted.protocol", "from vibrissa.robots import whisking\n"),
        (
            "vibrissa.thesis.planted.experiment",
            "from vibrissa.reproduce.registry import register\n",
        ),
        ("vibrissa.thesis.planted.report", "from vibrissa.thesis.planted.values import X\n"),
        ("vibrissa.cli.planted", "from vibrissa.thesis.planted import viewer\n"),
    ],
)
def test_role_rule_allows(module: str, source: str) -> None:
    assert layer_violations({module: ast.parse(source)}) == [], (module, source)


@pytest.mark.parametrize(
    ("source", "kind"),
    [
        ("from vibrissa.whisker.surfaces import TEXTURES\n", "layer"),
        ("from vibrissa import robots\n", "layer"),
        ("import vibrissa.experiments.protocols\n", "layer"),
        ("from vibrissa.reproduce import run_experiment\n", "layer"),
        ("from vibrissa.evaluate.loop import _helper\n", "private"),
        ("from vibrissa.experiments import runner\nrunner._model()\n", "private"),
    ],
)
def test_checks_catch_violations(source: str, kind: str) -> None:
    """The checks fail on a planted bad import in a recording-layer module."""
    mods = {"vibrissa.classify._planted": ast.parse(source)}
    found = layer_violations(mods) if kind == "layer" else private_violations(mods)
    assert found, source


def unresolved_imports(modules: dict[str, ast.Module]) -> list[str]:
    """Every ``from vibrissa.m import name`` (module level or inside a function) whose
    module does not exist or holds no ``name``: a refactor's broken function-local import,
    which nothing else finds before the function runs."""
    import importlib

    bad = []
    for mod, tree in modules.items():
        for target, names, line in _imports(mod, tree):
            try:
                module = importlib.import_module(target)
            except ImportError as exc:
                bad.append(f"{mod}:{line} {target}: {exc}")
                continue
            for n in names:
                if n != "*" and not hasattr(module, n) and f"{target}.{n}" not in modules:
                    bad.append(f"{mod}:{line} {target}.{n}")
    return bad


def test_every_import_resolves() -> None:
    assert unresolved_imports(_modules()) == []


def test_unresolved_import_check_catches_a_planted_one() -> None:
    mods = {
        "vibrissa.evaluate.planted": ast.parse(
            "def f():\n    from vibrissa.evaluate.metrics import no_such_name\n"
        )
    }
    assert unresolved_imports(mods) == [
        "vibrissa.evaluate.planted:2 vibrissa.evaluate.metrics.no_such_name"
    ]
