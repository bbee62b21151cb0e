"""The vectorized rasterizer agrees with the textbook scalar one (render.reference)."""

from __future__ import annotations

import numpy as np
import pytest

from render.camera import Camera
from render.frame import RenderMesh, render_frame
from render.reference import reference_depth_and_ids


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


def test_centers_on_a_steep_shared_edge_are_drawn_exactly_once():
    # screen points (px, py): the shared edge P (0.5, 0.5) -> Q (2.5, 6.5) passes through
    # the pixel centers (0.5, 0.5), (1.5, 3.5), (2.5, 6.5); R (3, 3.5) lies right of it, close
    # to it, L (0.5, 6.5) left of it. The top-left rule gives the centers to the triangle on
    # their right (P Q is its left edge): drawn exactly once, none dropped.
    camera = Camera((8, 8), subtype="orthographic", ortho_scale=1 / 8)  # 1 px per unit

    def world(px, py):  # x = px - W / 2, y = H / 2 - py at 1 px per unit
        return [px - 4.0, 4.0 - py, -1.0]

    p, q, r, l = world(0.5, 0.5), world(2.5, 6.5), world(3.0, 3.5), world(0.5, 6.5)
    right = RenderMesh(np.array([p, q, r]), np.array([[0, 1, 2]]), semantic_id=1)
    left = RenderMesh(np.array([p, l, q]), np.array([[0, 1, 2]]), semantic_id=2)
    depth, ids = reference_depth_and_ids([right, left], camera, np.eye(4))
    counts = [(reference_depth_and_ids([m], camera, np.eye(4))[0] > 0).sum() for m in (right, left)]
    assert (depth > 0).sum() == sum(counts)  # no center drawn twice
    assert ids[3, 1] == 1  # the center (1.5, 3.5) on the edge belongs to the right triangle
    np.testing.assert_array_equal(render_frame([right, left], camera, np.eye(4)).ids, ids)
