"""engine.viewer in headless Chromium: an exported replay and the live page, really drawn.

Both pages are opened in the ``page`` fixture (Debian's Chromium through Playwright, WebGL
by SwiftShader; skipped with the reason where no browser exists). Each test checks the page's
scene description (the k3d drawables by name), that nothing was fetched from the network, and
the pixels: stepping the world changes the picture, and the contact normals (drawn in
``CONTACT_COLOR``) are absent while the cubes fall and present once they land.
"""

from __future__ import annotations

import io
import json
import urllib.request
from pathlib import Path

import numpy as np
from PIL import Image

from engine.viewer import Viewer
from engine.viewer.settings import CONTACT_COLOR

from .test_viewer import add_cube, make_floor_sim, step

CAMERA = [1.2, 0.9, 1.4, 0.1, 0.1, 0.0, 0.0, 1.0, 0.0]  # eye, target, up: the cubes up close
NAMES_JS = "Object.values(window.rigidsimViewer.getWorld().ObjectsListJson).map(o => o.name)"


def small(page):
    """The page at 640 x 480: software WebGL draws a third of the 1024 x 768 pixels."""
    page.set_viewport_size({"width": 640, "height": 480})
    return page


def screenshot(page) -> np.ndarray:
    """``(H, W, 3)`` uint8 screenshot of the page."""
    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB"))


def contact_pixels(image: np.ndarray) -> int:
    """Pixels within 40 levels per channel of the contact normals' red (lit lines vary)."""
    red = np.array([(CONTACT_COLOR >> 16) & 255, (CONTACT_COLOR >> 8) & 255, CONTACT_COLOR & 255])
    return int(np.sum(np.all(np.abs(image.astype(int) - red) <= 40, axis=2)))


def changed_fraction(a: np.ndarray, b: np.ndarray) -> float:
    """Fraction of pixels whose colour differs by more than 24 levels in some channel."""
    return float(np.mean(np.any(np.abs(a.astype(int) - b.astype(int)) > 24, axis=2)))


def only_local_requests(page) -> list[str]:
    """Start recording requests that leave this machine's files and the page's own data."""
    remote: list[str] = []
    local = ("file:", "data:", "blob:", "http://127.0.0.1")
    page.on("request", lambda r: None if r.url.startswith(local) else remote.append(r.url))
    return remote


def two_falling_cubes(test_assets: Path):
    sim = make_floor_sim(test_assets)
    cubes = [add_cube(sim, [0.0, 0.6, 0.0]), add_cube(sim, [0.35, 0.9, 0.0])]
    return sim, cubes


def test_exported_replay_shows_the_cubes_and_contacts_appear_as_they_land(
    page, test_assets, tmp_path
):
    sim, cubes = two_falling_cubes(test_assets)
    handles = [cube.handle for cube in cubes]
    with sim:
        viewer = Viewer(sim, camera=CAMERA)
        viewer.start_recording()
        for _ in range(40):  # 1.33 s: both cubes have landed by 0.5 s
            step(sim, 2 / 60)
            viewer.update()
        path = viewer.replay().save(tmp_path / "replay.html")
    remote = only_local_requests(small(page))
    page.goto(path.as_uri())
    page.wait_for_function("window.rigidsimReady === true", timeout=60_000)
    names = page.evaluate(NAMES_JS)
    assert {"stage", "contacts", *handles} <= set(names)
    page.evaluate("window.rigidsimShowFrame(0)")
    page.wait_for_timeout(500)
    falling = screenshot(page)
    page.evaluate("window.rigidsimShowFrame(40)")
    page.wait_for_timeout(500)
    landed = screenshot(page)
    assert page.evaluate("window.rigidsimFrame") == 40
    assert changed_fraction(falling, landed) > 0.005  # the cubes moved on screen
    assert contact_pixels(falling) == 0  # in the air: no contact
    assert contact_pixels(landed) > 30  # on the floor: the normals are drawn
    # the slider drives the same frames a student scrubs through
    page.fill("#rigidsim-controls input[type=range]", "0")
    page.wait_for_timeout(500)
    assert page.evaluate("window.rigidsimFrame") == 0
    assert contact_pixels(screenshot(page)) == 0
    assert remote == [] and page.console_errors == []


def test_live_page_follows_the_simulation_steps(page, test_assets):
    sim, cubes = two_falling_cubes(test_assets)
    with sim, Viewer(sim, camera=CAMERA) as viewer:
        remote = only_local_requests(small(page))
        url = viewer.serve()
        page.goto(url)
        page.wait_for_function("window.rigidsimVersion >= 1", timeout=60_000)
        names = page.evaluate(NAMES_JS)
        assert {"stage", "contacts", *(cube.handle for cube in cubes)} <= set(names)
        page.wait_for_timeout(500)
        before = screenshot(page)
        assert contact_pixels(before) == 0
        viewer.follow()  # from now on every step_physics redraws
        step(sim, 1.0)
        with urllib.request.urlopen(f"{url}scene.json", timeout=10) as answer:
            version = json.loads(answer.read())["version"]
        page.wait_for_function(f"window.rigidsimVersion >= {version}", timeout=30_000)
        page.wait_for_timeout(500)
        after = screenshot(page)
        assert changed_fraction(before, after) > 0.005
        assert contact_pixels(after) > 10  # on the floor: the normals are drawn
        assert remote == [] and page.console_errors == []
