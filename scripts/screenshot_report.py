"""Screenshot an HTML report in headless Chromium, checking it as the tests do.

Usage (from the checkout root, with the dev extra installed and Debian's chromium)::

    python scripts/screenshot_report.py runs/ch5/report.html docs/screenshots/ch5.png \\
        [--width 1000] [--full-page]

Besides the PNG, the report is checked the way ``tests/evaluate/test_html_browser.py``
checks one (every image decoded, every table drawn, no console errors, no
sideways scrolling on a 390 px phone, all images present in print): the
problems found are printed and the exit status is 1 if there are any, 2 if no
browser could be found. The browser-driving code is ``tests/browser.py``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from browser import check_in_browser, find_chromium, playwright_available


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("report_html", type=Path, help="the HTML report to open")
    parser.add_argument("out_png", type=Path, help="where to write the screenshot (PNG)")
    parser.add_argument(
        "--width", type=int, default=1000, help="viewport width, CSS px (default 1000)"
    )
    parser.add_argument(
        "--full-page", action="store_true", help="capture the whole page, not only the first 900 px"
    )
    args = parser.parse_args(argv)
    if not args.report_html.is_file():
        parser.error(f"no such file: {args.report_html}")
    executable = find_chromium()
    if executable is None or not playwright_available():
        print(
            "no chromium browser or no playwright: install Debian's chromium package and "
            "pip install -e '.[dev]'",
            file=sys.stderr,
        )
        return 2
    result = check_in_browser(
        args.report_html,
        width=args.width,
        screenshot=args.out_png,
        full_page=args.full_page,
        executable=executable,
    )
    screen = result["views"]["screen"]
    print(
        f"{args.out_png}: {len(screen['images'])} images, {len(screen['tables'])} tables, "
        f"Chromium {result['browser_version']}, {result['seconds']:.1f} s"
    )
    for problem in result["problems"]:
        print(f"problem: {problem}", file=sys.stderr)
    return 1 if result["problems"] else 0


if __name__ == "__main__":
    sys.exit(main())
