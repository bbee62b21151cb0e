"""Proximity queries of the navmesh: nearest wall, island radii, disks of nodes, top-down maps.

Helpers of ``PathFinder`` that look at many nodes at once. Grid conventions are in
``navmesh.navmesh_data`` (Y up, meters, node = (layer * nz + iz) * nx + ix); every square
is ``cell_size`` wide and the navigable region is the union of the navigable squares.
"""

from __future__ import annotations

import math

import numpy as np

from navmesh.query import NavGrid


def closest_boundary_point(grid: NavGrid, node: int, point: np.ndarray, max_radius: float):
    """Closest navmesh boundary point to ``point`` (on ``node``) within ``max_radius``.

    Detour's ``findDistanceToWall`` on squares: squares connected to ``node`` are visited
    best-first by their distance to the point and the search stops once the next square is
    farther than the best wall found. Returns ``(hit_pos (3,), hit_normal (3,), distance)``
    with the normal the unit XZ vector from the wall to the point, or None when no boundary
    lies within ``max_radius``.
    """
    best_dist, best_hit = max_radius, None
    for near, square_dist in grid.expand_best_first(node, (point[0], point[2]), best_dist):
        if square_dist >= best_dist:
            break
        for side in grid.boundary_sides(near):
            dist, hx, hz = _point_segment(point[0], point[2], *side)
            if dist < best_dist:
                best_dist, best_hit = dist, (hx, grid.floor[near], hz)
    if best_hit is None:
        return None
    hit = np.array(best_hit)
    normal = np.array([point[0] - hit[0], 0.0, point[2] - hit[2]])
    norm = np.linalg.norm(normal)
    return hit, (normal / norm if norm > 0 else normal), best_dist


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


def topdown_islands(grid: NavGrid, bounds, mpp: float, height: float, eps: float):
    """Island index at each top-down pixel (vectorized ``is_navigable`` over the image)."""
    x_min, z_min = bounds[0][0], bounds[0][2]
    x_res = int((bounds[1][0] - x_min) / mpp)
    z_res = int((bounds[1][2] - z_min) / mpp)
    xs = x_min + np.arange(x_res) * mpp
    zs = z_min + np.arange(z_res) * mpp
    ix = np.floor((xs - grid.x0) / grid.cell_size).astype(np.int64)
    iz = np.floor((zs - grid.z0) / grid.cell_size).astype(np.int64)
    ok_x, ok_z = (ix >= 0) & (ix < grid.nx), (iz >= 0) & (iz < grid.nz)
    cells = np.clip(iz, 0, grid.nz - 1)[:, None] * grid.nx + np.clip(ix, 0, grid.nx - 1)[None]
    result = np.full((z_res, x_res), -1, dtype=np.int32)
    best_dy = np.full((z_res, x_res), np.inf)
    for layer in range(grid.n_layers):
        node = cells + layer * grid.n_cells
        dy = np.abs(grid.floor[node] - height)
        better = (grid.island[node] >= 0) & (dy <= eps) & (dy < best_dy)
        result = np.where(better, grid.island[node], result)
        best_dy = np.where(better, dy, best_dy)
    result[~(ok_z[:, None] & ok_x[None])] = -1
    return result
