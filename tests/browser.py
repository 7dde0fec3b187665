"""Open an HTML file in headless Chromium and report what a reader would see.

A helper module shared by the tests and by ``scripts/screenshot_report.py`` (it
is not a test file and imports neither pytest nor Playwright at import time).
It drives the system's Chromium (Debian's ``chromium`` package) through
Playwright for Python; Playwright never downloads a browser of its own here.

Use from a test::

    from browser import check_in_browser, chromium_or_skip

    def test_report_renders(tmp_path):
        chromium_or_skip()
        result = check_in_browser(tmp_path / "report.html", screenshot=tmp_path / "shot.png")
        assert result["problems"] == []

Test files outside ``tests/`` itself put this directory on ``sys.path`` first
(see ``tests/evaluate/test_html_browser.py``).
"""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path
from typing import Any

__all__ = [
    "CHROMIUM_ARGS",
    "PHONE_WIDTH",
    "PRINT_WIDTH",
    "check_in_browser",
    "chromium_or_skip",
    "find_chromium",
    "launch_chromium",
    "playwright_available",
]

#: Chromium flags: no sandbox (containers, root), no GPU, and no traffic of its own.
CHROMIUM_ARGS: tuple[str, ...] = (
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
)

#: CSS width of a phone screen, px (a 6.1-inch phone in portrait).
PHONE_WIDTH = 390

#: CSS width of the printable area of an A4 page with 15 mm margins, px (180 mm at 96 px/in).
PRINT_WIDTH = 680

_CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")

# Collects, in the page, what every image and table looks like.
_MEASURE_JS = """
async () => {
  const images = [...document.images];
  const decoded = await Promise.all(
    images.map((img) => img.decode().then(() => true, () => false)));
  const box = (el) => { const r = el.getBoundingClientRect();
                        return {width: r.width, height: r.height}; };
  const root = document.documentElement;
  return {
    images: images.map((img, i) => ({
      alt: img.alt,
      src: img.getAttribute('src').slice(0, 40),
      decoded: decoded[i],
      complete: img.complete,
      natural_width: img.naturalWidth,
      natural_height: img.naturalHeight,
      ...box(img),
    })),
    tables: [...document.querySelectorAll('table')].map((t) => ({
      rows: t.rows.length,
      body_rows: t.tBodies.length ? [...t.tBodies].reduce((n, b) => n + b.rows.length, 0)
                                  : t.rows.length,
      columns: t.rows.length ? t.rows[0].cells.length : 0,
      ...box(t),
    })),
    viewport_width: root.clientWidth,
    scroll_width: root.scrollWidth,
    body_scroll_width: document.body ? document.body.scrollWidth : 0,
  };
}
"""


def find_chromium() -> str | None:
    """Path of a Chromium executable, or None.

    ``$VIBRISSA_CHROMIUM`` wins when set; otherwise the usual command names on
    ``PATH`` are tried.
    """
    env = os.environ.get("VIBRISSA_CHROMIUM")
    if env:
        return env if Path(env).is_file() else shutil.which(env)
    for name in _CANDIDATES:
        path = shutil.which(name)
        if path:
            return path
    return None


def playwright_available() -> bool:
    """Whether Playwright for Python can be imported."""
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return False
    return True


def chromium_or_skip() -> str:
    """Return the Chromium executable, or skip the calling test saying why there is none."""
    import pytest

    executable = find_chromium()
    if executable is None:
        pytest.skip(
            "no chromium browser found (install Debian's chromium package: "
            "apt-get install chromium; .ci/run does so when it runs as root)"
        )
    if not playwright_available():
        pytest.skip("playwright is not installed (pip install -e '.[dev]')")
    return executable


def launch_chromium(playwright: Any, executable: str | None = None) -> Any:
    """Launch headless Chromium (the system's) from a started Playwright instance."""
    executable = executable or find_chromium()
    if executable is None:
        raise FileNotFoundError("no chromium browser found (install Debian's chromium package)")
    return playwright.chromium.launch(
        executable_path=executable, headless=True, args=list(CHROMIUM_ARGS)
    )


def _local(url: str) -> bool:
    return url.startswith(("data:", "file:"))


def _view(
    browser: Any,
    url: str,
    width: int,
    media: str,
    log: dict[str, list[str]],
    screenshot: Path | None = None,
    full_page: bool = True,
) -> dict[str, Any]:
    """Load ``url`` at ``width`` CSS px under ``media`` and measure it."""
    context = browser.new_context(
        viewport={"width": width, "height": 900}, device_scale_factor=1, offline=True
    )
    try:
        page = context.new_page()
        label = f"{media}@{width}px"
        page.on(
            "console",
            lambda msg: (
                log["console_errors"].append(f"{label}: {msg.text}")
                if msg.type == "error"
                else None
            ),
        )
        page.on("pageerror", lambda exc: log["page_errors"].append(f"{label}: {exc}"))
        page.on(
            "requestfailed",
            lambda req: (
                log["failed_requests"].append(f"{label}: {req.url[:80]} ({req.failure})")
                if _local(req.url)
                else None
            ),
        )

        def route(r: Any) -> None:
            if _local(r.request.url):
                r.continue_()
            else:
                log["blocked_requests"].append(f"{label}: {r.request.url[:80]}")
                r.abort()

        page.route("**/*", route)
        page.emulate_media(media=media)
        page.goto(url, wait_until="load")
        view = page.evaluate(_MEASURE_JS)
        view.update(
            width=width,
            media=media,
            horizontal_overflow=view["scroll_width"] > view["viewport_width"],
        )
        if screenshot is not None:
            screenshot.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(screenshot), full_page=full_page)
        return view
    finally:
        context.close()


def _problems(views: dict[str, dict[str, Any]], log: dict[str, list[str]]) -> list[str]:
    problems: list[str] = []
    for name, view in views.items():
        for i, img in enumerate(view["images"]):
            what = f"{name}: image {i} ({img['alt']!r}, {img['src']}...)"
            if not (img["decoded"] and img["natural_width"] > 0 and img["natural_height"] > 0):
                problems.append(f"{what} not decoded")
            elif not (img["width"] > 0 and img["height"] > 0):
                problems.append(f"{what} has an empty box")
            elif img["width"] > view["viewport_width"] + 0.5:
                problems.append(f"{what} wider than the page ({img['width']:.0f} px)")
        for i, table in enumerate(view["tables"]):
            if table["body_rows"] == 0 or table["columns"] == 0:
                problems.append(f"{name}: table {i} has no rows or columns")
            elif not (table["width"] > 0 and table["height"] > 0):
                problems.append(f"{name}: table {i} has an empty box")
        if view["horizontal_overflow"]:
            problems.append(
                f"{name}: the page is wider than its viewport ({view['scroll_width']} px content "
                f"in {view['viewport_width']} px)"
            )
    for key in ("console_errors", "page_errors", "failed_requests", "blocked_requests"):
        problems += [f"{key.replace('_', ' ')[:-1]}: {m}" for m in log[key]]
    return problems


def check_in_browser(
    html_path: str | os.PathLike[str],
    *,
    width: int = 1000,
    phone_width: int | None = PHONE_WIDTH,
    print_width: int | None = PRINT_WIDTH,
    screenshot: str | os.PathLike[str] | None = None,
    full_page: bool = True,
    executable: str | None = None,
) -> dict[str, Any]:
    """Render an HTML file in headless Chromium and report on its images and tables.

    The page is loaded offline (any request other than ``file:``/``data:`` is
    blocked and reported) in up to three views: ``screen`` at ``width`` CSS px,
    ``phone`` at ``phone_width`` and ``print`` (print media emulated, at
    ``print_width``, the width of a printed page).

    Parameters
    ----------
    html_path
        The HTML file.
    width
        Viewport width of the screen view, CSS px.
    phone_width
        Viewport width of the phone view, CSS px; None skips that view.
    print_width
        Viewport width of the print view, CSS px; None skips that view.
    screenshot
        If given, a PNG of the screen view is written there.
    full_page
        Whether the screenshot covers the whole page or only the first 900 px.
    executable
        Chromium to use; defaults to :func:`find_chromium`.

    Returns
    -------
    dict
        ``views``: per view name, ``images`` (``alt``, ``src`` prefix,
        ``decoded``, ``natural_width``/``natural_height`` in image px and the
        rendered ``width``/``height`` in CSS px), ``tables`` (``rows``,
        ``body_rows``, ``columns``, ``width``, ``height``), ``viewport_width``,
        ``scroll_width`` and ``horizontal_overflow``; ``console_errors``,
        ``page_errors``, ``failed_requests``, ``blocked_requests`` (lists of
        messages); ``problems``, everything above that a reader would notice
        (empty when the page is fine); ``browser_version``; ``seconds``, the
        wall time taken.
    """
    from playwright.sync_api import sync_playwright

    start = time.perf_counter()
    url = Path(html_path).resolve().as_uri()
    log: dict[str, list[str]] = {
        "console_errors": [],
        "page_errors": [],
        "failed_requests": [],
        "blocked_requests": [],
    }
    views: dict[str, dict[str, Any]] = {}
    with sync_playwright() as playwright:
        browser = launch_chromium(playwright, executable)
        try:
            views["screen"] = _view(
                browser,
                url,
                width,
                "screen",
                log,
                screenshot=None if screenshot is None else Path(screenshot),
                full_page=full_page,
            )
            if phone_width is not None:
                views["phone"] = _view(browser, url, phone_width, "screen", log)
            if print_width is not None:
                views["print"] = _view(browser, url, print_width, "print", log)
            version = browser.version
        finally:
            browser.close()
    return {
        "views": views,
        **log,
        "problems": _problems(views, log),
        "browser_version": version,
        "seconds": time.perf_counter() - start,
    }
