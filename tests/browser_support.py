"""Headless Chromium for the tests that look at pages (the docs site, the 3D viewer).

The browser is Debian's ``chromium`` (``/usr/bin/chromium``; ``RIGIDSIM_CHROMIUM`` overrides the
path), driven through Playwright's Python API with ``executable_path`` so that Playwright never
downloads a browser of its own. The test command installs no browser: where none can be found,
the tests that need one are skipped with a message saying what is missing; they never pass
without having looked. CI (``.ci/run``) installs Debian's package and sets
``RIGIDSIM_REQUIRE_BROWSER=1``, which turns that skip into a failure.

The flags are those of a closed network: no background connections, no component updates, no sync,
software WebGL (SwiftShader), a fresh profile each launch.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--enable-unsafe-swiftshader",
]


def chromium_path() -> Path | None:
    """Return the Chromium executable to drive, or None where none is installed."""
    override = os.environ.get("RIGIDSIM_CHROMIUM")
    if override:
        return Path(override) if Path(override).is_file() else None
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return Path(found)
    return None


def why_no_browser() -> str | None:
    """Return why no page can be opened here (None when a browser and Playwright are present)."""
    if chromium_path() is None:
        return "no Chromium found (install Debian's 'chromium' or set RIGIDSIM_CHROMIUM)"
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "Playwright's Python package is missing (pip install playwright)"
    return None


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """One headless Chromium for the whole session; skips with the reason where none exists."""
    reason = why_no_browser()
    if reason is not None:
        if os.environ.get("RIGIDSIM_REQUIRE_BROWSER") == "1":
            pytest.fail(f"RIGIDSIM_REQUIRE_BROWSER=1 but {reason}")
        pytest.skip(reason)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(
            executable_path=str(chromium_path()), args=CHROMIUM_ARGS
        )
        yield chromium
        chromium.close()


@pytest.fixture
def page(browser: Any) -> Iterator[Any]:
    """A fresh page (1024 x 768) whose console errors are collected in ``page.console_errors``."""
    context = browser.new_context(viewport={"width": 1024, "height": 768})
    new_page = context.new_page()
    errors: list[str] = []

    def keep_error(message: Any) -> None:
        if message.type == "error":
            errors.append(message.text)

    new_page.on("console", keep_error)
    new_page.on("pageerror", lambda error: errors.append(str(error)))
    new_page.console_errors = errors
    yield new_page
    context.close()
