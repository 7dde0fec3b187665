"""docs/architecture.md keeps one line for every module of the package, and no stale one."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src" / "vibrissa"


def _modules() -> set[str]:
    return {
        ".".join(p.relative_to(SRC).with_suffix("").parts)
        for p in SRC.rglob("*.py")
        if p.name != "__init__.py"
    }


def test_every_module_has_its_line_and_every_line_a_module():
    text = (ROOT / "docs" / "architecture.md").read_text()
    listed = set(re.findall(r"^\| `([a-z_.0-9]+)` \|", text, flags=re.MULTILINE))
    modules = _modules()
    assert modules - listed == set(), "modules without a line in docs/architecture.md"
    stale = {
        m
        for m in listed - modules
        if "." in m and not m.endswith(".py") and not (SRC / m.replace(".", "/")).is_dir()
    }
    assert stale == set(), "lines of docs/architecture.md naming no module"
