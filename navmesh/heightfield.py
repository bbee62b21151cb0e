"""Heightfield stages of the navmesh build: triangles -> solid spans per grid column.

Recast (Mononen, ``Recast/Source/RecastRasterization.cpp``, ``RecastFilter.cpp``) clips
every triangle against every cell it overlaps. rigidsim does the NumPy-friendly version:
each triangle is *sampled* on a barycentric lattice whose spacing is half the smallest cell
dimension, every sample falls into one grid column, and samples of one column closer than
``cell_height`` in y merge into one solid span ``[ymin, ymax]``. A horizontal floor becomes
a thin span, a wall a tall one; the top of a span is a candidate surface for the agent.

Inputs are world-frame arrays (Y up, meters): ``vertices (V, 3) float64``,
``faces (F, 3) int64`` (counter-clockwise seen from the front). Grid conventions are in
``navmesh.navmesh_data``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Samples generated per chunk of triangles: keeps temporaries around 100 MB at most.
_SAMPLES_PER_CHUNK = 2_000_000


@dataclass(frozen=True)
class GridSpec:
    """Placement of the XZ grid: cell (iz, ix) starts at ``origin_xz + (ix, iz) * cell_size``."""

    origin_xz: np.ndarray  # (2,) float64, world (x, z) of the grid corner, meters
    cell_size: float  # meters
    nx: int  # number of columns along +X
    nz: int  # number of rows along +Z
    y_min: float  # lowest vertex height, meters
    y_max: float  # highest vertex height, meters

    @property
    def n_cells(self) -> int:
        return self.nx * self.nz


@dataclass
class SolidSpans:
    """Solid spans of every column, sorted by (column, ymin); spans of a column are disjoint.

    ``column (K,) int64`` is the flat cell index ``iz * nx + ix``; ``ymin``, ``ymax`` are
    world heights in meters; ``walkable (K,) bool`` says whether the top of the span is a
    surface the agent may stand on (before clearance filtering).
    """

    column: np.ndarray
    ymin: np.ndarray
    ymax: np.ndarray
    walkable: np.ndarray


def make_grid(vertices: np.ndarray, cell_size: float) -> GridSpec:
    """Cover the XZ footprint of ``vertices (V, 3)`` with square cells of ``cell_size``."""
    bmin, bmax = vertices.min(axis=0), vertices.max(axis=0)
    # n = ceil(extent / cs), at least one cell, so every vertex lies inside the grid
    nx = max(1, int(np.ceil((bmax[0] - bmin[0]) / cell_size - 1e-9)))
    nz = max(1, int(np.ceil((bmax[2] - bmin[2]) / cell_size - 1e-9)))
    origin = np.array([bmin[0], bmin[2]], dtype=np.float64)
    return GridSpec(origin, float(cell_size), nx, nz, float(bmin[1]), float(bmax[1]))


def mark_walkable_triangles(
    vertices: np.ndarray, faces: np.ndarray, max_slope_deg: float
) -> np.ndarray:
    """Return ``(F,) bool``: the front face points up within ``max_slope_deg`` of +Y.

    A triangle is walkable when its unit normal n satisfies ``n_y >= cos(max_slope)``
    (Recast's ``rcMarkWalkableTriangles``); degenerate triangles are not walkable.
    """
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    normal = np.cross(b - a, c - a)  # n = (b - a) x (c - a), counter-clockwise front
    length = np.linalg.norm(normal, axis=1)
    safe = np.where(length > 0.0, length, 1.0)
    # walkable <=> n_y / |n| >= cos(slope); the epsilon keeps exactly-45-degree ramps walkable
    return (length > 0.0) & (normal[:, 1] / safe >= np.cos(np.radians(max_slope_deg)) - 1e-9)


def rasterize_triangles(
    vertices: np.ndarray,
    faces: np.ndarray,
    walkable_triangle: np.ndarray,
    grid: GridSpec,
    sample_spacing: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sample every triangle and bin the samples into grid columns.

    Returns ``(column (S,) int64, y (S,) float64, walkable (S,) bool)``: one entry per
    sample, its column index ``iz * nx + ix``, its height and its triangle's walkable flag.
    """
    a = vertices[faces[:, 0]]
    edge_ab = vertices[faces[:, 1]] - a
    edge_ac = vertices[faces[:, 2]] - a
    # n_u, n_v divisions along edges ab and ac: lattice steps at most sample_spacing long
    n_u = np.maximum(1, np.ceil(np.linalg.norm(edge_ab, axis=1) / sample_spacing))
    n_v = np.maximum(1, np.ceil(np.linalg.norm(edge_ac, axis=1) / sample_spacing))
    n_u, n_v = n_u.astype(np.int64), n_v.astype(np.int64)
    n_samples = (n_u + 1) * (n_v + 1)  # a lattice on the parallelogram, folded (see below)
    chunk_of_triangle = np.cumsum(n_samples) // _SAMPLES_PER_CHUNK
    columns, heights, flags = [], [], []
    for chunk in np.unique(chunk_of_triangle):
        tri = np.flatnonzero(chunk_of_triangle == chunk)
        col, y = _sample_triangles(a[tri], edge_ab[tri], edge_ac[tri], n_u[tri], n_v[tri], grid)
        columns.append(col)
        heights.append(y)
        flags.append(np.repeat(walkable_triangle[tri], n_samples[tri]))
    return np.concatenate(columns), np.concatenate(heights), np.concatenate(flags)


def _sample_triangles(a, edge_ab, edge_ac, n_u, n_v, grid: GridSpec):
    """Lattice samples ``p = a + u*(b-a) + v*(c-a)`` of k triangles -> (column, y).

    ``u = i / n_u``, ``v = j / n_v`` cover the parallelogram a, b, b + c - a, c; points with
    u + v > 1 are folded back onto the triangle by (u, v) -> (1 - u, 1 - v), which maps the
    lattice onto itself, so every triangle point is within one lattice step of a sample.
    """
    count = (n_u + 1) * (n_v + 1)
    owner = np.repeat(np.arange(len(n_u)), count)
    first = np.cumsum(count) - count
    local = np.arange(owner.size) - first[owner]
    i, j = np.divmod(local, n_v[owner] + 1)
    u = i / n_u[owner]  # u = i / n_u, i in 0..n_u
    v = j / n_v[owner]  # v = j / n_v, j in 0..n_v
    outside = u + v > 1.0
    u = np.where(outside, 1.0 - u, u)
    v = np.where(outside, 1.0 - v, v)
    points = a[owner] + u[:, None] * edge_ab[owner] + v[:, None] * edge_ac[owner]
    # ix = floor((x - x0) / cs), clipped so the max-bound vertex lands in the last cell
    ix = ((points[:, 0] - grid.origin_xz[0]) / grid.cell_size).astype(np.int64)
    iz = ((points[:, 2] - grid.origin_xz[1]) / grid.cell_size).astype(np.int64)
    ix, iz = np.clip(ix, 0, grid.nx - 1), np.clip(iz, 0, grid.nz - 1)
    return iz * grid.nx + ix, points[:, 1]


def merge_samples_into_spans(
    column: np.ndarray,
    y: np.ndarray,
    walkable: np.ndarray,
    grid: GridSpec,
    cell_height: float,
    max_climb: float,
) -> SolidSpans:
    """Merge the samples of each column into disjoint solid spans.

    Consecutive samples (sorted by height) of one column closer than ``cell_height`` belong
    to one span. As in Recast's ``addSpan`` flag merge, a span is walkable when a walkable
    sample lies within ``max_climb`` of its top (so a step's riser does not hide its tread).
    """
    height_range = grid.y_max - grid.y_min + 1.0
    # one sort on key = column * range + (y - y_min) orders samples by (column, y)
    order = np.argsort(column * height_range + (y - grid.y_min), kind="stable")
    column, y, walkable = column[order], y[order], walkable[order]
    starts = np.ones(y.size, dtype=bool)
    # a new span starts at a new column or after a vertical gap > cell_height
    starts[1:] = (column[1:] != column[:-1]) | (y[1:] - y[:-1] > cell_height)
    span_id = np.cumsum(starts) - 1
    first = np.flatnonzero(starts)
    last = np.r_[first[1:] - 1, y.size - 1]
    ymax = y[last]
    near_top = walkable & (y >= ymax[span_id] - max_climb)  # walkable sample near the top
    span_walkable = np.bincount(span_id, weights=near_top, minlength=first.size) > 0
    return SolidSpans(column[first], y[first], ymax, span_walkable)


def filter_low_hanging_obstacles(spans: SolidSpans, max_climb: float) -> None:
    """An unwalkable span whose top is within ``max_climb`` above a walkable span of the same
    column becomes walkable (curbs, stair nosings): Recast's
    ``rcFilterLowHangingWalkableObstacles``. Modifies ``spans.walkable`` in place."""
    same_column = spans.column[1:] == spans.column[:-1]
    below_walkable = spans.walkable[:-1].copy()  # the original flags of the lower span
    climbable = spans.ymax[1:] - spans.ymax[:-1] <= max_climb
    spans.walkable[1:] |= same_column & below_walkable & climbable


def span_clearance(spans: SolidSpans) -> np.ndarray:
    """Return ``(K,)`` the free height above each span: next span's ymin - ymax (inf at top)."""
    ceiling = np.full(spans.ymax.shape, np.inf)
    same_column = spans.column[1:] == spans.column[:-1]
    ceiling[:-1] = np.where(same_column, spans.ymin[1:], np.inf)
    return ceiling - spans.ymax


def filter_walkable_low_height_spans(spans: SolidSpans, agent_height: float) -> None:
    """Unmark spans whose clearance is below ``agent_height`` (a 1.4 m ceiling blocks a 1.5 m
    agent): Recast's ``rcFilterWalkableLowHeightSpans``. Modifies ``spans.walkable``."""
    spans.walkable &= span_clearance(spans) >= agent_height


def solid_overlaps(
    spans: SolidSpans, grid: GridSpec, column: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """Return ``(Q,) bool``: does column ``column[q]`` hold solid anywhere in ``[lo[q], hi[q]]``?

    Spans of one column are disjoint and sorted, so their tops are sorted too: a binary
    search for the first top >= lo finds the only span that can overlap the interval.
    """
    pad = max(1.0, float(np.max(hi - lo, initial=0.0)) + 1.0)
    stride = grid.y_max - grid.y_min + 2.0 * pad
    keys = spans.column * stride + (spans.ymax - grid.y_min + pad)
    # key(column, y) = column * stride + (y - y_min + pad) is increasing in (column, y)
    query = column * stride + np.maximum(lo - grid.y_min + pad, 0.0)
    idx = np.searchsorted(keys, query, side="left")
    found = idx < keys.size
    idx = np.minimum(idx, keys.size - 1)
    return found & (spans.column[idx] == column) & (spans.ymin[idx] <= hi)
