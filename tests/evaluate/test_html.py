"""The self-contained HTML report: tables, inlined figures, no network, escaping."""

from __future__ import annotations

import base64
import re
from html.parser import HTMLParser
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from vibrissa.evaluate.html import markdown_to_html, write_html_report

SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="40pt" height="20pt" viewBox="0 0 40 20">'
    '<rect width="40" height="20" fill="#36c"/></svg>'
)

REPORT = """# Chapter 9: a test report

Intro with a [link to the thesis](https://example.org/thesis.pdf) and `code`.

## Results

| classifier | kappa | error (mm) |
|---|---|---|
| `template_raw` | 0.96 / 0.27 | -2.22 (9.23) |
| `minirocket` | 0.94 / - | — |

- one
- two

```text
fenced <code> & more
```

## Figures

![errors/template_raw](figures/errors.png)
![a vector figure](figures/vector.svg)
"""


class _Tags(HTMLParser):
    """Every start tag with its attributes."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))


def _tags(document: str) -> list[tuple[str, dict[str, str | None]]]:
    parser = _Tags()
    parser.feed(document)
    return parser.tags


@pytest.fixture
def report_dir(tmp_path: Path) -> Path:
    figures = tmp_path / "figures"
    figures.mkdir()
    matplotlib.image.imsave(figures / "errors.png", np.arange(12.0).reshape(3, 4))
    (figures / "vector.svg").write_text(SVG, encoding="utf-8")
    (tmp_path / "report.md").write_text(REPORT, encoding="utf-8")
    return tmp_path


def test_complete_document_with_title_and_headings(report_dir):
    document = markdown_to_html(REPORT, base_dir=report_dir, title="Chapter 9")
    assert document.startswith("<!DOCTYPE html>")
    assert document.rstrip().endswith("</html>")
    assert "<title>Chapter 9</title>" in document
    assert '<meta name="viewport" content="width=device-width, initial-scale=1">' in document
    assert re.search(r"<h1[^>]*>Chapter 9: a test report</h1>", document)
    assert re.search(r"<h2[^>]*>Results</h2>", document)
    assert "<li>one</li>" in document
    assert "fenced &lt;code&gt; &amp; more" in document


def test_tables_become_scrollable_html_tables(report_dir):
    document = markdown_to_html(REPORT, base_dir=report_dir, title="t")
    tags = _tags(document)
    assert [t for t, _ in tags].count("table") == 1
    assert [t for t, _ in tags].count("tr") == 3
    assert '<div class="table-wrap">\n<table>' in document
    numeric = [a for t, a in tags if t == "td" and a.get("class") == "num"]
    assert len(numeric) == 4  # the kappa and error columns
    assert ("th", {"class": "num"}) in tags


def test_images_are_inlined(report_dir):
    document = markdown_to_html(REPORT, base_dir=report_dir, title="t")
    images = [a for t, a in _tags(document) if t == "img"]
    assert len(images) == 2
    assert all(a["src"].startswith("data:image/") for a in images)
    assert "figures/" not in " ".join(a["src"] for a in images)
    png, svg = images
    assert png["src"].startswith("data:image/png;base64,")
    assert (
        base64.b64decode(png["src"].split(",", 1)[1])
        == (report_dir / "figures" / "errors.png").read_bytes()
    )
    assert base64.b64decode(svg["src"].split(",", 1)[1]).decode() == SVG
    assert "<figcaption>errors/template_raw</figcaption>" in document


def test_percent_encoded_and_angle_bracket_paths(tmp_path):
    (tmp_path / "my figs").mkdir()
    matplotlib.image.imsave(tmp_path / "my figs" / "a b.png", np.zeros((2, 2)))
    text = "![one](my%20figs/a%20b.png)\n\n![two](<my figs/a b.png>)\n"
    document = markdown_to_html(text, base_dir=tmp_path, title="t")
    assert document.count('src="data:image/png;base64,') == 2


def test_missing_image_raises_naming_it(tmp_path):
    text = "# r\n\n![gone](figures/missing_figure.png)\n"
    with pytest.raises(FileNotFoundError, match="missing_figure.png"):
        markdown_to_html(text, base_dir=tmp_path, title="t")


@pytest.mark.parametrize("src", ["https://example.org/x.png", "//cdn.example.org/x.png"])
def test_remote_image_is_refused(tmp_path, src):
    with pytest.raises(ValueError, match="not a local file"):
        markdown_to_html(f"![remote]({src})\n", base_dir=tmp_path, title="t")


def test_unknown_image_type_is_refused(tmp_path):
    (tmp_path / "data.csv").write_text("a,b\n", encoding="utf-8")
    with pytest.raises(ValueError, match="unsupported type"):
        markdown_to_html("![csv](data.csv)\n", base_dir=tmp_path, title="t")


def test_no_network_resources(report_dir):
    document = markdown_to_html(REPORT, base_dir=report_dir, title="t")
    for tag, attrs in _tags(document):
        for name in ("src", "srcset", "data", "poster", "background"):
            value = attrs.get(name)
            assert value is None or value.startswith("data:"), (tag, name, value[:60])
        if tag == "a":
            continue  # links in prose may point to web pages
        href = attrs.get("href")
        assert href is None or not re.match(r"(?i)([a-z]+:)?//", href), (tag, href)
        assert tag not in {"script", "link", "iframe", "object", "embed"}
    assert "url(" not in document
    assert "@import" not in document
    # the prose link survives as an ordinary link
    assert '<a href="https://example.org/thesis.pdf">' in document
    assert "default-src 'none'" in document  # the Content-Security-Policy


def test_odd_characters_are_escaped(tmp_path):
    matplotlib.image.imsave(tmp_path / "x.png", np.zeros((2, 2)))
    caption = """cap <script>alert(1)</script> & "quoted" 'single' > <b>"""
    text = (
        f"# A <b>title</b> & more\n\nA < b & <i>c</i>\n\n![{caption}](x.png)\n\n"
        "| h |\n|---|\n| <td> |\n"
    )
    document = markdown_to_html(text, base_dir=tmp_path, title='<T> & "t"')
    tags = _tags(document)
    assert [t for t, _ in tags if t in {"script", "b", "i"}] == []
    assert '<title>&lt;T&gt; &amp; "t"</title>' in document
    (img,) = [a for t, a in tags if t == "img"]
    assert img["alt"] == caption  # escaped in the markup, intact once parsed
    assert "<figcaption>cap &lt;script&gt;alert(1)&lt;/script&gt; &amp;" in document
    assert "A &lt; b &amp; &lt;i&gt;c&lt;/i&gt;" in document
    assert "<td>&lt;td&gt;</td>" in document


def test_write_html_report_beside_markdown(report_dir):
    md = report_dir / "report.md"
    out = write_html_report(md)
    assert out == report_dir / "report.html"
    document = out.read_text(encoding="utf-8")
    assert "<title>Chapter 9: a test report</title>" in document
    assert [p.name for p in report_dir.iterdir() if p.name.startswith(".")] == []  # no temp file


def test_write_html_report_destination_and_title(report_dir, tmp_path):
    out = write_html_report(
        report_dir / "report.md", tmp_path / "elsewhere" / "r.html", title="Other"
    )
    assert out == tmp_path / "elsewhere" / "r.html"
    assert "<title>Other</title>" in out.read_text(encoding="utf-8")


def test_write_html_report_title_falls_back_to_file_name(tmp_path):
    md = tmp_path / "notes.md"
    md.write_text("## no top heading\n\ntext\n", encoding="utf-8")
    assert "<title>notes.md</title>" in write_html_report(md).read_text(encoding="utf-8")


def test_missing_image_leaves_no_file(report_dir):
    (report_dir / "figures" / "vector.svg").unlink()
    with pytest.raises(FileNotFoundError, match="vector.svg"):
        write_html_report(report_dir / "report.md")
    assert not (report_dir / "report.html").exists()
