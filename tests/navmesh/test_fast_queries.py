"""The navmesh shortcuts the greedy follower relies on give their references' answers.

* ``walls_within`` (one vectorized pass over the unlinked sides near many points) answers as
  ``has_wall_within`` (best-first flood) on a flat room and where layers are stacked (the
  flood is used there), and finds walls at all;
* ``step_from`` skips the end snap when the island window proves the island: the step's result
  is still the contract's (start when the end snaps to another island), and the skip is
  sound wherever it is taken (two floors 0.15 m apart);
* ``GeodesicField.distance_at`` of a snapped point is ``distance`` of the point, and the
  interpolation is the formula ``min_m |p - c_m| + D[m]`` over the square and its neighbours.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navmesh.proximity import has_wall_within, walls_within
from navmesh.step_filter import _end_snaps_to_island, step_from, try_step


def random_snapped_points(pathfinder, count: int, seed: int):
    grid = pathfinder.nav_grid
    pathfinder.seed(seed)
    nodes, points = [], []
    for _ in range(count):
        node, snapped = grid.nearest_node(pathfinder.get_random_navigable_point())
        nodes.append(node)
        points.append(snapped)
    return np.array(nodes), np.array(points)


@pytest.mark.parametrize("radius", [0.05, 0.2, 0.45])
def test_walls_within_answers_as_the_flood_on_a_flat_room(simple_room, radius):
    grid = simple_room.nav_grid
    nodes, points = random_snapped_points(simple_room, 400, seed=4)
    fast = walls_within(grid, nodes, points, radius)
    reference = [
        has_wall_within(grid, int(n), p, radius) for n, p in zip(nodes, points, strict=True)
    ]
    assert fast.tolist() == reference
    assert 0 < fast.sum() < len(fast)  # both answers occur


def stacked_floors(geometry):
    """A floor with a 2 m high deck over part of it: stacked layers near the deck."""
    return geometry.build(
        geometry.box([0, -0.1, 0], [4, 0, 4]),
        geometry.box([1, 1.9, 1], [3, 2.0, 3]),
        geometry.box([0.9, -0.1, 0.9], [1.0, 2.0, 1.0]),  # a post holding the deck
    )


def test_walls_within_answers_as_the_flood_where_layers_are_stacked(geometry):
    pathfinder = stacked_floors(geometry)
    grid = pathfinder.nav_grid
    assert grid.n_layers == 2
    nodes, points = random_snapped_points(pathfinder, 400, seed=1)
    cell_node, stacked_sum = grid.single_layer
    assert stacked_sum[-1, -1] > 0  # some cells hold two squares: the flood answers there
    fast = walls_within(grid, nodes, points, 0.3)
    reference = [has_wall_within(grid, int(n), p, 0.3) for n, p in zip(nodes, points, strict=True)]
    assert fast.tolist() == reference
    assert 0 < fast.sum() < len(fast)


def test_walls_within_of_no_points_is_empty(simple_room):
    grid = simple_room.nav_grid
    assert walls_within(grid, np.zeros(0, int), np.zeros((0, 3)), 0.2).shape == (0,)


def two_floors_apart(geometry):
    """Two floors with a 0.15 m gap: their islands are 0.35 m apart after erosion."""
    return geometry.build(
        geometry.box([0, -0.1, 0], [2, 0, 2]), geometry.box([2.15, -0.1, 0], [4, 0, 2])
    )


@pytest.mark.parametrize("length", [0.25, 0.4])
def test_steps_skip_the_end_snap_only_when_its_island_is_sure(geometry, length):
    pathfinder = two_floors_apart(geometry)
    grid = pathfinder.nav_grid
    assert pathfinder.num_islands == 2
    rng = np.random.default_rng(3)
    pathfinder.seed(3)
    skipped = other_island = 0
    for _ in range(600):
        start = pathfinder.get_random_navigable_point()
        angle = rng.uniform(0, 2 * math.pi)
        end = start + length * np.array([math.cos(angle), 0.0, math.sin(angle)])
        start_node, start_pt = grid.nearest_node(start)
        end_node, _ = grid.nearest_node(end)
        same = end_node >= 0 and grid.island[end_node] == grid.island[start_node]
        if _end_snaps_to_island(grid, start_node, end):
            skipped += 1
            assert same  # the skip is sound
        other_island += not same
        result = step_from(grid, start, start_node, start_pt, end, True)
        assert np.array_equal(result, try_step(grid, start, end, True))
        if not same:
            assert np.array_equal(result, start)  # the contract: another island -> start
    assert skipped > 300 and other_island > 0


def test_distance_at_is_the_interpolation_formula(simple_room):
    grid = simple_room.nav_grid
    simple_room.seed(8)
    field = simple_room.geodesic_field(simple_room.get_random_navigable_point())
    nodes, points = random_snapped_points(simple_room, 300, seed=6)
    around_checked = 0
    for node, point in zip(nodes, points, strict=True):
        value = field.distance_at(int(node), point)
        assert value == field.distance(point)
        goal = field.goal
        if grid.line_of_sight(int(node), point[[0, 2]], goal[[0, 2]], field.goal_node):
            assert value == pytest.approx(np.linalg.norm(goal - point), rel=1e-12)
            continue
        around = [int(node)] + [int(m) for m in grid.neighbours[:, node] if m >= 0]
        expected = min(
            np.linalg.norm(grid.node_center(m) - point) + field.node_distance[m] for m in around
        )
        assert value == pytest.approx(expected, rel=1e-12)
        around_checked += 1
    assert around_checked > 0
