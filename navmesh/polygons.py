"""The navmesh as a polygon mesh: navigable squares merged into rectangles, two triangles each.

Habitat's ``build_navmesh_vertices`` / ``build_navmesh_vertex_indices`` return Recast's
polygons as triangles: a few hundred to a few thousand vertices for a house. The grid navmesh
has one square per navigable cell (tens of thousands in an apartment), so the squares are
merged first, in two sweeps per layer (a greedy rectangle cover, as Recast's region merging
grows polygons):

1. **Runs**: along each grid row, consecutive squares of the same layer, island and surface
   height form a run ``[ix0, ix1)``.
2. **Rectangles**: a run continues the rectangle above it when the row before has a run with
   the same ``(ix0, ix1, layer, island, height)``; otherwise it starts a new rectangle.

Every rectangle becomes 4 corner vertices ``(x0, z0), (x1, z0), (x1, z1), (x0, z1)`` at its
height and two triangles counter-clockwise seen from above (+Y normals). The triangles cover
exactly the union of the navigable squares (same area, same islands); only squares of equal
height merge, so sloped floors stay as narrow strips.
"""

from __future__ import annotations

import numpy as np

from navmesh.query import NavGrid

#: two triangles of one rectangle over its corners (x0,z0), (x1,z0), (x1,z1), (x0,z1): +Y normals
RECTANGLE_TRIANGLES = np.array([0, 2, 1, 0, 3, 2])


def row_runs(grid: NavGrid, mask: np.ndarray) -> np.ndarray:
    """Step 1: ``(R, 6)`` runs ``(layer, iz, ix0, ix1, island, node)`` of equal squares.

    ``mask`` (N,) selects the squares; a run breaks where the mask, the island or the surface
    height changes along a row. ``node`` is the run's first node (for its height).
    """
    shape = (grid.n_layers, grid.nz, grid.nx)
    island = np.where(mask, grid.island, -1).reshape(shape)
    floor = np.where(mask, grid.floor, np.nan).reshape(shape)
    same = (island[..., 1:] == island[..., :-1]) & (floor[..., 1:] == floor[..., :-1])
    starts = (island >= 0) & np.concatenate([np.ones(shape[:2] + (1,), bool), ~same], axis=2)
    layer, iz, ix0 = np.nonzero(starts)
    # a run ends where the next run starts, or at the first square outside the mask
    ends = np.nonzero(
        np.concatenate([~same | (island[..., 1:] < 0), np.ones(shape[:2] + (1,), bool)], axis=2)
        & (island >= 0)
    )[2]
    node = (layer * grid.nz + iz) * grid.nx + ix0
    return np.stack([layer, iz, ix0, ends + 1, grid.island[node], node], axis=1)


def merge_runs(grid: NavGrid, runs: np.ndarray) -> np.ndarray:
    """Step 2: ``(K, 5)`` rectangles ``(ix0, ix1, iz0, iz1, node)`` from row runs."""
    open_rectangles: dict[tuple, list[int]] = {}  # (layer, ix0, ix1, island, height) -> rect
    rectangles: list[list[int]] = []
    for layer, iz, ix0, ix1, island, node in runs.tolist():
        key = (layer, ix0, ix1, island, float(grid.floor[node]))
        rect = open_rectangles.get(key)
        if rect is not None and rect[3] == iz:  # the run right below continues it
            rect[3] = iz + 1
            continue
        rect = [ix0, ix1, iz, iz + 1, node]
        open_rectangles[key] = rect
        rectangles.append(rect)
    return np.array(rectangles, dtype=np.int64).reshape(-1, 5)


def navmesh_polygons(grid: NavGrid, island_index: int = -1) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices (4K, 3), indices (6K,))`` of the merged navmesh of one island (-1: all)."""
    mask = grid.island >= 0 if island_index < 0 else grid.island == island_index
    rectangles = merge_runs(grid, row_runs(grid, mask))
    ix0, ix1, iz0, iz1, node = rectangles.T
    x0, x1 = grid.x0 + ix0 * grid.cell_size, grid.x0 + ix1 * grid.cell_size
    z0, z1 = grid.z0 + iz0 * grid.cell_size, grid.z0 + iz1 * grid.cell_size
    y = grid.floor[node]
    corners = np.stack(
        [
            np.stack([x0, y, z0], 1),
            np.stack([x1, y, z0], 1),
            np.stack([x1, y, z1], 1),
            np.stack([x0, y, z1], 1),
        ],
        axis=1,
    ).reshape(-1, 3)
    indices = (np.arange(len(rectangles))[:, None] * 4 + RECTANGLE_TRIANGLES).reshape(-1)
    return corners, indices
