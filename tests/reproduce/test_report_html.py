"""Each experiment's real report.html in headless Chromium: every table and figure renders.

Skipped, saying why, where no Chromium or Playwright is installed (``.ci/run`` installs
Chromium when it runs as root).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/: the browser harness
from browser import check_in_browser, chromium_or_skip
from vibrissa.reproduce import experiments


@pytest.mark.parametrize("name", list(experiments()))
def test_report_html_renders(quick_runs, name, tmp_path):
    exe = chromium_or_skip()
    out, _ = quick_runs[name]
    html = out / "report.html"
    text = html.read_text()
    assert "figures/" not in re.sub(r"data:[^\"']+", "", text), "an image is not inlined"
    assert not re.search(r"(src|href)=[\"']https?://", text)
    md = (out / "report.md").read_text()
    n_tables = len(re.findall(r"^\|---", md, flags=re.M))
    n_images = len(re.findall(r"!\[[^\]]*\]\(", md))
    assert n_tables > 3 and n_images > 3
    res = check_in_browser(html, screenshot=tmp_path / "shot.png", executable=exe)
    assert res["problems"] == []
    assert res["console_errors"] == [] and res["page_errors"] == []
    for view in res["views"].values():
        assert len(view["tables"]) == n_tables
        assert len(view["images"]) == n_images
        assert all(t["rows"] > 1 for t in view["tables"])
        assert all(i["decoded"] and i["natural_width"] > 0 for i in view["images"])
    assert (tmp_path / "shot.png").stat().st_size > 10_000


@pytest.mark.parametrize("name", list(experiments()))
def test_a_report_links_to_the_ledger_rows_of_its_claims(quick_runs, name):
    from vibrissa.thesis.claims import EXPERIMENTS, anchor, claims_for

    out, _ = quick_runs[name]
    md = (out / "report.md").read_text()
    html = (out / "report.html").read_text()
    if name not in EXPERIMENTS:
        assert "thesis_claims.md#" not in md
        return
    claims = claims_for(name)
    assert claims
    for c in claims:
        link = f"docs/thesis_claims.md#{anchor(c.id)}"
        assert link in md and f'href="{link}"' in html
