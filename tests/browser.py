"""A real headless browser (Debian's Chromium, driven by Playwright) for the page tests.

``load(path)`` opens a local file with every network request recorded (and refused), the
console errors collected and a screenshot taken.  Where no browser can be installed the
tests skip with the reason; ``.ci/run`` installs one and sets ``POLYELL_BROWSER``, and then
a missing browser is a failure.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

#: Flags of a headless Chromium in a closed sandbox (no background traffic, no GPU).
CHROMIUM_ARGS = [
    "--headless=new",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def chromium() -> str:
    """The browser's path, or skip (fail when CI promised one)."""
    path = os.environ.get("POLYELL_BROWSER") or shutil.which("chromium")
    if path and Path(path).exists():
        return path
    if os.environ.get("POLYELL_BROWSER"):
        pytest.fail(f"POLYELL_BROWSER={os.environ['POLYELL_BROWSER']} does not exist")
    pytest.skip("no Chromium on this machine: apt-get install chromium (as .ci/run does)")


@dataclass
class PageVisit:
    """What happened when a page was loaded."""

    requests: list[str] = field(default_factory=list)  # every URL that is not a local file
    errors: list[str] = field(default_factory=list)  # console errors and page exceptions
    screenshot: Path | None = None
    values: dict[str, object] = field(default_factory=dict)  # results of the checks


@contextmanager
def session(
    page_path: Path, wait_for: str, viewport: tuple[int, int] = (1100, 900)
) -> Iterator[tuple[Any, PageVisit]]:
    """Open ``page_path`` offline and wait for ``wait_for``; yield the Playwright page.

    Every request that is not a local file is recorded in the visit and refused; console
    errors and page exceptions are collected.  Use it to click, evaluate and take several
    screenshots of one page.
    """
    from playwright.sync_api import sync_playwright

    visit = PageVisit()
    own = page_path.resolve().as_uri()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium(), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})

            def route(r):
                url = r.request.url
                if url.startswith(("file:", "data:", "blob:")):  # local: not the network
                    r.continue_()
                    return
                visit.requests.append(url)
                r.abort()

            page.route("**/*", route)
            page.on(
                "console",
                lambda m: visit.errors.append(m.text) if m.type == "error" else None,
            )
            page.on("pageerror", lambda e: visit.errors.append(str(e)))
            page.goto(own, wait_until="load", timeout=60_000)
            page.wait_for_selector(wait_for, timeout=60_000)
            page.wait_for_timeout(500)  # let the plots and the math settle
            yield page, visit
        finally:
            browser.close()


def load(
    page_path: Path,
    screenshot: Path,
    checks: dict[str, str],
    wait_for: str,
    viewport: tuple[int, int] = (1100, 900),
) -> PageVisit:
    """Open ``page_path`` offline, wait for ``wait_for`` (a CSS selector), run ``checks``.

    ``checks`` maps names to JavaScript expressions evaluated in the page.
    """
    with session(page_path, wait_for, viewport) as (page, visit):
        for name, expression in checks.items():
            visit.values[name] = page.evaluate(expression)
        page.screenshot(path=str(screenshot), full_page=True)
        visit.screenshot = screenshot
    return visit


def coloured_share(png: Path) -> float:
    """Share of pixels that are neither white nor grey: how much of a colour plot is drawn."""
    import matplotlib.image

    image = matplotlib.image.imread(png)[..., :3]
    spread = image.max(axis=-1) - image.min(axis=-1)
    return float((spread > 0.15).mean())
