"""Self-contained HTML reports: one file beside ``report.md``, figures inlined.

:func:`write_html_report` turns an experiment's ``report.md`` into ``report.html``
beside it; :func:`markdown_to_html` does the conversion. The result is a single
HTML5 file that needs nothing else to be read:

- every local figure (PNG, JPEG, GIF, WebP, SVG) the Markdown links with
  ``![caption](figures/name.png)`` is inlined as a ``data:`` URI, so the file can
  be mailed, archived or opened from anywhere;
- nothing refers to the network: no remote images, fonts, style sheets or
  scripts (a Content-Security-Policy in the page forbids them as well). Links in
  the prose to web pages stay ordinary links;
- the embedded style sheet is readable on a phone (wide tables scroll inside
  their own box, figures shrink to the screen width) and in print (no scroll
  boxes, rows and figures not split across pages where the browser can help it).

Raw HTML in the Markdown is not passed through: ``<`` and ``&`` in captions,
table cells or prose are shown as written.
"""

from __future__ import annotations

import base64
import html
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from urllib.parse import unquote, urlsplit

import markdown
from markdown.extensions import Extension
from markdown.treeprocessors import Treeprocessor

from vibrissa._atomic import atomic_write_text

__all__ = ["IMAGE_TYPES", "markdown_to_html", "write_html_report"]

#: Media types of the image files that are inlined, by lower-case file suffix.
IMAGE_TYPES: dict[str, str] = {
    ".png": "image/png",
    ".jpg": "image/jpeg",
    ".jpeg": "image/jpeg",
    ".gif": "image/gif",
    ".webp": "image/webp",
    ".svg": "image/svg+xml",
}

# A cell holding only numbers and their punctuation ("0.96 / 0.27", "-2.22 (9.23)",
# "12 %", "-" or a dash for "none"), right-aligned so that the decimal places line up.
_DASHES = frozenset({"-", "\u2212", "\u2013", "\u2014"})
_NUMERIC_CELL = re.compile(r"[\d\s.,/()%+\-\u2212\u2013\u2014]+")
_DIGIT = re.compile(r"\d")

# Only inline styles and data: images; no scripts, fonts, frames or requests.
_CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"

_CSS = """
html { -webkit-text-size-adjust: 100%; text-size-adjust: 100%; }
body {
  font-family: system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial,
    "Noto Sans", "Liberation Sans", sans-serif;
  font-size: 1rem; line-height: 1.5; color: #1f2328; background: #fff;
  max-width: 60rem; margin: 0 auto; padding: 1rem 1rem 3rem;
  overflow-wrap: break-word;
}
h1, h2, h3, h4 { line-height: 1.25; margin: 1.6em 0 0.6em; }
h1 { font-size: 1.6rem; margin-top: 0.5em; }
h2 { font-size: 1.3rem; padding-bottom: 0.2em; border-bottom: 1px solid #d0d7de; }
h3 { font-size: 1.1rem; }
a { color: #0550ae; }
code, pre {
  font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, "Liberation Mono", monospace;
  font-size: 0.88em;
}
code { background: #f3f4f6; padding: 0.1em 0.3em; border-radius: 3px; }
pre { background: #f3f4f6; padding: 0.75rem; overflow-x: auto; border-radius: 4px; }
pre code { background: none; padding: 0; }
.table-wrap { overflow-x: auto; margin: 1rem 0; }
table { border-collapse: collapse; font-size: 0.9rem; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid #d0d7de; padding: 0.3rem 0.6rem; text-align: left; vertical-align: top; }
thead th { background: #eef1f4; }
tbody tr:nth-child(even) { background: #f6f8fa; }
th.num, td.num { text-align: right; white-space: nowrap; }
figure { margin: 1.5rem 0; }
img { display: block; max-width: 100%; height: auto; margin: 0 auto; }
figcaption { margin-top: 0.3rem; text-align: center; font-size: 0.9rem; color: #57606a; }
@media (max-width: 600px) {
  body { padding: 0.75rem 0.75rem 2rem; }
  h1 { font-size: 1.4rem; }
  table { font-size: 0.85rem; }
}
@media print {
  body { max-width: none; margin: 0; padding: 0; font-size: 10pt; }
  h1, h2, h3, h4 { break-after: avoid; page-break-after: avoid; }
  .table-wrap { overflow: visible; }
  table { font-size: 8pt; }
  th, td { padding: 0.15rem 0.3rem; overflow-wrap: anywhere; }
  th.num, td.num { white-space: normal; }
  thead { display: table-header-group; }
  tr, img, figure { break-inside: avoid; page-break-inside: avoid; }
  pre { white-space: pre-wrap; overflow: visible; }
  a { color: inherit; }
}
"""


def _data_uri(src: str, base_dir: Path) -> str:
    """Return the ``data:`` URI of the local image ``src`` (relative to ``base_dir``)."""
    parts = urlsplit(src)
    if parts.scheme or parts.netloc:
        raise ValueError(
            f"image {src!r} is not a local file: a self-contained report inlines only "
            "images beside it"
        )
    path = Path(unquote(parts.path))
    if not path.is_absolute():
        path = base_dir / path
    mime = IMAGE_TYPES.get(path.suffix.lower())
    if mime is None:
        raise ValueError(
            f"image {src!r}: unsupported type {path.suffix!r} (known: {sorted(IMAGE_TYPES)})"
        )
    if not path.is_file():
        raise FileNotFoundError(f"image {src!r} of the report not found (looked for {path})")
    return f"data:{mime};base64,{base64.b64encode(path.read_bytes()).decode('ascii')}"


def _only_images(p: ET.Element) -> bool:
    """Whether paragraph ``p`` holds nothing but images (and whitespace)."""
    if len(p) == 0 or (p.text or "").strip():
        return False
    return all(child.tag == "img" and not (child.tail or "").strip() for child in p)


def _is_numeric(text: str) -> bool:
    text = text.strip()
    return (
        bool(text)
        and _NUMERIC_CELL.fullmatch(text) is not None
        and (_DIGIT.search(text) is not None or text in _DASHES)
    )


class _ReportTreeprocessor(Treeprocessor):
    """Inline images, turn image paragraphs into figures and wrap tables for scrolling."""

    def __init__(self, md: markdown.Markdown, base_dir: Path) -> None:
        super().__init__(md)
        self.base_dir = base_dir

    def run(self, root: ET.Element) -> None:
        for img in root.iter("img"):
            src = img.get("src", "")
            if not src.startswith("data:"):
                img.set("src", _data_uri(src, self.base_dir))
        self._figures(root)
        self._tables(root)

    def _figures(self, parent: ET.Element) -> None:
        for index, child in enumerate(list(parent)):
            if child.tag == "p" and _only_images(child):
                images = list(child)
                div = ET.Element("div", {"class": "figures"})
                div.tail = child.tail
                for img in images:
                    img.tail = None
                    figure = ET.SubElement(div, "figure")
                    figure.append(img)
                    caption = img.get("alt", "").strip()
                    if caption:
                        ET.SubElement(figure, "figcaption").text = caption
                parent.remove(child)
                parent.insert(index, div)
            else:
                self._figures(child)

    def _tables(self, parent: ET.Element) -> None:
        for index, child in enumerate(list(parent)):
            if child.tag == "table":
                _mark_numeric_columns(child)
                wrap = ET.Element("div", {"class": "table-wrap"})
                wrap.tail = child.tail
                child.tail = None
                parent.remove(child)
                wrap.append(child)
                parent.insert(index, wrap)
            else:
                self._tables(child)


def _cell_text(cell: ET.Element) -> str:
    return "".join(cell.itertext())


def _mark_numeric_columns(table: ET.Element) -> None:
    """Give numeric cells, and the headers of all-numeric columns, ``class="num"``."""
    body_rows = [row for tbody in table.iter("tbody") for row in tbody.iter("tr")]
    numeric_columns: dict[int, bool] = {}
    for row in body_rows:
        for col, cell in enumerate(row.findall("td")):
            numeric = _is_numeric(_cell_text(cell))
            if numeric:
                cell.set("class", "num")
            numeric_columns[col] = numeric_columns.get(col, True) and numeric
    for thead in table.iter("thead"):
        for row in thead.iter("tr"):
            for col, cell in enumerate(row.findall("th")):
                if numeric_columns.get(col, False):
                    cell.set("class", "num")


class _ReportExtension(Extension):
    def __init__(self, base_dir: Path) -> None:
        super().__init__()
        self.base_dir = base_dir

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # Markdown's API
        # Raw HTML is shown as text, not passed through.
        md.preprocessors.deregister("html_block")
        md.inlinePatterns.deregister("html")
        # After "inline" (images exist) and before "prettify".
        md.treeprocessors.register(_ReportTreeprocessor(md, self.base_dir), "vibrissa_report", 15)


def markdown_to_html(text: str, *, base_dir: Path, title: str) -> str:
    """Convert a Markdown report into one self-contained HTML5 document.

    Parameters
    ----------
    text
        The Markdown (Python-Markdown dialect with tables and fenced code).
    base_dir
        Directory the report's relative image paths are relative to (the
        directory of ``report.md``).
    title
        Text of the document's ``<title>`` (escaped here).

    Returns
    -------
    str
        The complete document: embedded style sheet, every image inlined as a
        ``data:`` URI, no reference to any network resource.

    Raises
    ------
    FileNotFoundError
        If an image the Markdown links is missing (the message names it).
    ValueError
        If an image is remote (``http:`` and the like) or of an unsupported type.
    """
    md = markdown.Markdown(
        extensions=["tables", "fenced_code", "sane_lists", "toc", _ReportExtension(Path(base_dir))],
        output_format="html",
    )
    body = md.convert(text)
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f'<meta http-equiv="Content-Security-Policy" content="{_CSP}">\n'
        '<meta name="generator" content="vibrissa">\n'
        f"<title>{html.escape(title, quote=False)}</title>\n"
        f"<style>{_CSS}</style>\n</head>\n<body>\n<main>\n{body}\n</main>\n</body>\n</html>\n"
    )


def _first_heading(text: str) -> str | None:
    for line in text.splitlines():
        if line.startswith("# "):
            return line[2:].strip().strip("#").strip() or None
    return None


def write_html_report(
    md_path: str | os.PathLike[str],
    html_path: str | os.PathLike[str] | None = None,
    *,
    title: str | None = None,
) -> Path:
    """Write the self-contained HTML version of a Markdown report, atomically.

    Parameters
    ----------
    md_path
        The Markdown report (``report.md``); its images are looked up relative
        to its directory.
    html_path
        Destination; defaults to ``md_path`` with the suffix ``.html``
        (``report.html`` beside ``report.md``).
    title
        Document title; defaults to the report's first ``# `` heading, else the
        file name.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    FileNotFoundError
        If ``md_path`` or an image it links is missing; nothing is written then.
    """
    md_path = Path(md_path)
    text = md_path.read_text(encoding="utf-8")
    out = md_path.with_suffix(".html") if html_path is None else Path(html_path)
    if title is None:
        title = _first_heading(text) or md_path.name
    document = markdown_to_html(text, base_dir=md_path.parent, title=title)
    return atomic_write_text(out, document)
