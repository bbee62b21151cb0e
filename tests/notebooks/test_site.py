"""The documentation site, built as ``bash scripts/docs.sh --fast`` builds it and read in Chromium.

The build takes the notebooks that ``test_notebooks.py`` executed in this session (the
``executed_notebooks`` folder; any missing one is executed by the build), so CI runs each
notebook once. Then headless Chromium (``tests/browser_support.py``; skipped with the reason
where no browser exists) opens the site from disk, with no network, and checks what a reader
sees: every page is reachable from the index's navigation, equations are typeset by the
bundled MathJax (no raw ``$$`` or ``\\(`` left), the notebooks' figures and videos are
there and load, search finds a class, and no page shows an absolute path of the build.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
# pages Sphinx writes besides the content pages: indexes and the search page
GENERATED = {"genindex.html", "search.html", "py-modindex.html"}
MATH_TYPESET = """() => [...document.querySelectorAll('.math')].every(
    e => e.querySelector('.MathJax, .MathJax_Display, .MathJax_SVG, .MathJax_CHTML'))"""


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory, executed_notebooks: Path) -> Path:
    out = tmp_path_factory.mktemp("site") / "docs"
    env = dict(os.environ, PYTHON=sys.executable)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    done = subprocess.run(
        ["bash", "scripts/docs.sh", "--fast", "--executed", str(executed_notebooks)]
        + ["--out", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return out


def content_pages(site: Path) -> set[str]:
    pages = {
        path.relative_to(site).as_posix()
        for path in site.rglob("*.html")
        if not path.relative_to(site).parts[0].startswith("_")
    }
    return pages - GENERATED - {"replays/tutorial_replay.html"}


def test_every_docs_page_notebook_and_package_has_a_page(site: Path) -> None:
    pages = content_pages(site)
    for page in (ROOT / "docs").glob("*.md"):
        assert f"{page.stem}.html" in pages, page.name
    for notebook in (ROOT / "notebooks").glob("*.ipynb"):
        assert f"notebooks/{notebook.stem}.html" in pages, notebook.name
    for package in ("engine", "engine.physics", "render", "navmesh"):
        assert f"api/{package}.html" in pages


def test_no_page_shows_an_absolute_path_of_the_build(site: Path) -> None:
    forbidden = {str(ROOT), os.path.realpath(ROOT), str(site), str(site.parent), str(Path.home())}
    forbidden |= {"/tmp/pytest-of-", "/tmp/rigidsim-docs-"}
    for path in site.rglob("*.html"):
        text = path.read_text(encoding="utf-8", errors="replace")
        found = [folder for folder in forbidden if folder in text]
        assert found == [], f"{path.relative_to(site)} shows {found}"


def test_no_page_loads_anything_from_the_network(site: Path) -> None:
    for path in site.rglob("*.html"):
        text = path.read_text(encoding="utf-8", errors="replace")
        for tag in ("<script", "<link"):
            for chunk in text.split(tag)[1:]:
                head = chunk.split(">", 1)[0]
                assert 'src="http' not in head and 'href="http' not in head, (
                    f"{path.relative_to(site)}: {tag}{head}>"
                )


def open_page(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_load_state("load")


def test_pages_in_chromium(site: Path, page: Any) -> None:
    index = site / "index.html"
    open_page(page, index.as_uri())
    links = page.eval_on_selector_all(
        ".sidebar-tree a.reference.internal", "anchors => anchors.map(a => a.href)"
    )
    reachable = {
        Path(link.split("#")[0].removeprefix("file://")).relative_to(site).as_posix()
        for link in links
    }
    assert content_pages(site) - {"index.html"} <= reachable
    figures = videos = math_pages = 0
    for name in sorted(reachable):
        open_page(page, (site / name).as_uri())
        assert page.title(), name
        if page.locator(".math").count():
            page.wait_for_function(MATH_TYPESET, timeout=60_000)
            math_pages += 1
        text = page.inner_text("article")
        assert "$$" not in text and "\\(" not in text and "\\[" not in text, name
        # every image has loaded (a broken one has naturalWidth 0)
        broken = page.eval_on_selector_all(
            "article img", "images => images.filter(i => !i.complete || !i.naturalWidth).length"
        )
        assert broken == 0, name
        if name.startswith("notebooks/"):
            figures += page.locator(".cell_output img").count()
            videos += page.locator(".cell_output video source[src^='data:video/mp4']").count()
    assert math_pages >= 3  # notebooks 01, 02, 04 at least carry equations
    assert figures >= 10
    assert videos >= 9  # the tutorial notebook's nine videos, at least
    assert page.console_errors == []


def test_search_finds_the_pathfinder(site: Path, page: Any) -> None:
    open_page(page, (site / "search.html").as_uri() + "?q=PathFinder")
    page.wait_for_selector("#search-results li", timeout=60_000)
    assert "api/navmesh" in page.inner_html("#search-results")
