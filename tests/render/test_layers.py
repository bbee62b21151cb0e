"""render_over_layer: moving meshes drawn over a kept static frame equal a full render."""

from __future__ import annotations

import numpy as np
import pytest

from render.camera import Camera
from render.frame import RenderMesh, RenderScene, StaticLayer, render_frame, render_over_layer

H, W = 48, 80
QUAD_FACES = np.array([[0, 1, 2], [0, 2, 3]])


def quad(x0: float, x1: float, y0: float, y1: float, z: float) -> np.ndarray:
    """A fronto-parallel quad at camera-frame depth ``z`` (counter-clockwise seen from +z)."""
    return np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], dtype=float)


def random_meshes(rng: np.random.Generator, n: int, lit: bool, first_id: int) -> list:
    """``n`` random triangle soups in front of the camera, vertex colored."""
    meshes = []
    for i in range(n):
        vertices = rng.uniform(-1.5, 1.5, size=(20, 3)) + [0, 0, -3]
        faces = rng.integers(0, 20, size=(25, 3))
        colors = rng.integers(0, 256, size=(20, 4), dtype=np.uint8)
        meshes.append(
            RenderMesh(vertices, faces, vertex_colors=colors, lit=lit, semantic_id=first_id + i)
        )
    return meshes


def assert_same_frame(a, b) -> None:
    for name in ("rgba", "depth", "ids"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


@pytest.mark.parametrize("cull", [False, True])
def test_moving_meshes_over_a_static_layer_equal_the_full_render(cull):
    rng = np.random.default_rng(5)
    camera = Camera((H, W), hfov=75.0)
    static = random_meshes(rng, 3, lit=False, first_id=1)
    moving = random_meshes(rng, 2, lit=True, first_id=10)
    pose = np.eye(4)
    pose[:3, 3] = [0.1, 0.2, 0.3]
    layer = StaticLayer.from_frame(render_frame(static, camera, pose, cull_back_faces=cull))
    moving_scene = RenderScene(moving)
    buffers = None
    for step in range(3):  # move the moving meshes, reuse the layer and the buffers
        offset = np.eye(4)
        offset[:3, 3] = [0.2 * step, -0.1 * step, 0.05 * step]
        for i in range(len(moving)):
            moving_scene.set_world_from_mesh(i, offset)
            moving[i].world_from_mesh = offset
        over = render_over_layer(layer, moving_scene, camera, pose, buffers, cull)
        full = render_frame(static + moving, camera, pose, cull_back_faces=cull)
        assert_same_frame(over, full)
        buffers = over
    assert (over.ids >= 10).any() and ((over.ids > 0) & (over.ids < 10)).any()


def test_equal_depths_keep_the_static_pixel_as_the_full_render_does():
    camera = Camera((H, W))
    # a static and a moving quad in the very same plane, overlapping in x
    wall = RenderMesh(quad(-2, 0.5, -1, 1, -2.0), QUAD_FACES, semantic_id=1)
    patch = RenderMesh(quad(-0.5, 2, -1, 1, -2.0), QUAD_FACES, semantic_id=2, lit=True)
    layer = StaticLayer.from_frame(render_frame([wall], camera, np.eye(4)))
    over = render_over_layer(layer, [patch], camera, np.eye(4))
    full = render_frame([wall, patch], camera, np.eye(4))
    assert_same_frame(over, full)
    assert (over.ids == 1).any() and (over.ids == 2).any()


def test_a_moving_mesh_behind_the_static_layer_changes_nothing_and_none_gives_the_layer():
    camera = Camera((H, W))
    wall = RenderMesh(quad(-5, 5, -5, 5, -2.0), QUAD_FACES, semantic_id=1)
    hidden = RenderMesh(quad(-1, 1, -1, 1, -4.0), QUAD_FACES, semantic_id=2)
    static_frame = render_frame([wall], camera, np.eye(4))
    layer = StaticLayer.from_frame(static_frame)
    for moving in ([hidden], []):
        over = render_over_layer(layer, moving, camera, np.eye(4))
        assert_same_frame(over, static_frame)


def test_background_pixels_of_the_layer_take_moving_meshes():
    camera = Camera((H, W))
    layer = StaticLayer.from_frame(render_frame([], camera, np.eye(4)))
    box = RenderMesh(quad(-1, 1, -1, 1, -3.0), QUAD_FACES, semantic_id=4, lit=True)
    assert_same_frame(
        render_over_layer(layer, [box], camera, np.eye(4)), render_frame([box], camera, np.eye(4))
    )


def test_bad_layer_arguments_raise():
    camera = Camera((H, W))
    layer = StaticLayer.from_frame(render_frame([], camera, np.eye(4)))
    with pytest.raises(TypeError, match="layer"):
        render_over_layer("not a layer", [], camera, np.eye(4))
    with pytest.raises(ValueError, match="resolution"):
        render_over_layer(layer, [], Camera((10, 12)), np.eye(4))
    with pytest.raises(ValueError, match="resolution"):  # a camera larger than the layer
        render_over_layer(layer, [], Camera((H + 8, W)), np.eye(4))


def test_a_moving_mesh_covering_one_pixel_over_a_layer_equals_the_full_render():
    # the smallest change over a kept layer: a quad exactly on pixel (row 10, col 20)
    camera = Camera((H, W))
    depth = 2.0
    x0, x1 = ((c - camera.cx) * depth / camera.fx for c in (20, 21))
    y1, y0 = (-(r - camera.cy) * depth / camera.fy for r in (10, 11))
    background = RenderMesh(quad(-9, 9, -9, 9, -5.0), QUAD_FACES, base_color=(10, 20, 30))
    pixel = RenderMesh(quad(x0, x1, y0, y1, -depth), QUAD_FACES, base_color=(200, 100, 50))
    layer = StaticLayer.from_frame(render_frame([background], camera, np.eye(4)))
    over = render_over_layer(layer, [pixel], camera, np.eye(4))
    assert_same_frame(over, render_frame([background, pixel], camera, np.eye(4)))
    assert tuple(over.rgba[10, 20, :3]) == (200, 100, 50)
    assert over.depth[10, 20] == pytest.approx(depth)
    assert np.isclose(over.depth, 5.0).sum() == H * W - 1  # the rest is the layer
