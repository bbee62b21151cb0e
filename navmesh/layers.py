"""Layered-grid stages of the navmesh build: surfaces -> connected, eroded, labelled nodes.

After ``navmesh.heightfield`` every grid column holds solid spans; the top of each walkable
span with enough clearance is a *surface*. Here the surfaces become dense layered arrays
``(L, nz, nx)`` (layer 0 = lowest surface of the column), neighbouring surfaces whose heights
differ by at most ``agent_max_climb`` are linked (Recast's ``rcBuildCompactHeightfield``),
the walkable area is eroded by the agent radius with a chamfer distance transform over the
links (``rcErodeWalkableArea``), and connected components become islands.

Grid and node conventions are in ``navmesh.navmesh_data`` (node = (layer * nz + iz) * nx + ix,
``DIRECTIONS`` = +X, -X, +Z, -Z).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from navmesh.heightfield import GridSpec, SolidSpans, solid_overlaps, span_clearance
from navmesh.navmesh_data import DIRECTIONS

# Diagonal steps as pairs of side directions: (+X,+Z), (+X,-Z), (-X,+Z), (-X,-Z).
DIAGONAL_SIDES = np.array([[0, 2], [0, 3], [1, 2], [1, 3]], dtype=np.int64)


def build_layers(spans: SolidSpans, grid: GridSpec):
    """Scatter the walkable span tops into dense layered arrays.

    Returns ``floor (L, nz, nx)`` (NaN where no surface), ``ceiling (L, nz, nx)`` (height of
    the next solid above, inf for open sky) and ``walkable (L, nz, nx) bool``.
    """
    keep = spans.walkable
    column = spans.column[keep]
    floor = spans.ymax[keep]
    ceiling = floor + span_clearance(spans)[keep]
    starts = np.r_[True, column[1:] != column[:-1]] if column.size else np.zeros(0, bool)
    # rank of a surface within its column = index - index of the column's first surface
    first_of_group = np.maximum.accumulate(np.where(starts, np.arange(column.size), 0))
    layer = np.arange(column.size) - first_of_group
    n_layers = int(layer.max()) + 1 if layer.size else 1
    shape = (n_layers, grid.nz, grid.nx)
    floor_grid = np.full(shape, np.nan)
    ceiling_grid = np.full(shape, np.nan)
    flat = layer * grid.n_cells + column  # node index of every surface
    floor_grid.reshape(-1)[flat] = floor
    ceiling_grid.reshape(-1)[flat] = ceiling
    return floor_grid, ceiling_grid, ~np.isnan(floor_grid)


def shift_to_neighbour(values: np.ndarray, dx: int, dz: int, fill) -> np.ndarray:
    """Return ``out[..., iz, ix] = values[..., iz + dz, ix + dx]`` (``fill`` off the grid)."""
    out = np.full(values.shape, fill, dtype=values.dtype)
    nz, nx = values.shape[-2:]
    dst_z = slice(max(0, -dz), nz - max(0, dz))
    dst_x = slice(max(0, -dx), nx - max(0, dx))
    src_z = slice(max(0, dz), nz - max(0, -dz))
    src_x = slice(max(0, dx), nx - max(0, -dx))
    out[..., dst_z, dst_x] = values[..., src_z, src_x]
    return out


def filter_ledges(
    floor, walkable, spans: SolidSpans, grid: GridSpec, agent_height: float, max_climb: float
) -> np.ndarray:
    """Unmark surfaces next to a drop (Recast's ``rcFilterLedgeSpans``); returns walkable.

    A surface at height h is a ledge when, across one of its four sides, the grid ends or the
    neighbour column is empty from ``h - max_climb`` up to ``h + agent_height``: stepping
    there the agent would fall more than it can climb.
    """
    layer, iz, ix = np.nonzero(walkable)
    h = floor[layer, iz, ix]
    is_ledge = np.zeros(h.size, dtype=bool)
    for dx, dz in DIRECTIONS:
        nz_, nx_ = iz + dz, ix + dx
        inside = (nz_ >= 0) & (nz_ < grid.nz) & (nx_ >= 0) & (nx_ < grid.nx)
        column = np.where(inside, nz_ * grid.nx + nx_, 0)
        supported = solid_overlaps(spans, grid, column, h - max_climb, h + agent_height)
        is_ledge |= ~inside | ~supported
    result = walkable.copy()
    result[layer[is_ledge], iz[is_ledge], ix[is_ledge]] = False
    return result


def connect_neighbours(floor, ceiling, walkable, agent_height: float, max_climb: float):
    """Link each walkable surface to the closest-height walkable surface across each side.

    Surfaces a and b connect when ``|floor_a - floor_b| <= max_climb`` and the shared
    clearance ``min(ceil_a, ceil_b) - max(floor_a, floor_b) >= agent_height``.
    Returns ``links (4, L, nz, nx) int8``: neighbour layer, or -1.
    """
    n_layers = floor.shape[0]
    links = np.full((4,) + floor.shape, -1, dtype=np.int8)
    safe_floor = np.where(walkable, floor, np.inf)
    for d, (dx, dz) in enumerate(DIRECTIONS):
        nb_floor = shift_to_neighbour(safe_floor, int(dx), int(dz), np.inf)
        nb_ceiling = shift_to_neighbour(ceiling, int(dx), int(dz), np.nan)
        for a in range(n_layers):
            step = np.abs(nb_floor - floor[a])  # (L, nz, nx): |floor_b - floor_a| for every b
            with np.errstate(invalid="ignore"):  # inf - inf where either side is empty
                clearance = np.fmin(nb_ceiling, ceiling[a]) - np.fmax(nb_floor, floor[a])
            ok = (step <= max_climb) & (clearance >= agent_height) & walkable[a]
            cost = np.where(ok, step, np.inf)
            best = np.argmin(cost, axis=0)  # the closest height wins (first on ties)
            found = np.isfinite(np.min(cost, axis=0))
            links[d, a] = np.where(found, best, -1)
    return links


def neighbour_node_ids(links: np.ndarray) -> np.ndarray:
    """Return ``(8, N) int64`` node ids of the 4 side and 4 diagonal neighbours (-1 = none).

    Rows 0-3 follow ``DIRECTIONS``; rows 4-7 follow ``DIAGONAL_SIDES``. A diagonal step
    exists only when both L-shaped routes through the two side neighbours exist and land on
    the same node, so paths never cut a blocked corner.
    """
    n_layers, nz, nx = links.shape[1:]
    iz, ix = np.divmod(np.arange(nz * nx), nx)
    side = np.full((4, n_layers * nz * nx), -1, dtype=np.int64)
    for d, (dx, dz) in enumerate(DIRECTIONS):
        target_cell = (iz + dz) * nx + (ix + dx)
        for a in range(n_layers):
            layer_b = links[d, a].reshape(-1).astype(np.int64)
            node_b = layer_b * (nz * nx) + target_cell  # node = layer * n_cells + cell
            side[d, a * nz * nx : (a + 1) * nz * nx] = np.where(layer_b >= 0, node_b, -1)
    diagonal = np.full((4, side.shape[1]), -1, dtype=np.int64)
    for k, (d1, d2) in enumerate(DIAGONAL_SIDES):
        via_1 = _follow(side, side[d1], d2)  # step d1 then d2
        via_2 = _follow(side, side[d2], d1)  # step d2 then d1
        diagonal[k] = np.where((via_1 >= 0) & (via_1 == via_2), via_1, -1)
    return np.concatenate([side, diagonal])


def _follow(side: np.ndarray, nodes: np.ndarray, d: int) -> np.ndarray:
    """Neighbour across side d of each node in ``nodes`` (-1 stays -1)."""
    return np.where(nodes >= 0, side[d][np.maximum(nodes, 0)], -1)


def erode_walkable_area(walkable: np.ndarray, links: np.ndarray, radius_cells: int) -> np.ndarray:
    """Remove walkable nodes closer than ``radius_cells`` to the walkable boundary.

    Boundary nodes (a side without a link) get distance 0; a chamfer transform over the
    8 neighbours, ``dist_i = min(dist_i, dist_j + w_ij)`` with w = 1 (side) or sqrt(2)
    (diagonal), is relaxed ``radius_cells + 2`` times, enough for every distance below the
    radius to settle, or until a sweep changes nothing (so the work is bounded by the
    grid, not by the radius). Nodes with ``dist < radius_cells`` are removed. Returns the
    new mask.
    """
    if radius_cells <= 0:
        return walkable.copy()
    flat_walkable = walkable.reshape(-1)
    boundary = flat_walkable & np.any(links.reshape(4, -1) < 0, axis=0)
    dist = np.where(boundary, 0.0, np.inf)
    dist[~flat_walkable] = 0.0  # unwalkable nodes never count, keep them at 0
    neighbours = neighbour_node_ids(links)
    weight = np.r_[np.ones(4), np.full(4, np.sqrt(2.0))]
    for _ in range(radius_cells + 2):
        before = dist.copy()
        for row, w in zip(neighbours, weight, strict=True):
            has = row >= 0
            # dist_i = min(dist_i, dist_j + w) over every existing neighbour j
            candidate = np.where(has, dist[np.maximum(row, 0)] + w, np.inf)
            np.minimum(dist, candidate, out=dist)
        if np.array_equal(dist, before):
            break  # settled: further sweeps change nothing (a huge radius ends here too)
    return (flat_walkable & (dist >= radius_cells)).reshape(walkable.shape)


def restrict_links(links: np.ndarray, navigable: np.ndarray) -> np.ndarray:
    """Keep only links whose both ends are navigable; returns a new ``links`` array."""
    n_layers, nz, nx = navigable.shape
    out = links.copy()
    for d, (dx, dz) in enumerate(DIRECTIONS):
        nb_navigable = shift_to_neighbour(navigable, int(dx), int(dz), False)  # (L, nz, nx)
        for a in range(n_layers):
            layer_b = np.maximum(links[d, a], 0).astype(np.int64)
            target_ok = np.take_along_axis(nb_navigable, layer_b[None], axis=0)[0]
            ok = navigable[a] & (links[d, a] >= 0) & target_ok
            out[d, a] = np.where(ok, links[d, a], -1)
    return out


def label_islands(navigable: np.ndarray, links: np.ndarray, min_cells: int):
    """Connected components of the navigable nodes; drop islands under ``min_cells`` cells.

    Returns ``(navigable, links, island)``: the pruned mask, the links restricted to it and
    ``island (L, nz, nx) int32`` numbered by decreasing size (ties: lowest node first), -1
    where not navigable.
    """
    neighbours = neighbour_node_ids(links)[:4]
    n_nodes = neighbours.shape[1]
    src = np.repeat(np.arange(n_nodes)[None], 4, axis=0)
    has = neighbours >= 0
    graph = coo_matrix(
        (np.ones(int(has.sum())), (src[has], neighbours[has])), shape=(n_nodes, n_nodes)
    )
    _, label = connected_components(graph, directed=False)
    flat_nav = navigable.reshape(-1)
    label = np.where(flat_nav, label, -1)
    ids, first_node, size = np.unique(label[flat_nav], return_index=True, return_counts=True)
    first_node = np.flatnonzero(flat_nav)[first_node]
    kept = size >= max(1, min_cells)
    order = np.lexsort((first_node[kept], -size[kept]))  # biggest first, then lowest node
    new_id = np.full(max(int(ids.max(initial=-1)) + 1, 1), -1, dtype=np.int32)
    new_id[ids[kept][order]] = np.arange(order.size, dtype=np.int32)
    island = np.where(flat_nav, new_id[np.maximum(label, 0)], -1).astype(np.int32)
    navigable = (island >= 0).reshape(navigable.shape)
    return navigable, restrict_links(links, navigable), island.reshape(navigable.shape)
