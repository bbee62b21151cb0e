"""The navmesh as a polygon mesh: navigable squares merged into rectangles, two triangles each.

Habitat's ``build_navmesh_vertices`` / ``build_navmesh_vertex_indices`` return Recast's
polygons as triangles: a few hundred to a few thousand vertices for a house. The grid navmesh
has one square per navigable cell (tens of thousands in an apartment), so the squares are
merged first, in two sweeps per layer (a greedy rectangle cover, as Recast's polygon merging
grows convex polygons while they stay convex):

1. **Runs**: along each grid row, consecutive squares of the same layer and island whose
   surface heights differ by at most ``MERGE_HEIGHT_TOLERANCE`` form a run ``[ix0, ix1)``.
2. **Rectangles**: a run continues the rectangle above it when the row before has a run with
   the same ``(ix0, ix1, layer, island)`` and a first square within the same tolerance in
   height; otherwise it starts a new rectangle.

Every rectangle becomes 4 corner vertices ``(x0, z0), (x1, z0), (x1, z1), (x0, z1)`` and two
triangles counter-clockwise seen from above (+Y normals); each corner takes the surface height
of the rectangle's square at that corner, so a flat floor gives a flat rectangle and a ramp a
sloped one. The triangles cover exactly the union of the navigable squares (same area, same
islands). The tolerance is what lets a rasterized floor whose heights jitter by fractions of a
millimetre (``simple_room.glb``: 41,425 distinct heights among 43,128 squares) merge at all;
stair steps (2 cm and more) keep their own rectangles.
"""

from __future__ import annotations

import numpy as np

from navmesh.query import NavGrid

#: two triangles of one rectangle over its corners (x0,z0), (x1,z0), (x1,z1), (x0,z1): +Y normals
RECTANGLE_TRIANGLES = np.array([0, 2, 1, 0, 3, 2])
#: meters: neighbouring squares whose surface heights differ by at most this may merge
MERGE_HEIGHT_TOLERANCE = 0.02


def row_runs(grid: NavGrid, mask: np.ndarray) -> np.ndarray:
    """Step 1: ``(R, 6)`` runs ``(layer, iz, ix0, ix1, island, node)`` of equal squares.

    ``mask`` (N,) selects the squares; a run breaks where the mask or the island changes
    along a row, or the surface height steps by more than ``MERGE_HEIGHT_TOLERANCE``.
    ``node`` is the run's first node (for its height).
    """
    shape = (grid.n_layers, grid.nz, grid.nx)
    island = np.where(mask, grid.island, -1).reshape(shape)
    floor = np.where(mask, grid.floor, np.nan).reshape(shape)
    step = np.abs(floor[..., 1:] - floor[..., :-1])
    same = (island[..., 1:] == island[..., :-1]) & (step <= MERGE_HEIGHT_TOLERANCE)
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
    """Step 2: ``(K, 5)`` rectangles ``(ix0, ix1, iz0, iz1, node)`` from row runs (``node``:
    the first square)."""
    open_rectangles: dict[tuple, list[int]] = {}  # (layer, ix0, ix1, island) -> rect
    rectangles: list[list[int]] = []
    floor = grid.floor
    for layer, iz, ix0, ix1, island, node in runs.tolist():
        key = (layer, ix0, ix1, island)
        rect = open_rectangles.get(key)
        # the run right below continues it when its first square is close enough in height
        if (
            rect is not None
            and rect[3] == iz
            and abs(floor[node] - floor[rect[5]]) <= MERGE_HEIGHT_TOLERANCE
        ):
            rect[3], rect[5] = iz + 1, node
            continue
        rect = [ix0, ix1, iz, iz + 1, node, node]  # ..., first run's node, last run's node
        open_rectangles[key] = rect
        rectangles.append(rect)
    return np.array(rectangles, dtype=np.int64).reshape(-1, 6)[:, :5]


def navmesh_polygons(grid: NavGrid, island_index: int = -1) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices (4K, 3), indices (6K,))`` of the merged navmesh of one island (-1: all)."""
    mask = grid.island >= 0 if island_index < 0 else grid.island == island_index
    rectangles = merge_runs(grid, row_runs(grid, mask))
    ix0, ix1, iz0, iz1, node = rectangles.T
    x0, x1 = grid.x0 + ix0 * grid.cell_size, grid.x0 + ix1 * grid.cell_size
    z0, z1 = grid.z0 + iz0 * grid.cell_size, grid.z0 + iz1 * grid.cell_size
    # each corner at the height of the rectangle's square there (node = layer * n_cells + cell)
    layer_start = node - node % grid.n_cells
    corner_squares = [(iz0, ix0), (iz0, ix1 - 1), (iz1 - 1, ix1 - 1), (iz1 - 1, ix0)]
    heights = [grid.floor[layer_start + iz * grid.nx + ix] for iz, ix in corner_squares]
    corners = np.stack(
        [
            np.stack([x0, heights[0], z0], 1),
            np.stack([x1, heights[1], z0], 1),
            np.stack([x1, heights[2], z1], 1),
            np.stack([x0, heights[3], z1], 1),
        ],
        axis=1,
    ).reshape(-1, 3)
    indices = (np.arange(len(rectangles))[:, None] * 4 + RECTANGLE_TRIANGLES).reshape(-1)
    return corners, indices
