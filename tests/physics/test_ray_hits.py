"""Ray casts report every surface a ray crosses: all stage triangles, one hit per convex."""

from __future__ import annotations

import numpy as np
import pytest

from engine.attributes import StageAttributes
from engine.geo import Ray

from .helpers import add, floor_mesh, make_world, register_primitive


def _two_floor_world():
    """A stage of two stacked floors (y = 0 and y = 1) and a 0.2 m box resting on neither."""
    world, templates = make_world(floor=False)
    world.set_stage([floor_mesh(5.0), floor_mesh(5.0, height=1.0)], StageAttributes())
    box = add(world, templates, register_primitive(templates), [2.0, 0.5, 2.0])
    return world, box


def test_a_ray_down_through_two_floors_hits_both():
    world, _ = _two_floor_world()
    hits = world.cast_ray(Ray([0.5, 3.0, -0.2], [0.0, -1.0, 0.0])).hits
    assert [h.object_id for h in hits] == [0, 0]
    np.testing.assert_allclose([h.ray_distance for h in hits], [2.0, 3.0], atol=1e-12)
    np.testing.assert_allclose([list(h.normal) for h in hits], [[0, 1, 0], [0, 1, 0]], atol=1e-12)


def test_a_ray_through_a_shared_edge_counts_one_crossing():
    world, _ = _two_floor_world()
    # x = z lies on the diagonal both triangles of each floor share
    hits = world.cast_ray(Ray([0.3, 3.0, 0.3], [0.0, -1.0, 0.0])).hits
    np.testing.assert_allclose([h.ray_distance for h in hits], [2.0, 3.0], atol=1e-12)


def test_a_convex_body_reports_only_its_entry_and_max_distance_cuts():
    world, box = _two_floor_world()
    hits = world.cast_ray(Ray([2.0, 3.0, 2.0], [0.0, -1.0, 0.0])).hits
    # upper floor at 2.0, box top face at 2.4 (its bottom face is not reported), floor 3.0
    assert [h.object_id for h in hits] == [0, box.object_id, 0]
    np.testing.assert_allclose([h.ray_distance for h in hits], [2.0, 2.4, 3.0], atol=1e-9)
    short = world.cast_ray(Ray([2.0, 3.0, 2.0], [0.0, -1.0, 0.0]), max_distance=2.5).hits
    assert [h.ray_distance for h in short] == pytest.approx([2.0, 2.4])
