"""The navmesh shortcuts the greedy follower relies on give their references' answers.

* ``walls_within`` (one vectorized pass over the unlinked sides near many points) answers as
  ``has_wall_within`` (best-first flood) on a flat room and where layers are stacked (the
  flood is used there), and finds walls at all;
* ``step_from`` skips the end snap when the island window proves the island: the step's result
  is still the contract's (start when the end snaps to another island), and the skip is
  sound wherever it is taken (two floors 0.15 m apart);
* ``GeodesicField.distance_at`` of a snapped point is ``distance`` of the point and the
  brute-force shortest path over the whole visibility graph (every corner, every visible
  pair, no pruning); with ``at_most`` it is exact below the bound, a lower bound above.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from navmesh.proximity import has_wall_within, walls_within
from navmesh.step_filter import _end_snaps_to_island, step_from, try_step
from navmesh.visibility import find_corners


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


def brute_force_distances(grid, goal_node, goal):
    """Exact distances to ``goal`` with no shortcut: every corner, every pair of corners seen
    through the grid walk (no taut-edge pruning), Dijkstra over the full visibility graph."""
    nodes, points, _ = find_corners(grid)
    count = len(nodes)
    weights = np.zeros((count + 1, count + 1))  # index count: the goal

    def sees(a_node, a, b_node, b):
        return grid.line_of_sight(int(a_node), a[[0, 2]], b[[0, 2]], int(b_node))

    for i in range(count):
        if sees(goal_node, goal, nodes[i], points[i]):
            weights[count, i] = weights[i, count] = np.linalg.norm(points[i] - goal)
        for j in range(i + 1, count):
            if sees(nodes[i], points[i], nodes[j], points[j]):
                weights[i, j] = weights[j, i] = np.linalg.norm(points[i] - points[j])
    corner_distance = dijkstra(csr_matrix(weights), indices=count)[:count]

    def distance(node, point):
        if sees(node, point, goal_node, goal):
            return float(np.linalg.norm(goal - point))
        seen = [i for i in range(count) if sees(node, point, nodes[i], points[i])]
        return min(
            (float(np.linalg.norm(points[i] - point) + corner_distance[i]) for i in seen),
            default=math.inf,
        )

    return distance


def test_distance_at_is_the_shortest_path_over_every_visible_corner(simple_room):
    """The field's pruned, lazily settled search gives the brute-force visibility-graph
    distance (no taut pruning, every corner tried) to 1e-9 m; ``distance_at`` of a snapped
    point is ``distance``; with ``at_most`` the answer is exact below it and a lower bound
    at or above it."""
    grid = simple_room.nav_grid
    simple_room.seed(8)
    field = simple_room.geodesic_field(simple_room.get_random_navigable_point())
    reference = brute_force_distances(grid, field.goal_node, field.goal)
    nodes, points = random_snapped_points(simple_room, 120, seed=6)
    around_checked = 0
    for node, point in zip(nodes, points, strict=True):
        value = field.distance_at(int(node), point)
        assert value == field.distance(point)
        assert value == pytest.approx(reference(int(node), point), abs=1e-9)
        around_checked += not grid.line_of_sight(
            int(node), point[[0, 2]], field.goal[[0, 2]], field.goal_node
        )
        for at_most in (0.5 * value, value + 1e-6, 2.0 * value):
            fresh = simple_room.geodesic_field(field.goal)  # nothing settled yet
            bounded = fresh.distance_at(int(node), point, at_most)
            if value < at_most:
                assert bounded == pytest.approx(value, abs=1e-12)
            else:
                assert at_most <= bounded <= value + 1e-12
    assert around_checked > 20
