"""The vectorized rasterizer agrees with the textbook scalar one (render.reference): coverage,
depth and ids exactly, colors within one level of 255."""

from __future__ import annotations

import numpy as np
import pytest

from render.camera import Camera
from render.frame import RenderMesh, render_frame
from render.reference import bilinear_texel, reference_depth_and_ids, reference_frame
from render.shade import Lights


def random_scene(seed: int) -> list[RenderMesh]:
    """Random triangles around z = -3, some crossing the near plane or the image border."""
    rng = np.random.default_rng(seed)
    meshes = []
    for i in range(12):
        center = rng.uniform([-2, -1.5, -5], [2, 1.5, -0.5])
        vertices = center + rng.normal(scale=0.8, size=(3, 3))
        meshes.append(RenderMesh(vertices, np.array([[0, 1, 2]]), semantic_id=i + 1))
    return meshes


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("subtype", ["pinhole", "orthographic"])
def test_vectorized_and_scalar_rasterizers_agree(seed, subtype):
    camera = Camera((30, 40), hfov=80.0, near=0.3, subtype=subtype, ortho_scale=0.25)
    meshes = random_scene(seed)
    pose = np.eye(4)
    pose[:3, 3] = [0.1, 0.0, 0.2]
    frame = render_frame(meshes, camera, pose)
    depth, ids = reference_depth_and_ids(meshes, camera, pose)
    assert (depth > 0).sum() > 100  # the scene covers a good part of the image
    # coverage and visibility agree everywhere (the two use different formulas, so a pixel
    # center within rounding of an edge could in principle differ: none does here)
    np.testing.assert_array_equal(frame.depth > 0, depth > 0)
    np.testing.assert_array_equal(frame.ids, ids)
    # float32 depth buffer vs float64 reference
    np.testing.assert_allclose(frame.depth, depth, rtol=2e-6)


def test_scalar_reference_follows_the_top_left_rule_on_a_shared_diagonal():
    camera = Camera((8, 8), subtype="orthographic", ortho_scale=1 / 8)  # 1 px per unit
    # corners on pixel centers (pixel (r, c) center at x = c + 0.5 - 4, y = 4 - r - 0.5)
    a, b, c, d = (-3.5, 3.5), (2.5, 3.5), (2.5, -2.5), (-3.5, -2.5)
    vertices = np.array([[*a, -1.0], [*b, -1.0], [*c, -1.0], [*d, -1.0]])
    mesh = RenderMesh(vertices, np.array([[0, 1, 2], [0, 2, 3]]), semantic_id=1)
    depth, _ = reference_depth_and_ids([mesh], camera, np.eye(4))
    frame = render_frame([mesh], camera, np.eye(4))
    # the 6 x 6 block of centers on the top and left edges and inside; none twice
    assert (depth > 0).sum() == 36
    np.testing.assert_array_equal(frame.depth > 0, depth > 0)


def _shade_cases():
    """``test_shade``'s mixed scene (tests import in importlib mode)."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location(
        "_shade_cases", Path(__file__).parent / "test_shade.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("subtype", ["pinhole", "orthographic"])
def test_fast_colors_stay_within_one_level_of_the_float_reference(subtype):
    """Every material kind (flat, vertex colors, textures with and without tint, Gouraud)
    under the default lights, a world setup with a point light and a camera-frame light:
    the packed 8-bit path differs from the float fragment shader by at most 1/255."""
    meshes = _shade_cases()._mixed_scene(np.random.default_rng(15))
    shared = Lights([[0.0, 1.0, 0.3, 0.0], [2.0, 1.0, -2.0, 1.0]], [0.6, 0.3], ("world",) * 2)
    meshes[2].lights = meshes[4].lights = shared
    meshes[6].lights = Lights([[0.0, 0.0, 1.0, 0.0]], [0.5], ("camera",))
    camera = Camera((45, 60), hfov=80.0, subtype=subtype)
    pose = np.eye(4)
    pose[:3, 3] = [0.0, 0.3, 0.5]
    frame = render_frame(meshes, camera, pose)
    rgba, depth, ids = reference_frame(meshes, camera, pose)
    np.testing.assert_array_equal(frame.ids, ids)
    assert len(np.unique(ids)) >= 6  # every kind of mesh is on screen
    difference = np.abs(frame.rgba.astype(int) - rgba.astype(int))
    assert difference.max() <= 1
    assert np.count_nonzero(difference) > 0  # the fast path does quantize


@pytest.mark.parametrize("seed", range(2))
def test_clipped_textured_triangles_keep_their_colors(seed):
    """Triangles crossing the near plane: clipped pieces interpolate the attributes of the
    whole triangle (vertex colors, uvs) in both paths."""
    rng = np.random.default_rng(seed)
    texture = rng.integers(0, 256, (8, 6, 3), np.uint8)
    meshes = []
    for i, mesh in enumerate(random_scene(seed)):
        colors = rng.integers(0, 256, (3, 4), np.uint8)
        uvs = rng.uniform(-1.0, 2.0, (3, 2))
        meshes.append(
            RenderMesh(mesh.vertices, mesh.faces, vertex_colors=colors, uvs=uvs,
                       texture=texture, lit=i % 2 == 0, semantic_id=i + 1)
        )  # fmt: skip
    camera = Camera((30, 40), hfov=80.0, near=0.3)
    pose = np.eye(4)
    frame = render_frame(meshes, camera, pose)
    rgba, _, ids = reference_frame(meshes, camera, pose)
    np.testing.assert_array_equal(frame.ids, ids)
    assert np.abs(frame.rgba.astype(int) - rgba.astype(int)).max() <= 1


def test_one_pixels_color_by_hand():
    """A lit textured quad facing +x seen head on: ``base * texel * light`` with the light
    of a vertical face under the default setup, ``0.4 + 0.5 / sqrt(1.25) = 0.847``."""
    texture = np.array([[[200, 100, 50], [0, 0, 0]], [[0, 0, 0], [0, 0, 0]]], np.uint8)
    # the quad x = 0, y and z in [-1, 1], normal +x; uvs so that the image center is at
    # u = 0.25, v = 0.75: the center of the top-left texel (uv origin at the bottom)
    vertices = np.array([[0.0, -1, 1], [0.0, -1, -1], [0.0, 1, -1], [0.0, 1, 1]])
    uvs = np.array([[0.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0]])
    quad = RenderMesh(vertices, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs, texture=texture,
                      base_color=(255, 255, 128, 255), lit=True)  # fmt: skip
    pose = np.eye(4)
    pose[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # looking down -x
    pose[:3, 3] = [2.0, 0.0, 0.0]
    camera = Camera((1, 1), hfov=10.0)  # one pixel, its center on the optical axis
    light = 0.4 + 0.5 / np.sqrt(1.25)
    expected = np.rint(np.array([200, 100, 50 * 128 / 255]) * light)
    rgba, _, _ = reference_frame([quad], camera, pose)
    assert bilinear_texel(texture, 0.25, 0.75, "bottom").tolist() == [
        200 / 255,
        100 / 255,
        50 / 255,
    ]
    halfway = bilinear_texel(texture, 0.5, 0.75, "bottom")  # between two texel centers
    assert halfway == pytest.approx([100 / 255, 50 / 255, 25 / 255])
    wrapped = bilinear_texel(texture, -0.75, 1.75, "bottom")  # REPEAT: the same point
    assert wrapped == pytest.approx([200 / 255, 100 / 255, 50 / 255])
    frame = render_frame([quad], camera, pose)
    np.testing.assert_array_equal(rgba[0, 0], [*expected, 255])
    assert np.abs(frame.rgba.astype(int) - rgba.astype(int)).max() <= 1
