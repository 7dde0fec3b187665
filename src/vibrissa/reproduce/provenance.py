"""Which code made a result: a fingerprint of an experiment's modules, and the commit.

A committed result is evidence only for the code that made it. :func:`code_fingerprint`
hashes the *code* of every ``vibrissa`` module an experiment's package imports,
directly or through other ``vibrissa`` modules (imports inside functions count too),
so a result stored with its fingerprint can be checked against a checkout: a test
recomputes the fingerprint and fails when the committed result was made by other code.

What is hashed is each module's syntax tree with its docstrings removed
(:func:`ast.dump`), so editing a docstring, a comment or the layout of a file does not
stale the results, while any change to what the code does (a constant, an expression,
a default) does. Modules outside ``vibrissa`` (numpy, scipy, ...) are not hashed; their
versions are in the result's ``meta`` where they matter.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import subprocess
from functools import cache
from pathlib import Path

__all__ = ["code_fingerprint", "git_commit", "module_closure"]

_ROOT_PACKAGE = "vibrissa"
#: Modules that only present results (figures, reports, pages, the command line): they
#: do not change a number, so they are left out of the fingerprint and not followed.
_PRESENTATION_LEAVES = frozenset({"figures", "report", "report_common", "html", "viewer"})
_PRESENTATION_PREFIXES = ("vibrissa.evaluate.figures", "vibrissa.cli")


def _counts(name: str) -> bool:
    """Whether module ``name`` can change a result (not the root package, not presentation)."""
    if name == _ROOT_PACKAGE or not name.startswith(_ROOT_PACKAGE + "."):
        return False
    if name.rsplit(".", 1)[-1] in _PRESENTATION_LEAVES:
        return False
    return not any(name == p or name.startswith(p + ".") for p in _PRESENTATION_PREFIXES)


def _source_path(module: str) -> Path | None:
    """The ``.py`` file of ``module`` (a package's ``__init__.py``), or ``None``."""
    try:
        spec = importlib.util.find_spec(module)
    except (ImportError, ValueError):
        return None
    if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
        return None
    return Path(spec.origin)


def _is_package(path: Path) -> bool:
    return path.name == "__init__.py"


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The absolute module an ``ImportFrom`` node names (relative imports resolved)."""
    if node.level == 0:
        return node.module or ""
    parts = module.split(".")
    base = parts if is_package else parts[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def _imports(module: str, tree: ast.AST, is_package: bool) -> set[str]:
    """``vibrissa`` modules that ``tree`` imports (``from a import b``: ``a.b`` if a module)."""
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = _resolve(module, is_package, node)
            exports = _exports(base)
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if _source_path(sub) is not None:
                    found.add(sub)  # a submodule
                elif alias.name in exports:
                    found.add(exports[alias.name])  # a package's re-export: where it is made
                else:
                    found.add(base)  # made in the module itself (or a package's __init__)
    return {name for name in found if _counts(name) and _source_path(name) is not None}


@cache
def _exports(package: str) -> dict[str, str]:
    """Names a package's ``__init__`` re-exports -> the submodule that defines them.

    ``from vibrissa.data import load_dataset`` then counts ``vibrissa.data.netcdf``, where
    ``load_dataset`` is made, instead of the whole package: the package's ``__init__``
    imports every reader and writer, none of which changes what ``load_dataset`` returns.
    Only names the ``__init__`` imports from its own submodules count; an ``__init__``
    that is not a package, or a name it defines itself, gives nothing here.
    """
    path = _source_path(package)
    if path is None or not _is_package(path):
        return {}
    out: dict[str, str] = {}
    for node in ast.walk(_parsed(path)):
        if isinstance(node, ast.ImportFrom):
            source = _resolve(package, True, node)
            if source.startswith(package + ".") and _source_path(source) is not None:
                for alias in node.names:
                    # a name re-exported from a subpackage resolves through it in turn
                    out[alias.asname or alias.name] = _exports(source).get(alias.name, source)
    return out


def _strip_docstrings(tree: ast.AST) -> ast.AST:
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            ):
                node.body = body[1:] or [ast.Pass()]
    return tree


@cache
def _parsed(path: Path) -> ast.AST:
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def module_closure(package: str) -> dict[str, Path]:
    """Every ``vibrissa`` module ``package`` imports, transitively, with its file.

    Presentation modules (figures, reports, the viewer, the command line) and the root
    package's re-exports are neither counted nor followed.

    Parameters
    ----------
    package
        A module or package name, e.g. ``"vibrissa.thesis.scratchbot"``. A package brings
        in all of its own modules, then what they import.

    Returns
    -------
    dict
        Module name -> source file, sorted by name.

    Raises
    ------
    ValueError
        If ``package`` is not an importable ``vibrissa`` module with a source file.
    """
    if not (package == _ROOT_PACKAGE or package.startswith(_ROOT_PACKAGE + ".")):
        raise ValueError(f"package must be a {_ROOT_PACKAGE} module, got {package!r}")
    first = _source_path(package)
    if first is None:
        raise ValueError(f"no source file for module {package!r}")
    todo = [package]
    if _is_package(first):
        todo += [
            f"{package}.{p.stem}" for p in sorted(first.parent.glob("*.py")) if p.stem != "__init__"
        ]
    seen: dict[str, Path] = {}
    while todo:
        name = todo.pop()
        if name in seen or (name != package and not _counts(name)):
            continue
        path = _source_path(name)
        if path is None:
            continue
        seen[name] = path
        todo.extend(_imports(name, _parsed(path), _is_package(path)) - seen.keys())
    return dict(sorted(seen.items()))


def code_fingerprint(package: str) -> dict[str, object]:
    """The fingerprint of the code behind ``package``'s results.

    Parameters
    ----------
    package
        The experiment's package, e.g. ``"vibrissa.thesis.floor_texture"``.

    Returns
    -------
    dict
        ``digest`` (16 hex digits of a SHA-256 over each module's name and docstring-free
        syntax tree, in name order) and ``modules`` (how many modules it covers).
    """
    closure = module_closure(package)
    h = hashlib.sha256()
    for name, path in closure.items():
        tree = _strip_docstrings(ast.parse(path.read_text(encoding="utf-8")))
        h.update(name.encode())
        h.update(b"\0")
        h.update(ast.dump(tree, annotate_fields=False).encode())
        h.update(b"\0")
    return {"digest": h.hexdigest()[:16], "modules": len(closure)}


def git_commit(directory: str | Path | None = None) -> str | None:
    """The short commit of the checkout holding ``directory`` (default: this package).

    ``None`` outside a git checkout or without git; a ``+`` is appended when tracked files
    differ from the commit (the result was made by uncommitted code).
    """
    where = Path(directory) if directory is not None else Path(__file__).resolve().parent

    def git(*args: str) -> str:
        return subprocess.run(
            ["git", *args], cwd=where, capture_output=True, text=True, timeout=10, check=True
        ).stdout.strip()

    try:
        head = git("rev-parse", "--short", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("+" if dirty else "") if head else None
