"""The package's import graph keeps the layer rule of DESIGN.md and its private names private.

- ``signal``, ``data``, ``classify`` and ``evaluate`` never import the simulator
  (``whisker``, ``robots``, ``experiments``): they must work the same on recordings a
  user imports;
- nothing imports the orchestration layer (``reproduce``) or the CLI, except the CLI
  (and the orchestration layer itself);
- no module imports a private name (one leading underscore) from another module,
  neither with ``from m import _name`` nor as ``m._name``; a private *module* may be
  imported by the package that owns it (``from vibrissa.whisker import _kernels`` in
  ``vibrissa.whisker.rod``), as scikit-learn and aeon do.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "vibrissa"
SIMULATOR = {"whisker", "robots", "experiments"}
RECORDING_LAYERS = {"signal", "data", "classify", "evaluate", "slam"}
TOP = {"reproduce", "cli"}


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


def layer_violations(modules: dict[str, ast.Module]) -> list[str]:
    """Every import that breaks the layer rule, as ``module:line -> target``."""
    bad = []
    for mod, tree in modules.items():
        own = _layer(mod)
        for target, names, line in _imports(mod, tree):
            targets = {target} | {f"{target}.{n}" for n in names}
            layers = {_layer(t) for t in targets if _layer(t)}
            if target == "vibrissa":
                layers = {n for n in names if (SRC / n).exists() or (SRC / f"{n}.py").exists()}
            if own in RECORDING_LAYERS and layers & SIMULATOR:
                bad.append(f"{mod}:{line} -> {target} (simulator)")
            if own not in TOP and layers & TOP:
                bad.append(f"{mod}:{line} -> {target} (orchestration/CLI)")
            if own == "reproduce" and "cli" in layers:
                bad.append(f"{mod}:{line} -> {target} (CLI)")
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
                    if (SRC.parent / full.replace(".", "/")).with_suffix(".py").exists() or \
                            _is_package(full):
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
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in aliases and _private(node.attr)):
                bad.append(f"{mod}:{node.lineno} {aliases[node.value.id]}.{node.attr}")
    return bad


def test_layer_rule() -> None:
    assert layer_violations(_modules()) == []


def test_no_private_names_across_modules() -> None:
    assert private_violations(_modules()) == []


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
