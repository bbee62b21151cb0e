"""Proximity queries of the navmesh: nearest wall, walls near many points, island radii, disks.

Helpers of ``PathFinder`` that look at many nodes at once. ``has_wall_within`` is the
reference wall test (a best-first flood); ``walls_within`` answers it for many points in one
vectorized pass where no layers are stacked. Grid conventions are in
``navmesh.navmesh_data`` (Y up, meters, node = (layer * nz + iz) * nx + ix); every square
is ``cell_size`` wide and the navigable region is the union of the navigable squares.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from navmesh.query import NavGrid


def closest_boundary_point(grid: NavGrid, node: int, point: np.ndarray, max_radius: float):
    """Closest navmesh boundary point to ``point`` (on ``node``) within ``max_radius``.

    Detour's ``findDistanceToWall`` on squares: the squares connected to ``node`` (through side
    links) that meet the disk of radius ``max_radius`` around the point are searched for the
    boundary side nearest to it. Returns ``(hit_pos (3,), hit_normal (3,), distance)`` with the
    normal the unit XZ vector from the wall to the point, or None when no boundary lies within
    ``max_radius``. The search (:func:`nearest_wall_best_first`) is skipped where the square's
    clearance bound already rules out a wall within the radius (``NavGrid.clearance``): the
    answer is the same, None, without visiting a square.
    """
    centre_gap = math.hypot(*(grid.node_center(node)[[0, 2]] - point[[0, 2]]))
    if grid.clearance[node] - centre_gap >= max_radius:
        return None  # no boundary side can lie within the radius (see clearance_lower_bounds)
    found = nearest_wall_best_first(grid, node, float(point[0]), float(point[2]), max_radius)
    if found is None:
        return None
    (hx, hy, hz), best_dist = found
    hit = np.array([hx, hy, hz])
    normal = np.array([point[0] - hit[0], 0.0, point[2] - hit[2]])
    norm = np.linalg.norm(normal)
    return hit, (normal / norm if norm > 0 else normal), best_dist


def nearest_wall_best_first(grid: NavGrid, node: int, px: float, pz: float, max_radius: float):
    """Visit squares best-first by distance, stop once the next one is farther than the best
    wall; return ``((x, y, z) of the hit, distance)`` or None."""
    best_dist, best_hit = max_radius, None
    for near, square_dist in grid.expand_best_first(node, (px, pz), best_dist):
        if square_dist >= best_dist:
            break
        for side in grid.boundary_sides(near):
            dist, hx, hz = _point_segment(px, pz, *side)
            if dist < best_dist:
                best_dist, best_hit = dist, (hx, grid.floor[near], hz)
    return None if best_hit is None else (best_hit, best_dist)


def has_wall_within(grid: NavGrid, node: int, point: np.ndarray, radius: float) -> bool:
    """Whether a boundary side lies closer than ``radius`` to ``point`` (on ``node``).

    The same squares as :func:`closest_boundary_point`, visited in the same best-first order,
    but the search stops at the first wall closer than ``radius``: the answer equals
    ``closest_boundary_point(...)[2] < radius`` (None counting as no), at a fraction of the
    cost next to walls.
    """
    px, pz = float(point[0]), float(point[2])
    centre_gap = math.hypot(*(grid.node_center(node)[[0, 2]] - point[[0, 2]]))
    if grid.clearance[node] - centre_gap >= radius:
        return False
    for near, square_dist in grid.expand_best_first(node, (px, pz), radius):
        if square_dist >= radius:
            return False
        for side in grid.boundary_sides(near):
            if _point_segment(px, pz, *side)[0] < radius:
                return True
    return False


def walls_within(grid: NavGrid, nodes: np.ndarray, points: np.ndarray, radius: float) -> np.ndarray:
    """``has_wall_within`` for many points at once: ``(K,) bool``, a boundary side closer than
    ``radius`` to ``points[k]`` (on ``nodes[k]``); :func:`has_wall_within` is the reference.

    Where every cell of the window of ``ceil(radius / cell_size) + 1`` cells around a point's
    square holds at most one square (no stacked layers, ``NavGrid.single_layer``), the search
    needs no flood: the nearest boundary side of *any* square of the window is at the distance
    the flood finds. (The segment from the point to that side's closest point stays inside
    the disk; if it left the squares connected to the start it would first cross an unlinked
    side of a connected square, which is no farther.) Those points are answered with one
    vectorized pass over the window's unlinked sides; the others (stacked windows) by the
    best-first search. Distances are compared with ``< radius``, as the reference.
    """
    nodes = np.asarray(nodes, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    near = np.zeros(nodes.size, dtype=bool)
    flat: list[int] = []
    for k, (node, point) in enumerate(zip(nodes.tolist(), points, strict=True)):
        kind = _window_kind(grid, node, float(point[0]), float(point[2]), radius)
        if kind == "stacked":  # stacked layers nearby: the reference search
            near[k] = has_wall_within(grid, node, point, radius)
        elif kind == "flat":
            flat.append(k)
    if flat:
        near[flat] = _flat_walls_within(grid, nodes[flat], points[flat], radius)
    return near


def _window_kind(grid: NavGrid, node: int, px: float, pz: float, radius: float) -> str:
    """ "open" when the clearance bound rules out a wall (as in :func:`has_wall_within`), else
    "stacked" when the window of the point's square holds stacked layers, else "flat"."""
    cs = grid.cell_size
    iz, ix = divmod(node % grid.n_cells, grid.nx)
    gap = math.hypot(grid.x0 + (ix + 0.5) * cs - px, grid.z0 + (iz + 0.5) * cs - pz)
    if grid.clearance.item(node) - gap >= radius:
        return "open"
    reach = math.ceil(radius / cs) + 1
    total = grid.single_layer[1]  # summed-area table of the stacked cells
    z0, z1 = max(iz - reach, 0), min(iz + reach + 1, grid.nz)
    x0, x1 = max(ix - reach, 0), min(ix + reach + 1, grid.nx)
    stacked = total[z1, x1] - total[z0, x1] - total[z1, x0] + total[z0, x0]
    return "stacked" if stacked else "flat"


def _flat_walls_within(grid, nodes, points, radius) -> np.ndarray:
    """Whether an unlinked side of a window square lies closer than ``radius`` (vectorized)."""
    cs, cell_node = grid.cell_size, grid.single_layer[0]
    iz, ix = np.divmod(nodes % grid.n_cells, grid.nx)
    d_ix, d_iz = _window(math.ceil(radius / cs) + 1)
    cx, cz = ix[:, None] + d_ix, iz[:, None] + d_iz  # (K, W) window cells
    inside = (cx >= 0) & (cx < grid.nx) & (cz >= 0) & (cz < grid.nz)
    cells = np.clip(cz, 0, grid.nz - 1) * grid.nx + np.clip(cx, 0, grid.nx - 1)
    square = np.where(inside, cell_node[cells], -1)
    unlinked = (grid.neighbours[:4, np.maximum(square, 0)] < 0) & (square >= 0)  # (4, K, W)
    side, k, w = np.nonzero(unlinked)
    px, pz = points[k, 0], points[k, 2]
    lo_x, lo_z = grid.x0 + cx[k, w] * cs, grid.z0 + cz[k, w] * cs
    # closest point of each side: the side's fixed coordinate, the other one clamped
    fixed_x = np.where(side == 0, lo_x + cs, lo_x)  # sides 0 / 1: x = hi / lo, z free
    fixed_z = np.where(side == 2, lo_z + cs, lo_z)  # sides 2 / 3: z = hi / lo, x free
    along_z = side < 2
    qx = np.where(along_z, fixed_x, np.clip(px, lo_x, lo_x + cs))
    qz = np.where(along_z, np.clip(pz, lo_z, lo_z + cs), fixed_z)
    near = np.zeros(ix.size, dtype=bool)
    near[k[np.hypot(qx - px, qz - pz) < radius]] = True
    return near


@functools.cache
def _window(reach: int) -> tuple[np.ndarray, np.ndarray]:
    """Offsets ``(d_ix, d_iz)`` of the cells within ``reach`` cells (a square window)."""
    d_iz, d_ix = np.mgrid[-reach : reach + 1, -reach : reach + 1]
    return d_ix.ravel(), d_iz.ravel()


def _point_segment(px, pz, ax, az, bx, bz):
    """Distance from (px, pz) to segment a-b and the closest point (XZ plane)."""
    ex, ez = bx - ax, bz - az
    # t = clamp(((p - a) . e) / |e|^2, 0, 1), closest = a + t e
    t = min(max(((px - ax) * ex + (pz - az) * ez) / (ex * ex + ez * ez), 0.0), 1.0)
    hx, hz = ax + t * ex, az + t * ez
    return math.hypot(px - hx, pz - hz), hx, hz


def island_radii(grid: NavGrid) -> np.ndarray:
    """(n_islands,) max distance of cell centres from the island centroid, meters."""
    nodes = np.flatnonzero(grid.island >= 0)
    label = grid.island[nodes]
    iz, ix = np.divmod(nodes % grid.n_cells, grid.nx)
    centers = np.stack(
        [
            grid.x0 + (ix + 0.5) * grid.cell_size,
            grid.floor[nodes],
            grid.z0 + (iz + 0.5) * grid.cell_size,
        ],
        axis=1,
    )
    count = np.bincount(label, minlength=grid.n_islands)[:, None]
    centroid = np.stack(
        [np.bincount(label, weights=centers[:, k], minlength=grid.n_islands) for k in range(3)],
        axis=1,
    ) / np.maximum(count, 1)
    dist = np.linalg.norm(centers - centroid[label], axis=1)
    radius = np.zeros(grid.n_islands)
    np.maximum.at(radius, label, dist)
    return radius


def nodes_in_disk(grid: NavGrid, center: np.ndarray, radius: float, island: int) -> np.ndarray:
    """Nodes of ``island`` whose square centre lies within ``radius`` (XZ) of ``center``."""
    cs = grid.cell_size
    lo_x = max(0, math.floor((center[0] - radius - grid.x0) / cs))
    hi_x = min(grid.nx, math.ceil((center[0] + radius - grid.x0) / cs) + 1)
    lo_z = max(0, math.floor((center[2] - radius - grid.z0) / cs))
    hi_z = min(grid.nz, math.ceil((center[2] + radius - grid.z0) / cs) + 1)
    iz, ix = np.mgrid[lo_z:hi_z, lo_x:hi_x]
    cells = (iz * grid.nx + ix).ravel()
    nodes = (np.arange(grid.n_layers)[:, None] * grid.n_cells + cells).ravel()
    # |c - center|_xz <= radius for the cell centre c
    dx = grid.x0 + (np.tile(ix.ravel(), grid.n_layers) + 0.5) * cs - center[0]
    dz = grid.z0 + (np.tile(iz.ravel(), grid.n_layers) + 0.5) * cs - center[2]
    inside = (dx * dx + dz * dz <= radius * radius) & (grid.island[nodes] == island)
    return nodes[inside]
