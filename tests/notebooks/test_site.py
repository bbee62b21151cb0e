"""The documentation site, built as ``bash scripts/docs.sh --fast`` builds it and read in Chromium.

The build takes the notebooks that ``test_notebooks.py`` executed in this session (the
``executed_notebooks`` folder, shared by the xdist workers: the build waits for the notebooks
still running on another worker; any missing one is executed by the build), so CI runs each
notebook once. Then headless Chromium (``tests/browser_support.py``; skipped with the reason
where no browser exists) opens the site, served from a local server on 127.0.0.1 as a host
would serve it (and once from disk, as a student opens ``build/docs/index.html``), with no
network, and checks what a reader sees: every page is reachable from the index's navigation,
equations are typeset by the bundled MathJax (no raw ``$$`` or ``\\(`` left), the notebooks'
figures and videos are there and load, no page logs an error, search finds a class, and no
page shows an absolute path of the build. Without a browser it still checks that the build
printed no ``WARNING`` or ``ERROR`` line (Sphinx runs with ``-W``), that the search index
describes each object once and indexes the pages' text.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from functools import partial
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
# pages Sphinx writes besides the content pages: indexes and the search page
GENERATED = {"genindex.html", "search.html", "py-modindex.html"}


@dataclass(frozen=True)
class SiteBuild:
    site: Path  # the built site's folder
    log: str  # everything the build printed


# Sphinx's math elements ("math notranslate nohighlight"; MathJax's own output also has
# spans of class "math", hence the second class): each must hold MathJax's typeset output
MATH_TYPESET = """() => [...document.querySelectorAll('.math.notranslate')].every(
    e => e.querySelector('.MathJax, .MathJax_Display, .MathJax_SVG, .MathJax_CHTML'))"""


#: how long the build waits for the notebooks other xdist workers are executing
NOTEBOOK_WAIT_S = 900


def wait_for_executed_notebooks(session: pytest.Session, folder: Path) -> None:
    """Wait until every notebook whose execution test is in this session (on any xdist
    worker) has its executed copy in ``folder`` or has failed; after ``NOTEBOOK_WAIT_S`` the
    build executes what is missing itself."""
    names = [
        item.callspec.params["path"].name
        for item in session.items
        if getattr(item, "originalname", "") == "test_notebook_executes_in_fast_mode"
    ]
    deadline = time.monotonic() + NOTEBOOK_WAIT_S
    while time.monotonic() < deadline:
        waiting = [
            n for n in names if not (folder / n).exists() and not (folder / f"{n}.failed").exists()
        ]
        if not waiting:
            return
        time.sleep(2.0)


@pytest.fixture(scope="module")
def site_build(
    request: pytest.FixtureRequest,
    tmp_path_factory: pytest.TempPathFactory,
    executed_notebooks: Path,
) -> SiteBuild:
    wait_for_executed_notebooks(request.session, executed_notebooks)
    out = tmp_path_factory.mktemp("site") / "docs"
    env = dict(os.environ, PYTHON=sys.executable)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    done = subprocess.run(
        ["bash", "scripts/docs.sh", "--fast", "--executed", str(executed_notebooks)]
        # one Sphinx process: the suite's other workers keep the cores busy, and Sphinx's
        # parallel build spends about a fifth more CPU (pickling its environment between
        # processes) for no gain in time then
        + ["--out", str(out), "--jobs", "1"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return SiteBuild(out, done.stdout + done.stderr)


@pytest.fixture(scope="module")
def site(site_build: SiteBuild) -> Path:
    return site_build.site


def test_the_build_reports_no_warning_or_error(site_build: SiteBuild) -> None:
    # Sphinx's own warnings already fail the build (-W); this also catches what runs beside
    # it: a notebook kernel's or the replay writer's WARNING or ERROR lines
    flagged = [line for line in site_build.log.splitlines() if "WARNING" in line or "ERROR" in line]
    assert flagged == []


def test_each_object_is_described_once_and_pages_are_indexed_with_their_text(site: Path) -> None:
    text = (site / "searchindex.js").read_text(encoding="utf-8")
    index = json.loads(text[text.index("(") + 1 : text.rindex(")")])
    described = [
        f"{prefix}.{entry[4]}" for prefix, entries in index["objects"].items() for entry in entries
    ]
    assert len(described) == len(set(described))
    methods = [name for name in described if name.endswith(".ManagedRigidObject.apply_impulse")]
    assert len(methods) == 1, methods  # once, in the module that defines the class
    # a word of a page's body (not of its titles) finds that page
    docnames = index["docnames"]
    pages = index["terms"]["sutherland"]  # Sutherland-Hodgman clipping, in the rendering guide
    assert docnames.index("rendering") in (pages if isinstance(pages, list) else [pages])


class QuietHandler(SimpleHTTPRequestHandler):
    """Serves the site without logging; the browser's own favicon request gets no content
    (a 404 would be logged as a console error of every page)."""

    def do_GET(self) -> None:
        if self.path == "/favicon.ico":
            self.send_response(204)
            self.end_headers()
            return
        super().do_GET()

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - the base's name
        pass


@pytest.fixture(scope="module")
def server(site: Path) -> Iterator[str]:
    """The site on http://127.0.0.1:<free port>/ for the module's tests, then shut down."""
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), partial(QuietHandler, directory=str(site)))
    thread = threading.Thread(target=httpd.serve_forever, name="docs-site", daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join()


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


def real_errors(errors: list[str]) -> list[str]:
    """Console errors less MathJax 2's font probe: it declares a font ``MathJax_Blank`` at
    ``about:blank`` to time web fonts, which Chromium refuses (and logs) on every page."""
    probes = sum("Access to font at 'about:blank'" in error for error in errors)
    kept = [error for error in errors if "Access to font at 'about:blank'" not in error]
    for _ in range(probes):  # each refused probe also logs one failed load
        if "Failed to load resource: net::ERR_FAILED" in kept:
            kept.remove("Failed to load resource: net::ERR_FAILED")
    return kept


def open_page(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_load_state("load")


def test_pages_in_chromium(site: Path, server: str, page: Any) -> None:
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    open_page(page, server + "index.html")
    links = page.eval_on_selector_all(
        ".sidebar-tree a.reference.internal", "anchors => anchors.map(a => a.href)"
    )
    reachable = {link.split("#")[0].removeprefix(server) for link in links}
    assert content_pages(site) - {"index.html"} <= reachable
    figures = videos = math_pages = 0
    for name in sorted(reachable):
        open_page(page, server + name)
        assert page.title(), name
        if page.locator(".math.notranslate").count():
            try:
                page.wait_for_function(MATH_TYPESET, timeout=60_000)
            except PlaywrightTimeout:
                raise AssertionError(f"{name}: equations not typeset in 60 s") from None
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
    assert real_errors(page.console_errors) == []


def test_math_is_typeset_from_disk_too(site: Path, page: Any) -> None:
    # file:// pages may not load MathJax's web fonts (Chromium refuses fonts of origin
    # "null"), but the equations are typeset all the same
    open_page(page, (site / "notebooks" / "01_rigid_body_integration.html").as_uri())
    page.wait_for_function(MATH_TYPESET, timeout=60_000)
    assert "\\(" not in page.inner_text("article")


def test_search_finds_the_pathfinder(server: str, page: Any) -> None:
    open_page(page, server + "search.html?q=PathFinder")
    page.wait_for_selector("#search-results li", timeout=60_000)
    assert "api/navmesh" in page.inner_html("#search-results")
