"""build_navmesh: the whole navmesh build as numbered stages, after Recast's ``handleBuild``.

Input: the scene's triangles in the world frame (Y up, meters) -- ``vertices (V, 3)
float64`` and ``faces (F, 3) int64`` (counter-clockwise front faces) -- and a
``NavMeshSettings``. Output: a ``NavMeshData`` layered grid (see ``navmesh.navmesh_data``).

Stages (Recast's Steps 1-4, with the polygon Steps 5-7 replaced by a grid):
 1. grid        -- cover the XZ footprint with ``cell_size`` squares.
 2. slope       -- triangles whose normal is within ``agent_max_slope`` of +Y are walkable.
 3. rasterize   -- sample triangles into columns; merge samples into solid spans.
 4. filters     -- low hanging obstacles, clearance below ``agent_height``.
 5. layers      -- span tops become surfaces, several per column (floors, stairs, decks).
 6. ledges      -- drop surfaces next to drops deeper than ``agent_max_climb``.
 7. connect     -- link neighbour surfaces within ``agent_max_climb`` with enough headroom.
 8. erode       -- shrink the walkable area by ``agent_radius`` (chamfer distance).
 9. islands     -- connected components; islands under ``region_min_size**2`` cells go.

Reference: M. Mononen, Recast (``RecastDemo/Source/Sample_SoloMesh.cpp``), and the
"Recast settings uncovered" notes; Habitat-sim ``PathFinder::Impl::build``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from navmesh import heightfield as hf
from navmesh import layers
from navmesh.navmesh_data import NavMeshData
from navmesh.settings import (
    MAX_GRID_CELLS,
    MAX_RASTER_SAMPLES,
    NavMeshSettings,
    check_budget,
)


def build_navmesh(vertices: ArrayLike, faces: ArrayLike, settings: NavMeshSettings) -> NavMeshData:
    """Build the layered navigation grid of a triangle mesh.

    Parameters
    ----------
    vertices : (V, 3) float64
        World-frame positions, Y up, meters.
    faces : (F, 3) int64
        Vertex indices of each triangle, counter-clockwise seen from the front.
    settings : NavMeshSettings
        Agent size and grid resolution.

    Raises
    ------
    ValueError / TypeError
        For malformed arrays or settings (nothing is built).
    """
    vertices, faces = check_mesh(vertices, faces)
    settings.validate()
    s = settings
    spacing = 0.5 * min(s.cell_size, s.cell_height)
    check_build_budget(vertices, faces, s.cell_size, spacing)
    # -- Step 1. Grid: square cells covering the mesh footprint ---------------------------
    grid = hf.make_grid(vertices, s.cell_size)
    # -- Step 2. Mark walkable triangles by slope ------------------------------------------
    walkable_tri = hf.mark_walkable_triangles(vertices, faces, s.agent_max_slope)
    # -- Step 3. Rasterize: triangle samples -> solid spans per column ---------------------
    column, y, walkable = hf.rasterize_triangles(vertices, faces, walkable_tri, grid, spacing)
    spans = hf.merge_samples_into_spans(column, y, walkable, grid, s.cell_height, s.agent_max_climb)
    # -- Step 4. Span filters (each switchable as in Habitat) -------------------------------
    if s.filter_low_hanging_obstacles:
        hf.filter_low_hanging_obstacles(spans, s.agent_max_climb)
    if s.filter_walkable_low_height_spans:
        hf.filter_walkable_low_height_spans(spans, s.agent_height)
    # -- Step 5. Walkable surfaces -> dense layers (L, nz, nx) -----------------------------
    floor, ceiling, walkable_layer = layers.build_layers(spans, grid)
    # -- Step 6. Ledges: no standing next to a drop ----------------------------------------
    if s.filter_ledge_spans:
        walkable_layer = layers.filter_ledges(
            floor, walkable_layer, spans, grid, s.agent_height, s.agent_max_climb
        )
    # -- Step 7. Connect neighbour surfaces -------------------------------------------------
    links = layers.connect_neighbours(
        floor, ceiling, walkable_layer, s.agent_height, s.agent_max_climb
    )
    # -- Step 8. Erode by the agent radius ---------------------------------------------------
    radius_cells = math.ceil(s.agent_radius / s.cell_size - 1e-9)
    # no chamfer distance exceeds sqrt(2) x the node count: a larger radius erodes the same
    radius_cells = min(radius_cells, 2 * walkable_layer.size + 2)
    navigable = layers.erode_walkable_area(walkable_layer, links, radius_cells)
    # -- Step 9. Islands (connected components), small ones removed -----------------------
    min_cells = int(math.ceil(s.region_min_size**2))
    navigable, links, island = layers.label_islands(
        navigable, layers.restrict_links(links, navigable), min_cells
    )
    bounds = np.stack([vertices.min(axis=0), vertices.max(axis=0)])
    return NavMeshData(
        settings=NavMeshSettings(**vars(settings)),
        bounds=bounds,
        origin_xz=grid.origin_xz,
        cell_size=grid.cell_size,
        floor=floor,
        ceiling=ceiling,
        navigable=navigable,
        links=links,
        island=island,
    )


def check_build_budget(
    vertices: np.ndarray, faces: np.ndarray, cell_size: float, spacing: float
) -> None:
    """Refuse, before allocating anything, a build whose grid or rasterization would exceed
    ``MAX_GRID_CELLS`` / ``MAX_RASTER_SAMPLES`` (ValueError naming the budget)."""
    extent = vertices.max(axis=0) - vertices.min(axis=0)
    # cells = ceil(x extent / cs) * ceil(z extent / cs), in floats (no int overflow)
    cells = max(1.0, np.ceil(extent[0] / cell_size)) * max(1.0, np.ceil(extent[2] / cell_size))
    check_budget(
        cells,
        MAX_GRID_CELLS,
        "MAX_GRID_CELLS",
        f"a navmesh grid of cell_size {cell_size} over {extent[0]:.3g} x {extent[2]:.3g} m",
    )
    a = vertices[faces[:, 0]]
    # the rasterizer's lattice: (ceil(|ab| / s) + 1) (ceil(|ac| / s) + 1) samples per triangle
    n_u = np.maximum(1.0, np.ceil(np.linalg.norm(vertices[faces[:, 1]] - a, axis=1) / spacing))
    n_v = np.maximum(1.0, np.ceil(np.linalg.norm(vertices[faces[:, 2]] - a, axis=1) / spacing))
    check_budget(
        float(np.sum((n_u + 1.0) * (n_v + 1.0))),
        MAX_RASTER_SAMPLES,
        "MAX_RASTER_SAMPLES",
        f"rasterizing {len(faces)} triangles at a sample "
        f"spacing of {spacing:.3g} m (half of min(cell_size, cell_height))",
    )


def check_mesh(vertices: ArrayLike, faces: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Return ``vertices (V, 3) float64`` and ``faces (F, 3) int64`` or raise naming the input."""
    try:
        vertices = np.asarray(vertices, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise TypeError(f"vertices must be a (V, 3) float array, got {type(vertices)}") from err
    if vertices.ndim != 2 or vertices.shape[1] != 3 or vertices.shape[0] < 3:
        raise ValueError(f"vertices must have shape (V>=3, 3), got {vertices.shape}")
    if not np.all(np.isfinite(vertices)):
        raise ValueError("vertices contain NaN or inf")
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.shape[0] < 1:
        raise ValueError(f"faces must have shape (F>=1, 3), got {faces.shape}")
    if not np.issubdtype(faces.dtype, np.integer):
        raise TypeError(f"faces must be integers, got dtype {faces.dtype}")
    faces = faces.astype(np.int64)
    if faces.min() < 0 or faces.max() >= vertices.shape[0]:
        raise ValueError(
            f"faces index vertices out of range [0, {vertices.shape[0]}): "
            f"min {faces.min()}, max {faces.max()}"
        )
    return vertices, faces
