"""try_step / try_step_no_sliding: move an agent along the navmesh surface.

This is the contract of Detour's ``dtNavMeshQuery::moveAlongSurface`` as Habitat-sim's
``PathFinder::Impl::tryStep`` uses it (``src/esp/nav/PathFinder.cpp``):

1. Project ``start`` and ``end`` onto the navmesh with the nearest-node search
   (``NavGrid.nearest_node``: a (2, 4, 2) m box). If either finds nothing, or they lie on
   different islands, return ``start`` unchanged. An ``end`` merely *off* the mesh (within the
   box) is not a failure: the agent moves toward it.
2. Sliding (``allow_sliding=True``): Detour floods the polygons connected to the start whose
   area touches the disk centred on the midpoint of start-end with radius ``|end - start| / 2``,
   and returns the point of those polygons closest to ``end``. Here the polygons are grid
   squares. If ``end`` lies in a visited square the result is ``end``; otherwise it is the
   closest point on the reached boundary, i.e. the step slides along the wall.
3. No sliding (Habitat's ``allowSliding=false``): walk the straight segment start -> end and
   stop where it first leaves the navigable region, so the direction of motion is kept.
4. The result's y is the surface height of the square it lies in.

Shortcuts for callers that step often (the greedy follower), same results: ``step_from``
takes the start already snapped, and the end is snapped only when the island check needs it
(``_end_snaps_to_island``: no search when every navigable square near the end is on the
start's island).

Positions are world-frame (Y up, meters) ``(3,) float64`` arrays.
"""

from __future__ import annotations

import math

import numpy as np

from navmesh.query import NavGrid
from navmesh.settings import INSIDE_EPS, SNAP_HALF_EXTENTS

MAX_ISLAND_WINDOW = 8  # cells: longer steps snap their end with the search


def try_step(grid: NavGrid, start, end, allow_sliding: bool) -> np.ndarray:
    """Return where an agent moving from ``start`` toward ``end`` ends on the navmesh.

    Parameters
    ----------
    grid : NavGrid
        The navmesh.
    start, end : (3,) float
        World positions, meters.
    allow_sliding : bool
        Slide along walls (``try_step``) or stop at the first wall (``try_step_no_sliding``).
    """
    start = np.array(start, dtype=np.float64)
    start_node, start_pt = grid.nearest_node(start)
    return step_from(grid, start, start_node, start_pt, np.asarray(end, np.float64), allow_sliding)


def step_from(
    grid: NavGrid,
    start: np.ndarray,
    start_node: int,
    start_pt: np.ndarray | None,
    end: np.ndarray,
    allow_sliding: bool,
) -> np.ndarray:
    """:func:`try_step` with ``start`` already snapped (``grid.nearest_node(start)``).

    A caller trying many steps from one start (the greedy follower's candidate actions)
    snaps it once; the result is the same as ``try_step``'s.
    """
    # start_pt is None exactly when start_node is -1 (start is off the navmesh)
    if start_pt is None:
        return start
    if not _end_snaps_to_island(grid, start_node, end):
        end_node, _ = grid.nearest_node(end)
        if end_node < 0 or grid.island[start_node] != grid.island[end_node]:
            return start
    node, x, z, reached = _walk_straight(grid, start_node, start_pt, end)
    if allow_sliding and not reached:
        # an unobstructed segment is also what the disk search would find (end itself),
        # so the flood runs only when the straight walk hits the boundary
        node, x, z = _slide(grid, start_node, start_pt, end)
    return np.array([x, grid.floor[node], z])


def _end_snaps_to_island(grid: NavGrid, start_node: int, end: np.ndarray) -> bool:
    """Sure without a search that ``nearest_node(end)`` finds a node on the start's island.

    The start's node is one of that search's candidates, scoring ``s`` (its squared 3D
    distance to ``end``, or the in-square height score when ``end`` lies above it); the node
    found scores no more, so its square lies within ``sqrt(s)`` of ``end`` in XZ, i.e. in the
    window of ``floor(sqrt(s) / cell_size) + 1`` cells. When every navigable square of that
    window is on the start's island (``NavGrid.island_range``), so is the node found.
    """
    x, y, z = float(end[0]), float(end[1]), float(end[2])
    ix, iz = grid.cell_of(x, z)
    if not (0 <= ix < grid.nx and 0 <= iz < grid.nz):
        return False
    start_ix, start_iz = grid.node_cell(start_node)
    dy = abs(grid.floor.item(start_node) - y)
    if dy > SNAP_HALF_EXTENTS[1]:
        return False
    if (start_ix, start_iz) == (ix, iz):
        score = max(dy - grid.max_climb, 0.0) ** 2
    else:
        cs = grid.cell_size
        lo_x, lo_z = grid.x0 + start_ix * cs, grid.z0 + start_iz * cs
        gap_x = x - min(max(x, lo_x), lo_x + cs)
        gap_z = z - min(max(z, lo_z), lo_z + cs)
        score = gap_x * gap_x + gap_z * gap_z + dy * dy
    half = math.floor(math.sqrt(score) / grid.cell_size) + 1
    if half > MAX_ISLAND_WINDOW:
        return False
    island = grid.island[start_node]
    low, high = grid.island_range(half)
    return bool(low[iz, ix] == island and high[iz, ix] == island)


def _slide(grid: NavGrid, start_node: int, start_pt: np.ndarray, end: np.ndarray):
    """Closest point to ``end`` over the squares reached inside the search disk."""
    center = 0.5 * (start_pt + end)
    # Detour: radius = |end - start| / 2 (+ 1 mm so the end point's square is inside the disk)
    radius = 0.5 * math.hypot(end[0] - start_pt[0], end[2] - start_pt[2]) + 1e-3
    best_node, best_dist_sq, best_xz = start_node, math.inf, (start_pt[0], start_pt[2])
    for node in grid.nodes_near(start_node, (center[0], center[2]), radius):
        x, z = _clamp_to_square(grid, node, end[0], end[2])
        dist_sq = (x - end[0]) ** 2 + (z - end[2]) ** 2
        if dist_sq < best_dist_sq:
            best_node, best_dist_sq, best_xz = node, dist_sq, (x, z)
            if dist_sq == 0.0:  # end lies on this square: the step is unobstructed
                break
    if best_dist_sq > 0.0:  # pull the boundary point inside so it locates on best_node
        best_xz = grid.clamp_into_cell(best_node, best_xz[0], best_xz[1])
    return best_node, best_xz[0], best_xz[1]


def _clamp_to_square(grid: NavGrid, node: int, x: float, z: float) -> tuple[float, float]:
    """Closest point to (x, z) of the node's closed square (no inward nudge)."""
    ix, iz = grid.node_cell(node)
    cs = grid.cell_size
    lo_x, lo_z = grid.x0 + ix * cs, grid.z0 + iz * cs
    return min(max(x, lo_x), lo_x + cs), min(max(z, lo_z), lo_z + cs)


def _walk_straight(grid: NavGrid, start_node: int, start_pt: np.ndarray, end: np.ndarray):
    """Follow start -> end until the segment leaves the navmesh (direction kept).

    Returns ``(node, x, z, reached)``.
    """
    p0 = (start_pt[0], start_pt[2])
    node, t, reached = grid.walk_segment(start_node, p0, (end[0], end[2]))
    if reached:
        return node, end[0], end[2], True
    length = math.hypot(end[0] - p0[0], end[2] - p0[1])
    # back off INSIDE_EPS along the segment so the point stays in the last navigable square
    t = max(0.0, t - INSIDE_EPS / length) if length > 0.0 else 0.0
    return node, p0[0] + t * (end[0] - p0[0]), p0[1] + t * (end[2] - p0[1]), False
