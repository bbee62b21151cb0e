"""Debug lines over a rendered frame: pixels on the projected segment, the depth test against
the frame (hidden parts at opacity 0.1), and the plain reference bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from render.camera import Camera
from render.frame import RenderMesh, render_frame
from render.lines import OCCLUDED_OPACITY, draw_lines

CAMERA = Camera((48, 64), hfov=90.0)  # fx = 32 px


def blank():
    rgba = np.zeros((48, 64, 4), np.uint8)
    rgba[..., 3] = 255
    return rgba, np.zeros((48, 64), np.float32)


def test_a_line_covers_the_pixels_of_its_projection_in_its_color():
    rgba, depth = blank()
    # y = 0.53 at z = -2: py = 24 - 32 * 0.265 = 15.52, row 15; x from -0.98 to 0.98
    # projects to px 16.32 .. 47.68, columns 16 .. 47 (points clear of pixel edges)
    start, end = np.array([[-0.98, 0.53, -2.0]]), np.array([[0.98, 0.53, -2.0]])
    red = np.array([[1.0, 0.0, 0.0, 1.0]])
    draw_lines(rgba, depth, CAMERA, np.eye(4), start, end, red, red)
    rows, cols = np.nonzero(rgba[..., 0] == 255)
    assert set(rows.tolist()) == {15}
    assert cols.min() == 16 and cols.max() == 47 and len(cols) == 32
    assert np.all(rgba[rows, cols, 1:3] == 0)


def test_hidden_parts_are_faint_and_visible_parts_full():
    wall = RenderMesh(
        np.array([[0.0, -1, -1.5], [2, -1, -1.5], [2, 1, -1.5], [0.0, 1, -1.5]]),
        np.array([[0, 1, 2], [0, 2, 3]]),
        base_color=np.array([100, 100, 100, 255], np.uint8),
        lit=False,
    )  # covers the right half of the image, in front of the line
    frame = render_frame([wall], CAMERA, np.eye(4))
    rgba, depth = frame.rgba.copy(), frame.depth.copy()
    white = np.array([[1.0, 1.0, 1.0, 1.0]])
    draw_lines(
        rgba,
        depth,
        CAMERA,
        np.eye(4),
        np.array([[-1.0, 0, -2]]),
        np.array([[1.0, 0, -2]]),
        white,
        white,
    )
    assert rgba[24, 20, 0] == 255  # left: in front of nothing
    # right: behind the wall, blended at 0.1: floor(255 * 0.1 + 100 * 0.9 + 0.5) = 116
    expected = int(np.floor(255 * OCCLUDED_OPACITY + 100 * (1 - OCCLUDED_OPACITY) + 0.5))
    assert rgba[24, 44, 0] == expected
    np.testing.assert_array_equal(depth, frame.depth)  # lines do not write depth


def test_segments_crossing_the_near_plane_keep_their_front_part():
    rgba, depth = blank()
    green = np.array([[0.0, 1.0, 0.0, 1.0]])
    # from behind the camera to 4 m ahead, 0.5 m to the left: only the front part is drawn
    draw_lines(
        rgba,
        depth,
        CAMERA,
        np.eye(4),
        np.array([[-0.5, 0, 3.0]]),
        np.array([[-0.5, 0, -4.0]]),
        green,
        green,
    )
    rows, cols = np.nonzero(rgba[..., 1] == 255)
    assert len(cols) > 0 and cols.max() == 28  # the far end: 32 - 32 * 0.5 / 4 = 28
    assert cols.min() == 0  # ... and it leaves the image on the left


@pytest.mark.parametrize("width", [1.0, 3.0])
def test_vectorized_lines_equal_the_reference_bit_for_bit(width):
    rng = np.random.default_rng(7)
    wall = RenderMesh(
        np.array([[-1.0, -1, -2.5], [1, -1, -2.5], [1, 1, -3.5], [-1.0, 1, -3.5]]),
        np.array([[0, 1, 2], [0, 2, 3]]),
        base_color=np.array([90, 120, 30, 255], np.uint8),
        lit=False,
    )
    frame = render_frame([wall], CAMERA, np.eye(4))
    starts = rng.uniform(-2, 2, size=(12, 3)) + [0, 0, -3]
    ends = rng.uniform(-2, 2, size=(12, 3)) + [0, 0, -2]
    starts[0, 2] = 1.0  # crosses the near plane
    colors_a, colors_b = rng.random((12, 4)), rng.random((12, 4))
    fast, plain = frame.rgba.copy(), frame.rgba.copy()
    args = (frame.depth, CAMERA, np.eye(4), starts, ends, colors_a, colors_b, width)
    draw_lines(fast, *args)
    draw_lines(plain, *args, reference=True)
    np.testing.assert_array_equal(fast, plain)
    assert not np.array_equal(fast, frame.rgba)
