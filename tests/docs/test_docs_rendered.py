"""The measured docs are rendered from their templates and committed run files.

``scripts/render_docs.py`` renders ``docs/templates/<name>.md`` into ``docs/<name>.md``
from ``docs/runs/<source>.json``. These tests render without measuring anything.
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("render_docs", ROOT / "scripts" / "render_docs.py")
render_docs = importlib.util.module_from_spec(_spec)
sys.modules["render_docs"] = render_docs
_spec.loader.exec_module(render_docs)

TEMPLATES = sorted((ROOT / "docs" / "templates").glob("*.md"))
META = {"command": "test", "vibrissa_version": "0", "date": "2026-01-01", "dataset": None}


def test_there_are_templates():
    names = {t.name for t in TEMPLATES}
    assert {"methods.md", "chapter5.md", "physics.md"} <= names


@pytest.mark.parametrize("template", TEMPLATES, ids=lambda p: p.name)
def test_committed_doc_equals_its_render(template):
    doc = ROOT / "docs" / template.name
    assert doc.read_text(encoding="utf-8") == render_docs.render(template), (
        f"docs/{template.name} differs from its render: edit docs/templates/{template.name} "
        "and run `.venv/bin/python scripts/render_docs.py`"
    )


@pytest.mark.parametrize("template", TEMPLATES, ids=lambda p: p.name)
def test_rendered_doc_says_it_is_generated(template):
    first = (ROOT / "docs" / template.name).read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("<!-- Generated from docs/templates/") and "render_docs.py" in first


def test_thesis_values_is_not_generated():
    text = (ROOT / "docs" / "thesis_values.md").read_text(encoding="utf-8")
    assert "{{" not in text and not text.startswith("<!-- Generated")


def _runs(tmp_path, data):
    runs = tmp_path / "runs"
    runs.mkdir()
    (runs / "r.json").write_text(json.dumps(data))
    return runs


def test_render_substitutes_and_formats(tmp_path):
    runs = _runs(tmp_path, {"meta": META, "a": {"b": 1.23456, "n": 1408, "names": ["x", "y"]}})
    text = "A {{ r.a.b | .2f }}, {{r.a.n|,d}} trials, {{ r.a.names }}; B {{ r.a.b }}\n"
    out, sources = render_docs.render_text(text, "t.md", runs)
    assert out == "A 1.23, 1,408 trials, x, y; B 1.23456\n"
    assert sources == ["r"]


def test_missing_key_names_template_line_and_key(tmp_path):
    runs = _runs(tmp_path, {"meta": META, "a": {"b": 1.0}})
    with pytest.raises(render_docs.RenderError, match=r"t\.md:2: missing key 'r\.a\.c'"):
        render_docs.render_text("ok\nvalue {{ r.a.c | .1f }}\n", "t.md", runs)


def test_missing_run_file_and_meta_are_errors(tmp_path):
    runs = _runs(tmp_path, {"a": 1})
    with pytest.raises(render_docs.RenderError, match=r"t\.md:1: .*lacks meta keys"):
        render_docs.render_text("{{ r.a }}", "t.md", runs)
    with pytest.raises(render_docs.RenderError, match=r"t\.md:1: no run file"):
        render_docs.render_text("{{ other.a }}", "t.md", runs)


@pytest.mark.parametrize(
    "line", ["{{ r.a.b", "r.a.b }}", "{{ r }}", "{{ r.a.b | .2f | x }}", "{{ r.a.b + 1 }}"]
)
def test_malformed_placeholder_is_an_error(tmp_path, line):
    runs = _runs(tmp_path, {"meta": META, "a": {"b": 1.0}})
    with pytest.raises(render_docs.RenderError, match=r"t\.md:1: malformed placeholder"):
        render_docs.render_text(line + "\n", "t.md", runs)


def test_bad_format_is_an_error(tmp_path):
    runs = _runs(tmp_path, {"meta": META, "a": {"b": "text"}})
    with pytest.raises(render_docs.RenderError, match=r"t\.md:1: bad format"):
        render_docs.render_text("{{ r.a.b | .2f }}", "t.md", runs)


def test_check_reports_a_hand_edited_doc(tmp_path, monkeypatch, capsys):
    runs = _runs(tmp_path, {"meta": META, "a": {"b": 2.5}})
    templates, docs = tmp_path / "templates", tmp_path / "docs"
    templates.mkdir()
    docs.mkdir()
    (templates / "x.md").write_text("b = {{ r.a.b | .1f }}\n")
    monkeypatch.setattr(render_docs, "RUNS", runs)
    monkeypatch.setattr(render_docs, "TEMPLATES", templates)
    monkeypatch.setattr(render_docs, "DOCS", docs)
    assert render_docs.main(["--check"]) == 1
    assert render_docs.main([]) == 0
    assert (docs / "x.md").read_text().endswith("b = 2.5\n")
    assert render_docs.main(["--check"]) == 0
    (docs / "x.md").write_text((docs / "x.md").read_text().replace("2.5", "2.6"))
    assert render_docs.main(["--check"]) == 1
    assert "x.md differs" in capsys.readouterr().out


# --- the guard: no hand-typed measured number in a template ------------------------------

NUMBER = re.compile(r"(?<![\w.])(\d+)\.(\d+)(?![\w.]*\d)")
SECTION = r"[1-7]\.\d(?:\.\d)?(?![\d.])(?!\s*(?:%|[a-zA-Z]))"
CITES = re.compile(
    r"thesis|table|figure|(?:\(|\bsections?\s|\beqs?\.\s|\|\s)\s*"
    + SECTION
    + r"|"
    + SECTION
    + r"\s*[),;]",
    re.I,
)


def significant_decimals(whole: str, frac: str) -> int:
    """Decimals that carry information: leading zeros of ``0.0x`` do not count."""
    return len(frac.lstrip("0")) if int(whole) == 0 else len(frac)


def unsourced_numbers(text: str) -> list[tuple[int, str]]:
    """(line, number) of decimals with 2+ significant decimals that no citation covers.

    Allowed: anything in fenced code blocks, code spans and placeholders; a line that
    cites the thesis: it contains "thesis", "table", "figure" or a section number such
    as 4.3 or 5.3.1 (in parentheses, after "section", "eq." or a table bar, or before
    ")", "," or ";"; never followed by a unit, so "1.2 %" or "3.8 deg" is no section);
    in a markdown table, a cell whose column header cites the thesis; and a decimal that
    a template comment ``{# ... #}`` declares (a setting of the code, a test's tolerance
    or a constant of theory, not a measurement).
    """
    declared = {m.group(0) for c in re.findall(r"\{#.*?#\}", text) for m in NUMBER.finditer(c)}
    text = re.sub(r"\{#.*?#\}", " ", text)
    found = []
    in_code = False
    header: list[str] | None = None
    for lineno, raw in enumerate(text.splitlines(), 1):
        if raw.lstrip().startswith("```"):
            in_code = not in_code
            continue
        if in_code:
            continue
        line = re.sub(r"\{\{.*?\}\}", " ", re.sub(r"`[^`]*`", " ", raw))
        is_row = line.lstrip().startswith("|")
        if not is_row:
            header = None
        if CITES.search(line):
            if is_row and header is None:
                header = [c.strip() for c in line.strip().strip("|").split("|")]
            continue
        if is_row and header is None:
            header = [c.strip() for c in line.strip().strip("|").split("|")]
        cells = line.strip().strip("|").split("|") if is_row else [line]
        for i, cell in enumerate(cells):
            if is_row and header and i < len(header) and CITES.search(header[i]):
                continue
            for m in NUMBER.finditer(cell):
                if significant_decimals(*m.groups()) >= 2 and m.group(0) not in declared:
                    found.append((lineno, m.group(0)))
    return found


def test_guard_catches_typed_numbers_and_allows_citations():
    assert unsourced_numbers("our error is 12.75 mm\n") == [(1, "12.75")]
    assert unsourced_numbers("kappa 0.99 here\n") == [(1, "0.99")]
    assert unsourced_numbers("thesis: 12.75 mm\n(4.3): 53.99\n`x = 1.234`\n") == []
    assert unsourced_numbers("as in 5.3.1, 53.99\n| 4.3.2 | 0.25 |\n") == []
    assert unsourced_numbers("within 1.2 %: 12.75\n1.5 mm, 12.75\n") == [(1, "12.75"), (2, "12.75")]
    assert unsourced_numbers("threshold 0.05 V, 1e-3, 0.5-99.5th\n") == []
    assert unsourced_numbers("{{ r.a | .2f }} mm\n```\n1.2345\n```\n") == []
    table = "| name | ours / thesis |\n|---|---|\n| a | {{ r.a }} / 0.27 |\n| b | 0.33 |\n"
    assert unsourced_numbers(table) == []
    table = "| name | ours |\n|---|---|\n| a | 0.27 |\n"
    assert unsourced_numbers(table) == [(3, "0.27")]
    assert unsourced_numbers("{# settings: 0.25 (dt, ms) #}\ndt 0.25 ms, 0.35 s\n") == [(2, "0.35")]


@pytest.mark.parametrize("template", TEMPLATES, ids=lambda p: p.name)
def test_template_has_no_hand_typed_measured_number(template):
    found = unsourced_numbers(template.read_text(encoding="utf-8"))
    assert not found, (
        f"{template.name}: decimals not from a run file or a thesis citation "
        f"(line, number): {found}; make them placeholders ({{{{ source.key | .2f }}}})"
    )
