"""Sphinx extension: search results show text on a site opened from disk (``file://``).

Sphinx's search page shows, under each page it finds, the lines around the words searched; it
reads them by fetching the page, which a browser refuses on ``file://`` (results would show
titles only). At the end of the build this writes ``_static/search_pages.js``: every page's
main content (``[role=main]``) reduced to its text and the elements that carry an ``id`` (the
anchors a result may point to), and the search page loads it with ``search_offline.js``,
which answers those fetches from it on ``file://``. About 1.5 MB, loaded by the search page
only.
"""

from __future__ import annotations

import html
import json
import re
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

PAGES_SCRIPT = "search_pages.js"
VOID_TAGS = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
             "track", "wbr"}  # fmt: skip
SKIPPED_PAGES = {"search.html", "genindex.html", "py-modindex.html"}


class MainContent(HTMLParser):
    """The text of a page's ``<article role="main">``, keeping each ``id`` as a ``<div>``."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.open: list[tuple[str, bool, bool]] = []  # (tag, wrote a div, text skipped)
        self.skipping = 0
        self.parts: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        found = dict(attrs)
        if not self.open and not (tag == "article" and found.get("role") == "main"):
            return
        if tag in VOID_TAGS:
            return
        anchor = found.get("id") if self.open else None
        skipped = tag in ("script", "style") or "headerlink" in (found.get("class") or "")
        if anchor:
            self.parts.append(f'<div id="{html.escape(anchor)}">')
        self.skipping += skipped
        self.open.append((tag, bool(anchor), skipped))

    def handle_endtag(self, tag: str) -> None:
        while self.open:
            opened, wrote_div, skipped = self.open.pop()
            self.parts.append("</div>" if wrote_div else "")
            self.skipping -= skipped
            if opened == tag:
                return

    def handle_data(self, data: str) -> None:
        if self.open and not self.skipping:
            self.parts.append(html.escape(re.sub(r"\s+", " ", data), quote=False))

    def text(self) -> str:
        return "".join(self.parts)


def main_content(page: Path) -> str:
    parser = MainContent()
    parser.feed(page.read_text(encoding="utf-8"))
    return parser.text()


def write_pages_script(outdir: Path) -> None:
    """``_static/search_pages.js``: ``window.RIGIDSIM_SEARCH_PAGES = {page: content}``."""
    pages = {}
    for page in sorted(outdir.rglob("*.html")):
        name = page.relative_to(outdir).as_posix()
        if name.startswith("_") or name in SKIPPED_PAGES:
            continue
        pages[name] = main_content(page)
    text = f"window.RIGIDSIM_SEARCH_PAGES = {json.dumps(pages, ensure_ascii=False)};\n"
    (outdir / "_static" / PAGES_SCRIPT).write_text(text, encoding="utf-8")


def add_scripts(app: Any, pagename: str, templatename: str, context: Any, doctree: Any) -> None:
    if pagename == "search":  # the two scripts load on the search page only
        app.add_js_file(PAGES_SCRIPT)
        app.add_js_file("search_offline.js")


def finish(app: Any, exception: Exception | None) -> None:
    if exception is None and app.builder.format == "html":
        write_pages_script(Path(app.outdir))


def setup(app: Any) -> dict[str, Any]:
    app.connect("html-page-context", add_scripts)
    app.connect("build-finished", finish)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
