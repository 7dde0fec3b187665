"""The ``>>>`` examples in the package's docstrings run and print what they show.

Only the modules whose source holds an example are imported (found by reading the
files), so collecting this test does not import every module, e.g. the numba kernels.
"""

from __future__ import annotations

import doctest
import importlib
from pathlib import Path

import pytest

import vibrissa

PACKAGE = Path(vibrissa.__file__).resolve().parent


def modules_with_examples() -> list[str]:
    """Dotted names of the package's modules whose source holds a ``>>>`` example."""
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if ">>>" not in path.read_text(encoding="utf-8"):
            continue
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def test_the_examples_are_found():
    assert {
        "vibrissa.examples",
        "vibrissa.experiments.protocols",
        "vibrissa.data.importers",
    } <= set(modules_with_examples())


@pytest.mark.parametrize("name", modules_with_examples())
def test_docstring_examples(name: str):
    module = importlib.import_module(name)
    result = doctest.testmod(
        module,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
        verbose=False,
        report=False,
    )
    assert result.attempted > 0, f"{name}: no example found"
    assert result.failed == 0, f"{name}: {result.failed} of {result.attempted} examples failed"
