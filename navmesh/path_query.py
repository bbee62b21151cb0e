"""PathFinder.find_path's search: snap the ends, order them, the shortest path to each.

For a start and one or more ends (Habitat's ``MultiGoalShortestPath``):

1. Snap every point (``NavGrid.nearest_node``); ends off the mesh or on another island than
   the start are unreachable.
2. Visit the reachable ends by straight-line distance from the start, a lower bound of the
   geodesic, and skip an end that cannot beat the best path so far (Habitat's multi-goal
   pruning).
3. For each end: the straight segment when it stays on the navmesh
   (``NavGrid.line_of_sight``), else the shortest path over the navmesh's visibility graph,
   searched from the end (``navmesh.geodesic_field``: the path bends only at the navmesh's
   reflex corners, ``navmesh.visibility``). The follower's distance field answers with the
   same search, so a path's length and the field's distance are one number.
"""

from __future__ import annotations

import math

import numpy as np

from navmesh.geodesic_field import GeodesicField
from navmesh.query import NavGrid
from navmesh.visibility import CornerGraph


def path_length(points: list[np.ndarray]) -> float:
    """Sum of the 3D lengths of the segments of a polyline (Habitat's ``pathLength``)."""
    if len(points) < 2:
        return 0.0
    return float(np.sum(np.linalg.norm(np.diff(np.asarray(points), axis=0), axis=1)))


def best_path(
    grid: NavGrid, corners: CornerGraph, start: np.ndarray, ends: list[np.ndarray]
) -> tuple[int, list[np.ndarray]]:
    """(index of the closest reachable end, its waypoints) or (-1, [])."""
    start_node, start_pt = grid.nearest_node(start)
    if start_pt is None:  # start is off the navmesh (start_node == -1)
        return -1, []
    goals: list[tuple[int, int, np.ndarray]] = []  # (end index, node, snapped end)
    for k, end in enumerate(ends):
        node, pt = grid.nearest_node(end)
        if pt is not None and grid.island[node] == grid.island[start_node]:
            goals.append((k, node, pt))
    if not goals:
        return -1, []
    goals.sort(key=lambda goal: (float(np.linalg.norm(goal[2] - start_pt)), goal[0]))
    best: tuple[int, list[np.ndarray], float] = (-1, [], math.inf)
    for k, node, pt in goals:
        if np.linalg.norm(pt - start_pt) >= best[2]:
            continue
        points = single_path(grid, corners, start_node, start_pt, node, pt)
        length = path_length(points)
        if points and length < best[2]:
            best = (k, points, length)
    return best[0], best[1]


def single_path(
    grid: NavGrid,
    corners: CornerGraph,
    start_node: int,
    start_pt: np.ndarray,
    end_node: int,
    end_pt: np.ndarray,
) -> list[np.ndarray]:
    """Waypoints from start_pt to end_pt (same island): straight when in line of sight,
    else the shortest path over the visibility graph."""
    if np.allclose(start_pt, end_pt):
        return [start_pt.copy(), end_pt.copy()]
    if grid.line_of_sight(start_node, start_pt[[0, 2]], end_pt[[0, 2]], end_node):
        return [start_pt.copy(), end_pt.copy()]
    return GeodesicField(grid, corners, end_pt).path_from(start_pt)
