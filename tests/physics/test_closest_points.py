"""Closest point on a triangle (the sphere-against-mesh contact's geometry): the plane
projection inside the triangle's prism, else the nearest point of its edges; checked against
hand geometry and against a dense sampling of the triangle."""

from __future__ import annotations

import numpy as np
import pytest

from engine.physics.collision.collide import closest_points_on_triangles

# a right triangle in the plane y = 1: legs 2 m along +x and 1 m along +z
TRI = np.array([[[0.0, 1.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 1.0]]])


@pytest.mark.parametrize(
    "point, expected",
    [
        ((0.5, 3.0, 0.25), (0.5, 1.0, 0.25)),  # above the inside: straight down
        ((0.5, -2.0, 0.25), (0.5, 1.0, 0.25)),  # below the inside: straight up
        ((1.0, 1.5, -1.0), (1.0, 1.0, 0.0)),  # beyond the x leg: its point with that x
        ((-1.0, 1.0, 0.5), (0.0, 1.0, 0.5)),  # beyond the z leg
        ((-1.0, 0.0, -1.0), (0.0, 1.0, 0.0)),  # beyond the right-angle corner: the corner
        ((3.0, 1.0, -0.5), (2.0, 1.0, 0.0)),  # beyond the far corner on x
        ((0.0, 1.0, 3.0), (0.0, 1.0, 1.0)),  # beyond the far corner on z
        # beyond the hypotenuse x + 2 z = 2: the foot of the perpendicular
        ((2.0, 1.0, 1.0), (1.6, 1.0, 0.2)),
    ],
)
def test_closest_point_matches_hand_geometry(point, expected):
    closest = closest_points_on_triangles(TRI, np.array(point))
    np.testing.assert_allclose(closest, [expected], atol=1e-12)


def test_closest_points_beat_a_dense_sampling_of_each_triangle():
    rng = np.random.default_rng(26)
    tris = rng.normal(size=(40, 3, 3))
    # barycentric grid (u, v, 1 - u - v), 1/60 spacing
    u, v = np.meshgrid(np.linspace(0, 1, 61), np.linspace(0, 1, 61))
    keep = u + v <= 1.0
    bary = np.stack([1.0 - u[keep] - v[keep], u[keep], v[keep]], axis=1)  # (s, 3)
    for point in rng.normal(scale=2.0, size=(5, 3)):
        closest = closest_points_on_triangles(tris, point)
        samples = np.einsum("sk,tkd->tsd", bary, tris)  # (t, s, 3) points on each triangle
        sampled = np.linalg.norm(samples - point, axis=2).min(axis=1)
        exact = np.linalg.norm(closest - point, axis=1)
        assert np.all(exact <= sampled + 1e-12)  # never farther than any point of it
        # and on the triangle: the sampled minimum is at most one grid step farther
        edge = np.linalg.norm(tris - np.roll(tris, 1, axis=1), axis=2).max(axis=1)
        assert np.all(sampled - exact <= edge / 60.0 + 1e-12)
