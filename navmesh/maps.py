"""Top-down maps of the navmesh: which island lies under each pixel of an XZ raster.

``PathFinder.get_topdown_view`` / ``get_topdown_island_view`` (Habitat's names): pixel
``(h, w)`` is the world point ``(x_min + w * mpp, height, z_min + h * mpp)`` over the bounds of
the mesh the navmesh was built from; it holds the island of the navigable surface within
``eps`` meters of ``height`` there (the closest such surface when several layers qualify),
-1 where there is none. This is ``PathFinder.is_navigable`` evaluated over the image at once.
The arguments are checked first and the image size is bounded (``MAX_TOPDOWN_PIXELS``).
"""

from __future__ import annotations

import math

import numpy as np

from navmesh.query import NavGrid
from navmesh.settings import MAX_TOPDOWN_PIXELS, check_budget


def check_topdown_arguments(meters_per_pixel: object, height: object, eps: object) -> None:
    """Raise ValueError / TypeError naming the bad argument of a top-down view."""
    if not (
        isinstance(meters_per_pixel, (int, float))
        and not isinstance(meters_per_pixel, bool)
        and math.isfinite(meters_per_pixel)
        and meters_per_pixel > 0
    ):
        raise ValueError(f"meters_per_pixel must be finite and > 0, got {meters_per_pixel!r}")
    if isinstance(height, bool) or not isinstance(height, (int, float, np.integer, np.floating)):
        raise TypeError(f"height must be a number, got {height!r}")
    if not math.isfinite(height):
        raise ValueError(f"height must be finite, got {height!r}")
    if not (isinstance(eps, (int, float, np.integer, np.floating)) and eps >= 0):
        raise ValueError(f"eps must be a number >= 0, got {eps!r}")


def topdown_island_view(
    grid: NavGrid, bounds: np.ndarray, meters_per_pixel: float, height: float, eps: float
) -> np.ndarray:
    """``(z pixels, x pixels) int32`` island map over ``bounds`` (checked arguments)."""
    span = bounds[1] - bounds[0]
    # (z span / mpp) x (x span / mpp) pixels, in floats so that no int can overflow
    pixels = float(span[0] / meters_per_pixel) * float(span[2] / meters_per_pixel)
    check_budget(
        pixels,
        MAX_TOPDOWN_PIXELS,
        "MAX_TOPDOWN_PIXELS",
        f"a top-down view at {meters_per_pixel} m per pixel",
    )
    return topdown_islands(grid, bounds, float(meters_per_pixel), float(height), float(eps))


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
