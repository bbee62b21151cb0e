"""The navmesh's corners and the visibility graph between them, for exact geodesic distances.

The navigable region is a union of grid squares (``navmesh.navmesh_data``), so it is a polygon
(with holes, on several layers) whose sides are cell sides. A shortest path in a polygon is a
polyline that bends only at *reflex corners*: the lattice points where the walkable region
wraps 270 degrees around a blocked square (Lee & Preparata 1984; de Berg et al.,
*Computational Geometry*, ch. 15, "visibility graphs"). On the grid such a corner belongs to the
node whose two side neighbours of one quadrant are linked while the diagonal square between
them is not (``NavGrid.neighbours``: rows 0-3 sides, rows 4-7 diagonals, ``DIAGONAL_SIDES``).

* **Corner points.** The corner of node ``n`` toward quadrant ``(sx, sz)`` (signs +1 / -1) is
  the lattice point pulled ``INSIDE_EPS`` into ``n`` (as ``NavGrid.clamp_into_cell`` does, so a
  segment to it never passes exactly through the lattice point), at ``n``'s surface height.
* **Taut edges.** A path through corner ``c`` (blocked square in direction ``(sx, sz)``) can be
  shortest only if the straight line through ``c`` along the path's direction ``d`` does not
  cut into the blocked square: not ``sx dx > 0 and sz dz > 0`` (the line would go on into it)
  and not ``sx dx < 0 and sz dz < 0`` (it would come out of it). Otherwise moving the bend into
  the free side shortens the path. :func:`taut_at` tests it for many directions at once.
* **Visibility.** Two points see each other when the straight XZ segment between them stays
  on the navmesh (``NavGrid.line_of_sight``, a grid walk). :class:`CornerGraph` holds, for each
  corner, the corners it sees through taut edges, with the 3D lengths ``|c_i - c_j|``; the rows
  are computed when first asked for and kept for every later goal on the same navmesh.

Reference: T. Lozano-Perez & M. Wesley (1979), "An algorithm for planning collision-free paths
among polyhedral obstacles" (the visibility graph); its reduced (tangent) form as in
H. Rohnert (1986), "Shortest paths in the plane with convex polygonal obstacles".
"""

from __future__ import annotations

import numpy as np

from navmesh.layers import DIAGONAL_SIDES
from navmesh.query import NavGrid
from navmesh.settings import INSIDE_EPS

#: square meters: products of coordinate differences this small count as zero (rounding)
ROUNDING_SLACK = 1e-12


def find_corners(grid: NavGrid) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(nodes (C,), points (C, 3), quadrant (C, 2))`` of every reflex corner.

    ``quadrant`` holds the signs ``(sx, sz)`` pointing from the corner to its blocked square.
    """
    nodes_list, sx_list, sz_list = [], [], []
    sides = grid.neighbours
    for k, (side_1, side_2) in enumerate(DIAGONAL_SIDES):
        has_corner = grid.navigable & (sides[side_1] >= 0) & (sides[side_2] >= 0)
        has_corner &= sides[4 + k] < 0
        found = np.flatnonzero(has_corner)
        nodes_list.append(found)
        # DIRECTIONS: side 0 is +X, side 1 is -X, side 2 is +Z, side 3 is -Z
        sx_list.append(np.full(found.size, 1.0 if side_1 == 0 else -1.0))
        sz_list.append(np.full(found.size, 1.0 if side_2 == 2 else -1.0))
    nodes = np.concatenate(nodes_list)
    quadrant = np.stack([np.concatenate(sx_list), np.concatenate(sz_list)], axis=1)
    order = np.lexsort((quadrant[:, 1], quadrant[:, 0], nodes))  # deterministic: by node
    nodes, quadrant = nodes[order], quadrant[order]
    iz, ix = np.divmod(nodes % grid.n_cells, grid.nx)
    cs = grid.cell_size
    inset = 0.5 * cs - min(INSIDE_EPS, 0.25 * cs)  # centre -> corner, pulled inside
    points = np.stack(
        [
            grid.x0 + (ix + 0.5) * cs + quadrant[:, 0] * inset,
            grid.floor[nodes],
            grid.z0 + (iz + 0.5) * cs + quadrant[:, 1] * inset,
        ],
        axis=1,
    )
    return nodes, points, quadrant


def taut_at(quadrant: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Whether lines along ``direction (K, 2 or 3)`` (x, [y,] z) through corners with
    blocked quadrants ``quadrant (K, 2)`` stay out of the blocked squares (see the module).

    A line along a wall (a point slid along it lies ``INSIDE_EPS`` off it, as the corner does)
    has one component zero up to rounding: ``ROUNDING_SLACK`` keeps it. The test only prunes
    edges no shortest path uses, so a looser one is still exact.
    """
    along_x = quadrant[:, 0] * direction[:, 0]
    along_z = quadrant[:, 1] * direction[:, -1]
    return along_x * along_z <= ROUNDING_SLACK


class CornerGraph:
    """The navmesh's reflex corners and their taut visibility edges (rows built on demand)."""

    def __init__(self, grid: NavGrid) -> None:
        self.grid = grid
        self.nodes, self.points, self.quadrant = find_corners(grid)
        self.island = grid.island[self.nodes] if self.nodes.size else np.zeros(0, np.int32)
        self._rows: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    @property
    def size(self) -> int:
        """Number of corners."""
        return int(self.nodes.size)

    def visible_from(
        self, node: int, point: np.ndarray, candidates: np.ndarray | None = None
    ) -> np.ndarray:
        """Indices of the corners (among ``candidates``, default all of ``node``'s island) that
        ``point`` on ``node`` sees through an edge taut at the corner."""
        if candidates is None:
            candidates = np.flatnonzero(self.island == self.grid.island[node])
        direction = self.points[candidates] - point
        keep = candidates[taut_at(self.quadrant[candidates], direction)]
        sight = self.grid.line_of_sight
        xz = (float(point[0]), float(point[2]))
        return np.array(
            [
                c
                for c in keep.tolist()
                if sight(node, xz, (self.points[c, 0], self.points[c, 2]), int(self.nodes[c]))
            ],
            dtype=np.int64,
        )

    def row(self, corner: int) -> tuple[np.ndarray, np.ndarray]:
        """``(neighbours (k,), lengths (k,))``: the corners ``corner`` sees through edges taut
        at both ends, and the 3D edge lengths (computed once per corner and navmesh)."""
        found = self._rows.get(corner)
        if found is not None:
            return found
        point, quadrant = self.points[corner], self.quadrant[corner : corner + 1]
        others = np.flatnonzero(self.island == self.island[corner])
        others = others[others != corner]
        direction = self.points[others] - point
        others = others[taut_at(np.repeat(quadrant, others.size, axis=0), direction)]
        neighbours = self.visible_from(int(self.nodes[corner]), point, others)
        lengths = np.linalg.norm(self.points[neighbours] - point, axis=1)
        self._rows[corner] = (neighbours, lengths)
        return neighbours, lengths
