"""The exact geodesic distance to one goal from anywhere on the navmesh, searched once per goal.

A follower that asks "how far is the goal from here?" for every candidate action would pay a
whole path search each time. Turning the search around answers every such question from one
search from the goal, over the navmesh's visibility graph (``navmesh.visibility``: its reflex
corners and the taut edges between corners that see each other):

1. **Corners from the goal** (Dijkstra, settled lazily): a corner the goal sees starts at
   ``|c - goal|``; a settled corner ``u`` offers ``D[u] + |u - v|`` to every corner ``v`` of its
   visibility row. Settling in increasing ``D`` gives ``D[c]``, the length of the shortest path
   from corner ``c`` to the goal, and ``parent[c]``, the next corner on it (-1: the goal).
   Corners are settled only as far as queries need (``_settle_until``).
2. **A point p** (snapped to its node): when the segment ``p -> goal`` stays on the navmesh the
   distance is ``|p - goal|``; otherwise the shortest path leaves ``p`` straight to a corner it
   sees, so::

       d(p) = min over corners c that p sees (taut at c) of ( |p - c| + D[c] ).

   The candidates are tried in increasing order of ``|p - c| + D[c]``; the first one ``p`` sees
   is the answer, because every other candidate is at least as long, seen or not (a corner not
   yet settled has ``D`` at least the Dijkstra frontier, so candidates are tried only up to it).
   Unreachable (off the mesh, another island): ``inf``.

The distances are those of the shortest path in the polygon the navigable squares form (3D
segment lengths, bends only at corners): ``PathFinder.find_path`` answers the same question for
one start with the same corners and visibility (``tests/navmesh/test_polygons_and_field.py``
compares them). :meth:`GeodesicField.path_from` returns the path itself. Exact answers are
kept per snapped point: a follower's next pose is one of the candidate ends it just scored.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from numpy.typing import ArrayLike

from navmesh.query import NavGrid
from navmesh.visibility import ROUNDING_SLACK, CornerGraph, taut_at

GOAL = -1  # parent of a corner whose shortest path goes straight to the goal
MAX_REMEMBERED = 100_000  # exact answers kept per field (then the memo starts again)
#: columns of the settled corners (see GeodesicField._settled_view)
_SettledView = tuple[np.ndarray, ...]


class GeodesicField:
    """Shortest-path distances to ``goal``: ``distance(point)``, ``path_from(point)``."""

    def __init__(self, grid: NavGrid, corners: CornerGraph, goal: ArrayLike) -> None:
        self.grid = grid
        self.corners = corners
        goal_point = np.asarray(goal, dtype=np.float64)
        self.goal_node, snapped = grid.nearest_node(goal_point)
        self.goal: np.ndarray | None = snapped
        #: D[c]: settled shortest-path length from corner c to the goal (inf: not settled)
        self.corner_distance = np.full(corners.size, math.inf)
        #: the next corner on c's shortest path (GOAL: straight to the goal)
        self.parent = np.full(corners.size, GOAL, dtype=np.int64)
        self._settled: list[int] = []
        #: exact answers by snapped point (node, x, y, z): see _remember
        self._answers: dict[tuple, tuple[float, int]] = {}
        self._settled_arrays: _SettledView | None = None
        # (key, corner, via): via GOAL entries still need the goal's line of sight checked
        self._heap: list[tuple[float, int, int]] = []
        if snapped is not None:
            self._seed_from_goal(snapped)

    def _seed_from_goal(self, goal: np.ndarray) -> None:
        """Every corner of the goal's island, taut toward the goal, keyed ``|c - goal|``."""
        corners = self.corners
        same_island = np.flatnonzero(corners.island == self.grid.island[self.goal_node])
        direction = corners.points[same_island] - goal
        taut = same_island[taut_at(corners.quadrant[same_island], direction)]
        lengths = np.linalg.norm(corners.points[taut] - goal, axis=1)
        self._heap = [(d, c, GOAL) for d, c in zip(lengths.tolist(), taut.tolist(), strict=True)]
        heapq.heapify(self._heap)

    @property
    def frontier(self) -> float:
        """Every corner not settled yet is at least this far from the goal."""
        return self._heap[0][0] if self._heap else math.inf

    def _settle_until(self, bound: float) -> None:
        """Settle (step 1 of the module) every corner whose distance is at most ``bound``."""
        corners, goal, grid = self.corners, self.goal, self.grid
        assert goal is not None
        while self._heap and self._heap[0][0] <= bound:
            key, corner, via = heapq.heappop(self._heap)
            if math.isfinite(self.corner_distance[corner]):
                continue
            if via == GOAL:
                target = corners.points[corner]
                if not grid.line_of_sight(
                    self.goal_node,
                    (goal[0], goal[2]),
                    (target[0], target[2]),
                    int(corners.nodes[corner]),
                ):
                    continue
            self.corner_distance[corner], self.parent[corner] = key, via
            self._settled.append(corner)
            self._settled_arrays = None
            neighbours, lengths = corners.row(corner)
            for other, length in zip(neighbours.tolist(), lengths.tolist(), strict=True):
                if not math.isfinite(self.corner_distance[other]):
                    heapq.heappush(self._heap, (key + length, other, corner))

    def _settled_view(self) -> _SettledView:
        """Columns of the settled corners: indices, x, y, z, blocked quadrant signs sx, sz,
        distances D, and the x, z of the direction to the next waypoint."""
        if self._settled_arrays is None:
            assert self.goal is not None
            index = np.array(self._settled, dtype=np.int64)
            corners = self.corners
            parent = self.parent[index]
            following = np.where(
                (parent == GOAL)[:, None], self.goal, corners.points[np.maximum(parent, 0)]
            )
            points = corners.points[index]
            onward = following - points
            quadrant = corners.quadrant[index]
            self._settled_arrays = (
                index,
                *(np.ascontiguousarray(points[:, k]) for k in range(3)),
                np.ascontiguousarray(quadrant[:, 0]),
                np.ascontiguousarray(quadrant[:, 1]),
                self.corner_distance[index],
                np.ascontiguousarray(onward[:, 0]),
                np.ascontiguousarray(onward[:, 2]),
            )
        return self._settled_arrays

    def distance(self, point: ArrayLike) -> float:
        """Geodesic distance from ``point`` to the goal (see the module), meters."""
        if self.goal is None:
            return math.inf
        node, snapped = self.grid.nearest_node(np.asarray(point, dtype=np.float64))
        return self.distance_at(node, snapped)

    def distance_at(
        self, node: int, snapped: np.ndarray | None, at_most: float = math.inf
    ) -> float:
        """:meth:`distance` of a point already snapped: ``grid.nearest_node(point)``.

        With ``at_most``: exact when the distance is below it, else some lower bound of the
        distance that is at least ``at_most`` (the search stops there: a caller that only
        needs to know "shorter than ``at_most``?" saves the line-of-sight tests).
        """
        return self._first_hop(node, snapped, at_most)[0]

    def _first_hop(
        self, node: int, snapped: np.ndarray | None, at_most: float = math.inf
    ) -> tuple[float, int]:
        """(distance, first corner of the shortest path or GOAL); (inf, GOAL) unreachable;
        (a lower bound >= at_most, GOAL) when the distance is not below ``at_most``."""
        goal, grid = self.goal, self.grid
        if goal is None or snapped is None or grid.island[node] != grid.island[self.goal_node]:
            return math.inf, GOAL
        sx, sy, sz = (float(v) for v in snapped)
        key = (node, sx, sy, sz)
        known = self._answers.get(key)
        if known is not None:
            return known
        gx, gy, gz = (float(v) for v in goal)
        straight = math.hypot(gx - sx, gy - sy, gz - sz)
        if straight >= at_most:  # every path is at least the straight line
            return straight, GOAL
        if grid.line_of_sight(node, (sx, sz), (gx, gz), self.goal_node):
            return self._remember(key, (straight, GOAL))
        return self._search_corners(node, snapped, at_most)

    def _remember(self, key: tuple, answer: tuple[float, int]) -> tuple[float, int]:
        """Keep an exact answer for the same snapped point (a follower's next pose is a
        candidate end it scored); the memo starts again beyond ``MAX_REMEMBERED``."""
        if len(self._answers) >= MAX_REMEMBERED:
            self._answers.clear()
        self._answers[key] = answer
        return answer

    def _search_corners(self, node: int, snapped: np.ndarray, at_most: float) -> tuple[float, int]:
        """Step 2 of the module for a point the goal does not see (see :meth:`_first_hop`)."""
        tried: set[int] = set()
        while True:
            frontier = self.frontier
            found, bound = self._best_settled(node, snapped, min(frontier, at_most), tried)
            if found is not None:
                return self._remember((node, *(float(v) for v in snapped)), found)
            # untried settled corners give at least `bound`, unsettled ones the frontier
            if min(bound, frontier) >= at_most:
                return min(bound, frontier), GOAL
            if not math.isfinite(frontier):
                # every corner settled and none passed the taut tests: try them all unpruned
                # (a guard against rounding; the pruned tests are only shortcuts)
                found, _ = self._best_settled(node, snapped, math.inf, set(), pruned=False)
                if found is None:
                    return math.inf, GOAL
                return self._remember((node, *(float(v) for v in snapped)), found)
            # a candidate beyond the frontier: settle up to it; none left: the next corner
            self._settle_until(max(bound, frontier) if math.isfinite(bound) else frontier)

    def _best_settled(
        self, node: int, point: np.ndarray, limit: float, tried: set[int], pruned: bool = True
    ) -> tuple[tuple[float, int] | None, float]:
        """The best settled corner ``point`` sees, if its route is no longer than ``limit``
        (the frontier, or less); else (None, the smallest value of the corners not yet
        tried, or inf)."""
        index, xs, ys, zs, sx, sz, distance, onward_x, onward_z = self._settled_view()
        if index.size == 0:
            return None, math.inf
        dx, dz = xs - float(point[0]), zs - float(point[2])
        dy = ys - float(point[1])
        values = np.sqrt(dx * dx + dy * dy + dz * dz) + distance
        if pruned:
            # p -> c -> onward must be taut at c and bend around c's blocked square (module)
            taut = (sx * dx) * (sz * dz) <= ROUNDING_SLACK
            turn = dx * onward_z - dz * onward_x
            around = dx * sz - dz * sx
            values[~(taut & (turn * around >= -ROUNDING_SLACK))] = math.inf
        # only candidates within the limit are tried; the rest bound the answer from below
        within = np.flatnonzero(values <= limit)
        order = within[np.argsort(values[within], kind="stable")].tolist()
        sight, px, pz = self.grid.line_of_sight, float(point[0]), float(point[2])
        corner_nodes = self.corners.nodes
        for k in order:
            corner = int(index[k])
            if corner in tried:
                continue
            tried.add(corner)
            target = (float(xs[k]), float(zs[k]))
            if sight(node, (px, pz), target, int(corner_nodes[corner])):
                return (float(values[k]), corner), float(values[k])
        # the smallest value beyond the limit among corners not tried (inf: none)
        untried = values > limit
        return None, float(values[untried].min()) if np.any(untried) else math.inf

    def path_from(self, point: ArrayLike) -> list[np.ndarray]:
        """Waypoints of the shortest path from (snapped) ``point`` to the goal: the point, the
        corners it bends at, the goal; ``[]`` when unreachable."""
        node, snapped = self.grid.nearest_node(np.asarray(point, dtype=np.float64))
        length, corner = self._first_hop(node, snapped)
        if not math.isfinite(length) or snapped is None or self.goal is None:
            return []
        points = [snapped.copy()]
        while corner != GOAL:
            points.append(self.corners.points[corner].copy())
            corner = int(self.parent[corner])
        points.append(self.goal.copy())
        return points
