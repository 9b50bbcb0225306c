"""The documentation renders offline (issue 14): built here (the notebooks executed by the
build), opened in headless Chromium without network, its mathematics typeset by the
packaged MathJax."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from browser import load

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", str(DOCS), str(out)],
        check=True,
        capture_output=True,
        text=True,
    )
    return out


@pytest.mark.parametrize(
    "page", ["theory.html", "index.html", "notebooks/paper.html", "notebooks/candidates.html"]
)
def test_pages_render_their_mathematics_without_network(site, tmp_path, page):
    visit = load(
        site / page,
        tmp_path / "page.png",
        {
            "typeset": "document.querySelectorAll('mjx-container').length",
            "raw": r"(document.body.innerText.match(/\\\(|\\\[/g) || []).length",
            "errors": "document.querySelectorAll('mjx-merror').length",
            "figures": "[...document.images].filter(i => i.complete && i.naturalWidth > 0).length",
        },
        wait_for="body" if page == "index.html" else "mjx-container",
    )
    assert visit.requests == [], visit.requests  # MathJax and its fonts come from _static
    assert visit.errors == []
    if page == "theory.html":
        assert visit.values["typeset"] > 50  # every formula of the theory page
    if page.startswith("notebooks/"):  # executed: its figure is there and loads
        assert visit.values["figures"] >= 1 and visit.values["typeset"] >= 4
    assert visit.values["raw"] == 0 and visit.values["errors"] == 0
