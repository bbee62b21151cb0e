"""PathFinder.find_path's search: snap the ends, order them, straight line or grid search.

For a start and one or more ends (Habitat's ``MultiGoalShortestPath``):

1. Snap every point (``NavGrid.nearest_node``); ends off the mesh or on another island than
   the start are unreachable.
2. Visit the reachable ends by straight-line distance from the start, a lower bound of the
   geodesic, and skip an end that cannot beat the best path so far (Habitat's multi-goal
   pruning).
3. For each end: the straight segment when it stays on the navmesh
   (``NavGrid.line_of_sight``), else Dijkstra on the grid graph and string pulling
   (``navmesh.search``).
"""

from __future__ import annotations

import math

import numpy as np

from navmesh.query import NavGrid
from navmesh.search import GridGraph, path_length, pull_string


def best_path(
    grid: NavGrid, graph: GridGraph, start: np.ndarray, ends: list[np.ndarray]
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
        points = single_path(grid, graph, start_node, start_pt, node, pt)
        length = path_length(points)
        if length < best[2]:
            best = (k, points, length)
    return best[0], best[1]


def single_path(
    grid: NavGrid,
    graph: GridGraph,
    start_node: int,
    start_pt: np.ndarray,
    end_node: int,
    end_pt: np.ndarray,
) -> list[np.ndarray]:
    """Waypoints from start_pt to end_pt (same island): straight when in line of sight,
    else Dijkstra on the grid graph then string pulling."""
    if np.allclose(start_pt, end_pt):
        return [start_pt.copy(), end_pt.copy()]
    if grid.line_of_sight(start_node, start_pt[[0, 2]], end_pt[[0, 2]], end_node):
        return [start_pt.copy(), end_pt.copy()]
    limit = 2.0 * float(np.linalg.norm(end_pt - start_pt)) + 1.0
    _, pred = graph.tree_from(start_node, [end_node], limit)
    nodes = graph.node_path(pred, start_node, end_node)
    return pull_string(grid, nodes, start_pt, end_pt)
