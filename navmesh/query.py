"""NavGrid: point queries on a built navmesh -- locate, snap, walk a segment, local searches.

The navigable region is the union of the squares of navigable nodes (see
``navmesh.navmesh_data`` for the grid conventions: Y up, cells ``[layer, iz, ix]``, node =
(layer * nz + iz) * nx + ix). Its boundary is made of cell sides without a link.

``nearest_node`` follows Detour's ``findNearestPoly`` as Habitat calls it: candidates are
nodes within a box of half extents (2 m, 4 m, 2 m) around the query point; a node whose
square contains the point scores ``max(|dy| - max_climb, 0)^2``, any other node the squared
3D distance to its square. The best node and the closest point on it are returned.

Tables built on first use, for queries that would otherwise search: ``clearance`` (lower
bounds of the distance to a wall), ``single_layer`` (the only square of each cell, stacked
cells counted) and ``island_range`` (the islands within a window of cells).
"""

from __future__ import annotations

import functools
import heapq
import math

import numpy as np
from scipy.ndimage import maximum_filter, minimum_filter

from navmesh.layers import neighbour_node_ids
from navmesh.navmesh_data import NavMeshData
from navmesh.settings import INSIDE_EPS, SNAP_HALF_EXTENTS


class NavGrid:
    """Read-only query structure over a ``NavMeshData``.

    Attributes
    ----------
    floor : (N,) float64
        Surface height of every node (NaN for missing layers), meters.
    island : (N,) int32
        Island index of every node, -1 when not navigable.
    neighbours : (8, N) int64
        Side (rows 0-3, ``DIRECTIONS``) and diagonal (rows 4-7) neighbour node ids, -1 none.
    """

    def __init__(self, data: NavMeshData):
        self.data = data
        self.n_layers, self.nz, self.nx = data.shape
        self.n_cells = self.nz * self.nx
        self.cell_size = float(data.cell_size)
        self.x0, self.z0 = (float(v) for v in data.origin_xz)
        self.max_climb = float(data.settings.agent_max_climb)
        self.floor = data.floor.reshape(-1)
        self.island = data.island.reshape(-1)
        self.navigable = data.navigable.reshape(-1)
        self.neighbours = neighbour_node_ids(data.links)
        self.n_islands = int(self.island.max(initial=-1)) + 1
        self._reach = math.ceil(SNAP_HALF_EXTENTS[0] / self.cell_size) + 1  # cells
        box_half = math.ceil(SNAP_HALF_EXTENTS[0] / self.cell_size)
        self._island_ranges: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        # nearest_node's windows: 3 and 10 cells around the point, then the whole snap box
        self._windows: list[tuple[int | None, tuple[np.ndarray, np.ndarray]]] = [
            (half, _window_offsets(half, self.nx, self.nz)) for half in (3, 10) if half < box_half
        ] + [(None, _window_offsets(box_half, self.nx, self.nz))]

    @functools.cached_property
    def clearance(self) -> np.ndarray:
        """(N,) lower bounds of the square centres' distances to the boundary (computed on
        first use; see :func:`clearance_lower_bounds`)."""
        return clearance_lower_bounds(self)

    @functools.cached_property
    def single_layer(self) -> tuple[np.ndarray, np.ndarray]:
        """``(cell_node (n_cells,), stacked_sum (nz + 1, nx + 1))`` for single-layer shortcuts.

        A square a search may visit is navigable or linked. ``cell_node[cell]`` is the only such
        node of the cell (-1: none, -2: stacked, i.e. several layers); ``stacked_sum`` is the
        summed-area table of the stacked cells, so a window of cells is free of them when
        ``S[z1, x1] - S[z0, x1] - S[z1, x0] + S[z0, x0] == 0`` (computed on first use).
        """
        used = (self.navigable | np.any(self.neighbours[:4] >= 0, axis=0)).reshape(
            self.n_layers, self.n_cells
        )
        count = used.sum(axis=0)
        first = np.argmax(used, axis=0) * self.n_cells + np.arange(self.n_cells)
        cell_node = np.where(count == 1, first, np.where(count == 0, -1, -2))
        stacked = (count > 1).reshape(self.nz, self.nx).astype(np.int64)
        stacked_sum = np.zeros((self.nz + 1, self.nx + 1), dtype=np.int64)
        stacked_sum[1:, 1:] = stacked.cumsum(axis=0).cumsum(axis=1)
        return cell_node, stacked_sum

    def island_range(self, half: int) -> tuple[np.ndarray, np.ndarray]:
        """``(lowest, highest)`` island index ``(nz, nx)`` of the navigable nodes in the window
        of ``half`` cells around each cell (``n_islands`` / -1 where there are none).

        Where both equal one island, every navigable square of the window is on it (a
        min/max filter over the grid, computed once per ``half``).
        """
        if half not in self._island_ranges:
            island = self.island.reshape(self.n_layers, self.nz, self.nx)
            low = np.where(island >= 0, island, self.n_islands).min(axis=0)
            size = 2 * half + 1
            self._island_ranges[half] = (
                minimum_filter(low, size=size, mode="constant", cval=self.n_islands),
                maximum_filter(island.max(axis=0), size=size, mode="constant", cval=-1),
            )
        return self._island_ranges[half]

    # -- cells and nodes ---------------------------------------------------------------------
    def cell_of(self, x: float, z: float) -> tuple[int, int]:
        """(ix, iz) of the cell containing world (x, z); may lie outside the grid.

        Far points are clamped to a cell just beyond the snap window around the grid (so
        ``1e300`` gives a far outside cell, never an overflow); no query looks further.
        """
        u = (x - self.x0) / self.cell_size  # may be inf for |x| near the float limit
        v = (z - self.z0) / self.cell_size
        reach = self._reach
        if -reach < u < self.nx + reach and -reach < v < self.nz + reach:
            return math.floor(u), math.floor(v)
        return (
            math.floor(min(max(u, -reach), self.nx + reach)),
            math.floor(min(max(v, -reach), self.nz + reach)),
        )

    def node_cell(self, node: int) -> tuple[int, int]:
        """(ix, iz) of a node."""
        iz, ix = divmod(node % self.n_cells, self.nx)
        return ix, iz

    def node_center(self, node: int) -> np.ndarray:
        """(3,) world position of the centre of a node's square at its surface height."""
        ix, iz = self.node_cell(node)
        return np.array(
            [
                self.x0 + (ix + 0.5) * self.cell_size,
                self.floor[node],
                self.z0 + (iz + 0.5) * self.cell_size,
            ]
        )

    def clamp_into_cell(self, node: int, x: float, z: float) -> tuple[float, float]:
        """Closest point to (x, z) inside the node's square (pulled INSIDE_EPS inwards)."""
        ix, iz = self.node_cell(node)
        lo_x, lo_z = self.x0 + ix * self.cell_size, self.z0 + iz * self.cell_size
        eps = min(INSIDE_EPS, 0.25 * self.cell_size)
        cx = min(max(x, lo_x + eps), lo_x + self.cell_size - eps)
        cz = min(max(z, lo_z + eps), lo_z + self.cell_size - eps)
        return cx, cz

    def nodes_at(self, ix: int, iz: int) -> list[int]:
        """Navigable nodes of cell (ix, iz), bottom layer first (empty outside the grid)."""
        if not (0 <= ix < self.nx and 0 <= iz < self.nz):
            return []
        cell = iz * self.nx + ix
        return [
            cell + layer * self.n_cells
            for layer in range(self.n_layers)
            if self.navigable[cell + layer * self.n_cells]
        ]

    # -- nearest node (Detour's findNearestPoly) -----------------------------------------------
    def nearest_node(self, point, island_index: int = -1) -> tuple[int, np.ndarray | None]:
        """Return ``(node, snapped (3,))`` of the best node near ``point`` or ``(-1, None)``."""
        x, y, z = (float(v) for v in point)
        ix, iz = self.cell_of(x, z)
        best, best_score = -1, math.inf
        for node in self.nodes_at(ix, iz):  # fast path: a surface right under the point
            if island_index >= 0 and self.island[node] != island_index:
                continue
            dy = abs(self.floor[node] - y)
            score = max(dy - self.max_climb, 0.0) ** 2
            if dy <= SNAP_HALF_EXTENTS[1] and score < best_score:
                best, best_score = node, score
        if best >= 0 and best_score == 0.0:
            return best, np.array([x, self.floor[best], z])
        return self._nearest_in_window(x, y, z, ix, iz, island_index)

    def _nearest_in_window(self, x, y, z, ix, iz, island_index):
        """Vectorized search of the nodes in the snap box around (x, y, z), nearest first.

        Growing windows of ``half`` cells around the point's cell are searched in turn; every
        square outside a window is at least ``half * cell_size`` away, so a best score below
        ``(half * cell_size)^2`` is the snap box's answer too (the same node, ties included:
        each window lists its squares in the snap box's order).
        """
        u, v = (x - self.x0) / self.cell_size, (z - self.z0) / self.cell_size
        inside_cell = (
            math.isfinite(u) and math.isfinite(v) and (math.floor(u), math.floor(v)) == (ix, iz)
        )
        for half, window in self._windows:
            found = self._best_in_window(window, x, y, z, ix, iz, island_index)
            if found is None:
                continue
            node, score = found
            if half is None or (inside_cell and score < (half * self.cell_size) ** 2):
                own = self.node_cell(node) == (ix, iz)
                sx, sz = (x, z) if own else self.clamp_into_cell(node, x, z)
                return node, np.array([sx, self.floor[node], sz])
        return -1, None

    def _best_in_window(self, window, x, y, z, ix, iz, island_index):
        """(node, score) of the best square among the window's cells, or None."""
        cs = self.cell_size
        d_ix, d_iz = window
        cx, cz = ix + d_ix, iz + d_iz
        inside = (cx >= 0) & (cx < self.nx) & (cz >= 0) & (cz < self.nz)
        cx, cz = cx[inside], cz[inside]
        nodes = (np.arange(self.n_layers)[:, None] * self.n_cells + (cz * self.nx + cx)).ravel()
        cx, cz = np.tile(cx, self.n_layers), np.tile(cz, self.n_layers)
        floor = self.floor[nodes]
        ok = self.navigable[nodes] & (np.abs(floor - y) <= SNAP_HALF_EXTENTS[1])
        if island_index >= 0:
            ok &= self.island[nodes] == island_index
        if not np.any(ok):
            return None
        nodes, cx, cz, floor = nodes[ok], cx[ok], cz[ok], floor[ok]
        # closest point of each square: clamp (x, z) into [lo, lo + cs]
        px = np.clip(x, self.x0 + cx * cs, self.x0 + (cx + 1) * cs)
        pz = np.clip(z, self.z0 + cz * cs, self.z0 + (cz + 1) * cs)
        own = (cx == ix) & (cz == iz)
        # score = max(|dy| - climb, 0)^2 over the own cell, else |p - closest|^2
        score = np.where(
            own,
            np.maximum(np.abs(floor - y) - self.max_climb, 0.0) ** 2,
            (px - x) ** 2 + (pz - z) ** 2 + (floor - y) ** 2,
        )
        k = int(np.argmin(score))
        return int(nodes[k]), float(score[k])

    # -- walking a straight segment (grid traversal, Amanatides & Woo 1987) --------------------
    def walk_segment(self, node: int, p0, p1) -> tuple[int, float, bool]:
        """Follow the XZ segment p0 -> p1 from ``node`` (whose cell contains p0) across links.

        Returns ``(last_node, t, reached)``: ``reached`` when the cell of p1 is entered, else
        ``t`` in [0, 1] is the segment parameter where it leaves the navigable region.
        Corners crossed exactly need the diagonal link (both L-routes open).
        """
        x, z = float(p0[0]), float(p0[-1])
        dx, dz = float(p1[0]) - x, float(p1[-1]) - z
        ix, iz = self.node_cell(node)
        end_ix, end_iz = self.cell_of(float(p1[0]), float(p1[-1]))
        t_max_x, t_step_x, side_x = self._axis_setup(x - self.x0, dx, ix, 0)
        t_max_z, t_step_z, side_z = self._axis_setup(z - self.z0, dz, iz, 2)
        step_x, step_z = (1 if dx > 0 else -1), (1 if dz > 0 else -1)
        diagonal_row = 4 + 2 * (side_x == 1) + (side_z == 3)
        link = self.neighbours.item  # plain-int reads: this loop runs per cell crossed
        for _ in range(abs(end_ix - ix) + abs(end_iz - iz) + 2):
            if ix == end_ix and iz == end_iz:
                return node, 1.0, True
            tie = -1e-12 < t_max_x - t_max_z < 1e-12
            if tie:
                row, t = diagonal_row, t_max_x
            elif t_max_x < t_max_z:
                row, t = side_x, t_max_x
            else:
                row, t = side_z, t_max_z
            if t > 1.0:  # p1 lies on a cell side: the end cell is the current one
                return node, 1.0, True
            nxt = link(row, node)
            if nxt < 0:
                return node, t, False
            node = nxt
            if tie or row == side_x:
                ix, t_max_x = ix + step_x, t_max_x + t_step_x
            if tie or row == side_z:
                iz, t_max_z = iz + step_z, t_max_z + t_step_z
        return node, 1.0, True

    def _axis_setup(self, offset: float, delta: float, index: int, side_pos: int):
        """t of the first side crossing, t per cell and the side row along one axis."""
        if delta == 0.0:
            return math.inf, math.inf, side_pos
        cs = self.cell_size
        if delta > 0:
            return ((index + 1) * cs - offset) / delta, cs / delta, side_pos
        return (index * cs - offset) / delta, -cs / delta, side_pos + 1

    def line_of_sight(self, node: int, p0, p1, target: int = -1) -> bool:
        """True when the straight XZ segment p0 -> p1 stays on the navmesh from ``node``
        (and, when ``target >= 0``, arrives on that node, not on another floor)."""
        last, _, reached = self.walk_segment(node, p0, p1)
        if not reached or target < 0 or last == target:
            return reached
        # p1 on a side shared by two linked squares may be "reached" in the neighbour
        return bool(np.any(self.neighbours[:, last] == target))

    # -- local searches ------------------------------------------------------------------------
    def nodes_near(self, start: int, center, radius: float) -> list[int]:
        """Nodes connected to ``start`` through squares that intersect the XZ disk
        (center, radius), in best-first order of their distance to the centre."""
        return [node for node, _ in self.expand_best_first(start, center, radius)]

    def _square_distance(self, node: int, cx: float, cz: float) -> float:
        iz, ix = divmod(node % self.n_cells, self.nx)
        lo_x, lo_z = self.x0 + ix * self.cell_size, self.z0 + iz * self.cell_size
        ddx = max(lo_x - cx, 0.0, cx - lo_x - self.cell_size)
        ddz = max(lo_z - cz, 0.0, cz - lo_z - self.cell_size)
        return math.hypot(ddx, ddz)

    def expand_best_first(self, start: int, center, radius: float):
        """Best-first flood over side links inside a disk; yields (node, distance)."""
        cx, cz = float(center[0]), float(center[-1])
        heap = [(self._square_distance(start, cx, cz), start)]
        seen = {start}
        link = self.neighbours.item  # plain-int reads: this loop runs per query
        while heap:
            dist, node = heapq.heappop(heap)
            yield node, dist
            for row in range(4):
                nxt = link(row, node)
                if nxt < 0 or nxt in seen:
                    continue
                seen.add(nxt)
                d = self._square_distance(nxt, cx, cz)
                if d <= radius:
                    heapq.heappush(heap, (d, nxt))

    def boundary_sides(self, node: int):
        """Yield the XZ end points ``(ax, az, bx, bz)`` of each side of ``node`` without a link."""
        ix, iz = self.node_cell(node)
        cs = self.cell_size
        lo_x, lo_z = self.x0 + ix * cs, self.z0 + iz * cs
        hi_x, hi_z = lo_x + cs, lo_z + cs
        sides = (
            (hi_x, lo_z, hi_x, hi_z),
            (lo_x, lo_z, lo_x, hi_z),
            (lo_x, hi_z, hi_x, hi_z),
            (lo_x, lo_z, hi_x, lo_z),
        )  # +X, -X, +Z, -Z
        link = self.neighbours.item
        for row in range(4):
            if link(row, node) < 0:
                yield sides[row]


def clearance_lower_bounds(grid: NavGrid, max_levels: int = 64) -> np.ndarray:
    """(N,) a lower bound of each square centre's distance to the navmesh boundary, meters.

    A square is *interior* at level 0 when its four sides are linked, and at level k when it
    and its 8 linked neighbours are interior at level k - 1. Every side of the
    ``(2k + 1) x (2k + 1)`` block around a level-k square is then linked, so the nearest
    boundary side is at least ``(k + 1/2) cell_size`` from its centre (0 for squares with a
    boundary side of their own). ``closest_boundary_point`` uses it to answer "no wall within
    the radius" without a search: a point ``p`` on square ``n`` is at least
    ``bound[n] - |p - c_n|`` from every wall.
    """
    links = grid.neighbours
    interior = grid.navigable & np.all(links[:4] >= 0, axis=0)
    bound = np.where(interior, 0.5 * grid.cell_size, 0.0)
    for level in range(1, max_levels):
        # a missing neighbour (-1) reads the sentinel slot, which is never interior
        padded = np.append(interior, False)
        interior = interior & np.all(padded[links], axis=0)
        if not interior.any():
            break
        bound[interior] = (level + 0.5) * grid.cell_size
    return bound


def _window_offsets(half_cells: int, nx: int, nz: int) -> tuple[np.ndarray, np.ndarray]:
    """Cell offsets (d_ix, d_iz) of the square snap window, clipped to the grid size."""
    hx, hz = min(half_cells, nx), min(half_cells, nz)
    d_iz, d_ix = np.mgrid[-hz : hz + 1, -hx : hx + 1]
    return d_ix.ravel(), d_iz.ravel()
