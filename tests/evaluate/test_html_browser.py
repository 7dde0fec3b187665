"""The HTML report in headless Chromium: figures decoded, tables drawn, phone and print.

Skipped, saying why, where no Chromium (Debian's ``chromium``) or no Playwright is
installed; ``.ci/run`` installs Chromium when it runs as root.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
from PIL import Image

from vibrissa.evaluate.html import write_html_report

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: the browser harness
from browser import PHONE_WIDTH, PRINT_WIDTH, check_in_browser, chromium_or_skip

PNG_DPI = 200
WIDE_COLUMNS = 14


def _figure(path: Path, title: str, **save) -> None:
    fig, ax = plt.subplots(figsize=(6.0, 3.0))
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, np.sin(2 * np.pi * x), label="signal")
    ax.set(title=title, xlabel="time (s)", ylabel="moment (N mm)")
    ax.legend()
    fig.savefig(path, **save)
    plt.close(fig)


def _report(tmp_path: Path) -> Path:
    """A report.md with two PNG figures (200 dpi), one SVG figure and three tables."""
    figures = tmp_path / "figures"
    figures.mkdir()
    _figure(figures / "errors.png", "errors", dpi=PNG_DPI)
    _figure(figures / "kappa.png", "kappa <&>", dpi=PNG_DPI)
    _figure(figures / "curve.svg", "a vector figure")
    wide_header = (
        "| classifier | "
        + " | ".join(f"fraction {i / WIDE_COLUMNS:.2f}" for i in range(1, WIDE_COLUMNS + 1))
        + " |"
    )
    wide_rule = "|---" * (WIDE_COLUMNS + 1) + "|"
    wide_rows = [
        f"| `naive_bayes_velocity_robust_{r}` | "
        + " | ".join(
            f"{-r * i / 7:.2f} ({i + r:.2f}) / {i:.2f} ({r:.2f})" for i in range(WIDE_COLUMNS)
        )
        + " |"
        for r in range(6)
    ]
    text = "\n".join(
        [
            "# Chapter 9: a browser test report",
            "",
            "Trials: 144 (2 channels x 6001 samples at 4000.0 Hz); a long line of prose that "
            "must wrap on a phone rather than push the page sideways.",
            "",
            "## Kappa",
            "",
            "| classifier | angle | speed |",
            "|---|---|---|",
            "| `template_raw` | 0.96 / 0.27 | 0.92 / 0.25 |",
            "| `minirocket` | 0.94 / - | 0.92 / - |",
            "",
            "## A wide table",
            "",
            wide_header,
            wide_rule,
            *wide_rows,
            "",
            "## Sequential",
            "",
            "| contacts | kappa |",
            "|---|---|",
            *[f"| {n} | {0.5 + n / 100:.2f} |" for n in (1, 2, 3, 5, 10)],
            "",
            "## Figures",
            "",
            "![errors/template_raw](figures/errors.png)",
            "![kappa <&>](figures/kappa.png)",
            "![a vector figure](figures/curve.svg)",
            "",
        ]
    )
    md = tmp_path / "report.md"
    md.write_text(text, encoding="utf-8")
    return write_html_report(md)


def test_report_renders_in_chromium(tmp_path):
    executable = chromium_or_skip()
    html_path = _report(tmp_path)
    shot = tmp_path / "docs" / "report.png"
    result = check_in_browser(html_path, width=1000, screenshot=shot, executable=executable)

    assert result["problems"] == []
    assert result["console_errors"] == result["page_errors"] == []
    assert result["blocked_requests"] == result["failed_requests"] == []
    assert set(result["views"]) == {"screen", "phone", "print"}
    for name, view in result["views"].items():
        images = view["images"]
        assert [img["alt"] for img in images] == [
            "errors/template_raw",
            "kappa <&>",
            "a vector figure",
        ], name
        for img in images:
            assert img["decoded"] and img["complete"], (name, img)
            assert img["natural_width"] > 0 and img["natural_height"] > 0, (name, img)
            assert img["width"] > 0 and img["height"] > 0, (name, img)
            assert img["width"] <= view["viewport_width"], (name, img)
        # 6 x 3 in at 200 dpi
        assert (images[0]["natural_width"], images[0]["natural_height"]) == (1200, 600)
        tables = view["tables"]
        assert [(t["body_rows"], t["columns"]) for t in tables] == [
            (2, 3),
            (6, WIDE_COLUMNS + 1),
            (5, 2),
        ], name
        assert all(t["width"] > 0 and t["height"] > 0 for t in tables), name
        assert not view["horizontal_overflow"], name

    phone = result["views"]["phone"]
    assert phone["viewport_width"] <= PHONE_WIDTH
    # the wide table is wider than the phone, yet the page does not scroll sideways:
    # the table scrolls inside its own box
    assert phone["tables"][1]["width"] > PHONE_WIDTH
    assert phone["scroll_width"] <= phone["viewport_width"]
    assert all(img["width"] <= phone["viewport_width"] for img in phone["images"])

    # on paper (print media, A4 width) every figure is still decoded and drawn within
    # the page, and even the wide table fits (checked for all views above)
    printed = result["views"]["print"]
    assert printed["media"] == "print" and printed["width"] == PRINT_WIDTH
    assert printed["tables"][1]["width"] <= PRINT_WIDTH

    with Image.open(shot) as png:
        assert png.format == "PNG"
        assert png.width == 1000 and png.height > 900  # the full page


def test_checker_reports_what_is_broken(tmp_path):
    executable = chromium_or_skip()
    page = tmp_path / "broken.html"
    page.write_text(
        "<!DOCTYPE html><html><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'></head><body>"
        "<img alt='broken' src='data:image/png;base64,AAAAAAAA'>"
        "<img alt='remote' src='http://127.0.0.1:9/x.png'>"
        "<table></table>"
        "<div style='width: 2000px'>too wide for a phone</div>"
        "<script>console.error('boom from the page')</script>"
        "</body></html>",
        encoding="utf-8",
    )
    result = check_in_browser(page, print_width=None, executable=executable)
    problems = "\n".join(result["problems"])
    assert "image 0 ('broken'" in problems and "not decoded" in problems
    assert "image 1 ('remote'" in problems
    assert "127.0.0.1:9" in "\n".join(result["blocked_requests"])
    assert "table 0 has no rows" in problems
    assert "phone: the page is wider than its viewport" in problems
    assert any("boom from the page" in m for m in result["console_errors"])
    assert set(result["views"]) == {"screen", "phone"}
