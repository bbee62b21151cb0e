"""Shortest paths on the layered grid: Dijkstra on the 8-connected graph, then string pulling.

1. The navigable nodes form a graph whose edges join each node to its side and diagonal
   neighbours (``NavGrid.neighbours``) with the 3D distance between square centres as
   weight. ``scipy.sparse.csgraph.dijkstra`` (compiled) finds the grid shortest path,
   bounded by a search radius that doubles until the goal is reached.
2. The grid path zig-zags (an 8-connected path can be 8 % longer than the straight line),
   so it is pulled taut: from each anchor the farthest path point in line of sight becomes
   the next waypoint (greedy string pulling, as in Botea et al. 2004 / Theta* post-smoothing),
   then each waypoint is slid to the corner of its square that shortens the path
   (the taut string touches obstacle corners), which brings the length within about 1 % of
   the true any-angle shortest path on the grid.

Points are world-frame (Y up, meters) ``(3,) float64`` arrays at the surface height.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from navmesh.query import NavGrid


class GridGraph:
    """Compressed graph of the navigable nodes for ``scipy.sparse.csgraph.dijkstra``."""

    def __init__(self, grid: NavGrid):
        self.grid = grid
        self.nodes = np.flatnonzero(grid.navigable)  # (M,) compact -> node id
        self.compact = np.full(grid.navigable.size, -1, dtype=np.int64)
        self.compact[self.nodes] = np.arange(self.nodes.size)
        centers = self.centers_of(self.nodes)
        rows, cols, weights = [], [], []
        for row in grid.neighbours:
            target = row[self.nodes]
            has = target >= 0
            src, dst = np.flatnonzero(has), self.compact[target[has]]
            # w_ij = |c_i - c_j|, the 3D distance between the two square centres
            weights.append(np.linalg.norm(centers[src] - centers[dst], axis=1))
            rows.append(src)
            cols.append(dst)
        m = self.nodes.size
        self.matrix = csr_matrix(
            (np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(m, m)
        )

    def centers_of(self, nodes: np.ndarray) -> np.ndarray:
        """(k, 3) world centres of the squares of ``nodes`` at their surface heights."""
        g = self.grid
        iz, ix = np.divmod(nodes % g.n_cells, g.nx)
        return np.stack(
            [g.x0 + (ix + 0.5) * g.cell_size, g.floor[nodes], g.z0 + (iz + 0.5) * g.cell_size],
            axis=1,
        )

    def tree_from(self, start: int, goals: list[int], limit: float):
        """Dijkstra from ``start`` until every goal is reached (radius doubling from limit).

        Returns ``(distance (M,), predecessor (M,))`` over compact indices.
        """
        source = int(self.compact[start])
        targets = self.compact[np.asarray(goals, dtype=np.int64)]
        while True:
            dist, pred = dijkstra(
                self.matrix, indices=source, return_predecessors=True, limit=limit
            )
            if np.all(np.isfinite(dist[targets])) or not np.isfinite(limit):
                return dist, pred
            limit = np.inf if limit > 1e6 else 2.0 * limit

    def node_path(self, pred: np.ndarray, start: int, goal: int) -> list[int]:
        """Node ids from start to goal following the predecessor tree."""
        path, k, source = [], int(self.compact[goal]), int(self.compact[start])
        while k != source:
            path.append(int(self.nodes[k]))
            k = int(pred[k])
        path.append(start)
        return path[::-1]


def pull_string(grid: NavGrid, nodes: list[int], start_pt, end_pt) -> list[np.ndarray]:
    """Waypoints of a taut path along the node chain ``nodes`` from start_pt to end_pt."""
    points = [np.asarray(start_pt, float)]
    points += [grid.node_center(n) for n in nodes[1:-1]]
    points.append(np.asarray(end_pt, float))
    keep = _greedy_visible(grid, nodes, points)
    way_nodes = [nodes[k] for k in keep]
    way_points = [points[k] for k in keep]
    _slide_to_corners(grid, way_nodes, way_points)
    _drop_redundant(grid, way_nodes, way_points)
    return way_points


def _drop_redundant(grid: NavGrid, nodes: list[int], points: list[np.ndarray]) -> None:
    """Remove interior waypoints whose two neighbours see each other; in place."""
    k = 1
    while k < len(points) - 1:
        if _visible(grid, nodes[k - 1], points[k - 1], points[k + 1], nodes[k + 1]):
            del nodes[k], points[k]
            k = max(1, k - 1)
        else:
            k += 1


def _visible(grid: NavGrid, node_a: int, pa, pb, node_b: int) -> bool:
    """Line of sight from point pa on node_a to point pb on node_b."""
    return grid.line_of_sight(node_a, (pa[0], pa[2]), (pb[0], pb[2]), node_b)


def _greedy_visible(grid: NavGrid, nodes: list[int], points: list[np.ndarray]) -> list[int]:
    """Indices of the kept path points: from each anchor jump to the farthest visible point,
    found by galloping (1, 2, 4, ...) then bisecting."""
    keep, anchor, last = [0], 0, len(points) - 1
    while anchor < last:
        step, good = 1, anchor + 1
        while anchor + step <= last and _visible(
            grid, nodes[anchor], points[anchor], points[anchor + step], nodes[anchor + step]
        ):
            good = anchor + step
            step *= 2
        lo, hi = good, min(anchor + step, last + 1)  # good is visible, hi is not (or past end)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if _visible(grid, nodes[anchor], points[anchor], points[mid], nodes[mid]):
                lo = mid
            else:
                hi = mid
        keep.append(lo)
        anchor = lo
    return keep


def _slide_to_corners(grid: NavGrid, nodes: list[int], points: list[np.ndarray]) -> None:
    """Move each interior waypoint to the corner of its square (pulled INSIDE_EPS in) that
    shortens the path while keeping both segments in line of sight; in place."""
    cs = grid.cell_size
    for k in range(1, len(points) - 1):
        prev_pt, next_pt = points[k - 1], points[k + 1]
        best = np.linalg.norm(points[k] - prev_pt) + np.linalg.norm(next_pt - points[k])
        center = grid.node_center(nodes[k])
        for sx in (-0.5, 0.5):
            for sz in (-0.5, 0.5):
                x, z = grid.clamp_into_cell(nodes[k], center[0] + sx * cs, center[2] + sz * cs)
                cand = np.array([x, center[1], z])
                length = np.linalg.norm(cand - prev_pt) + np.linalg.norm(next_pt - cand)
                if (
                    length < best
                    and _visible(grid, nodes[k - 1], prev_pt, cand, nodes[k])
                    and _visible(grid, nodes[k], cand, next_pt, nodes[k + 1])
                ):
                    best, points[k] = length, cand


def path_length(points: list[np.ndarray]) -> float:
    """Sum of the 3D lengths of the segments of a polyline (Habitat's ``pathLength``)."""
    if len(points) < 2:
        return 0.0
    return float(np.sum(np.linalg.norm(np.diff(np.asarray(points), axis=0), axis=1)))
