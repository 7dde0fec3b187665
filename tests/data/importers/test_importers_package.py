"""Tests of the layout of the importers package (vibrissa.data.importers)."""

from __future__ import annotations

import ast
import importlib
import pkgutil

import vibrissa.data
import vibrissa.data.importers as importers

#: The public names of the single module the package replaced.
OLD_PUBLIC_NAMES = [
    "FORMATS",
    "ImportMapping",
    "ImportMappingError",
    "detect_format",
    "import_file",
    "import_recording",
    "load_mapping",
    "parse_axis_option",
    "parse_range",
]


def test_public_names_importable_as_before() -> None:
    assert sorted(importers.__all__) == sorted(OLD_PUBLIC_NAMES)
    for name in OLD_PUBLIC_NAMES:
        assert getattr(importers, name) is not None
    for name in (
        "ImportMapping",
        "ImportMappingError",
        "import_file",
        "import_recording",
        "load_mapping",
    ):
        assert getattr(vibrissa.data, name) is getattr(importers, name)
    assert importers.FORMATS == ("mat", "csv", "npz")
    assert issubclass(importers.ImportMappingError, ValueError)


def test_modules_import_no_private_names_of_each_other() -> None:
    modules = [m.name for m in pkgutil.iter_modules(importers.__path__)]
    assert {
        "mapping",
        "dispatch",
        "arrays",
        "matlab_v5",
        "matlab_hdf5",
        "csv_files",
        "_common",
    } <= set(modules)
    for name in modules:
        mod = importlib.import_module(f"vibrissa.data.importers.{name}")
        assert mod.__doc__, name
        tree = ast.parse(open(mod.__file__, encoding="utf-8").read())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("vibrissa"):
                private = [
                    a.name
                    for a in node.names
                    if a.name.startswith("_") and not a.name.startswith("__")
                ]
                assert not private, f"{name} imports {private} from {node.module}"


def test_package_docstring_points_to_the_user_guide() -> None:
    assert "docs/importing.md" in importers.__doc__
