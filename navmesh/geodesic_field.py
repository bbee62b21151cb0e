"""The geodesic distance to one goal from everywhere on the navmesh, computed once per goal.

A follower that asks "how far is the goal from here?" for every candidate action would pay a
whole path search each time (``PathFinder.find_path``: Dijkstra from the start, then string
pulling). Turning the search around answers every such question from one search:

1. **One Dijkstra from the goal** over the grid graph (``navmesh.search.GridGraph``: nodes are
   the navigable squares, edges join side and diagonal neighbours with the 3D distance between
   square centres) gives ``D[n]``, the grid distance from the centre of node ``n`` to the goal
   point, for every node of the goal's island (``scipy.sparse.csgraph.dijkstra``, compiled).
2. **A point ``p``** snaps to its node ``n`` (``NavGrid.nearest_node``). When the straight
   segment ``p -> goal`` stays on the navmesh the distance is exact, ``|p - goal|``; otherwise::

       d(p) = min over m in {n and its 8 neighbours} of ( |p - c_m| + D[m] )

   (``c_m`` the centre of square ``m``), a first-order interpolation of the field at ``p``.
   Unreachable (off the mesh, another island): ``inf``.

Accuracy: the 8-connected grid metric overestimates a free-space distance by at most
``sqrt(4 - 2 sqrt(2)) ~ 8.2 %`` (a path at 22.5 degrees to the grid); the line-of-sight rule makes
the last straight leg exact, and only paths that bend round corners carry that bias. The
difference of ``d`` between two points one step apart, which is what a greedy follower scores,
is within a few percent of the true geodesic difference. ``PathFinder.find_path`` remains the
exact (string-pulled) answer; this field is for the many-queries-per-goal case.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.sparse.csgraph import dijkstra

from navmesh.query import NavGrid
from navmesh.search import GridGraph


class GeodesicField:
    """Distances to ``goal`` from every node (``D``), and ``distance(point)`` for any point."""

    def __init__(self, grid: NavGrid, graph: GridGraph, goal: ArrayLike) -> None:
        self.grid = grid
        self.graph = graph
        goal_point = np.asarray(goal, dtype=np.float64)
        self.goal_node, snapped = grid.nearest_node(goal_point)
        self.goal: np.ndarray | None = snapped
        # D[n]: grid distance from the centre of node n to the snapped goal (inf: unreachable)
        self.node_distance = np.full(grid.navigable.size, math.inf)
        if snapped is None:
            return
        compact = dijkstra(graph.matrix, indices=int(graph.compact[self.goal_node]))
        offset = float(np.linalg.norm(grid.node_center(self.goal_node) - snapped))
        self.node_distance[graph.nodes] = compact + offset

    def distance(self, point: ArrayLike) -> float:
        """Geodesic distance from ``point`` to the goal (see the module for the rule), meters."""
        if self.goal is None:
            return math.inf
        node, snapped = self.grid.nearest_node(np.asarray(point, dtype=np.float64))
        return self.distance_at(node, snapped)

    def distance_at(self, node: int, snapped: np.ndarray | None) -> float:
        """:meth:`distance` of a point already snapped: ``grid.nearest_node(point)``."""
        if self.goal is None or snapped is None or not math.isfinite(self.node_distance[node]):
            return math.inf
        grid, goal = self.grid, self.goal
        sx, sy, sz = (float(v) for v in snapped)
        gx, gy, gz = (float(v) for v in goal)
        if grid.line_of_sight(node, (sx, sz), (gx, gz), self.goal_node):
            return math.hypot(gx - sx, gy - sy, gz - sz)
        # min over m in {node and its 8 neighbours} of |p - c_m| + D[m] (plain floats: 9 terms)
        best, cs, link = math.inf, grid.cell_size, grid.neighbours.item
        for m in [node] + [link(row, node) for row in range(8)]:
            if m < 0:
                continue
            iz, ix = divmod(m % grid.n_cells, grid.nx)
            cx, cz = grid.x0 + (ix + 0.5) * cs, grid.z0 + (iz + 0.5) * cs
            through = math.hypot(cx - sx, grid.floor.item(m) - sy, cz - sz)
            best = min(best, through + self.node_distance.item(m))
        return best
