"""Which stage triangles lie near each body: a uniform grid of the static stage, built once.

The stage (body 0) is a static triangle mesh; every step the ``stage-hull`` contact rule
needs, for each body resting on it, the few triangles near the body. Asking fcl's BVH costs
one Python call per body; this grid answers all bodies of a step with a handful of NumPy
calls (Ericson, *Real-Time Collision Detection*, 7.1 "Uniform grids"; Teschner et al. 2003,
"Optimized spatial hashing", use the same cell lists).

Building (once per stage, kept on the stage shape): the ground plane X-Z is cut into square
cells of side ``c`` (``STAGE_GRID_CELL``, grown if the grid would hold more than
``STAGE_GRID_MAX_CELLS`` cells); every triangle is filed under each cell its axis-aligned box
covers,

::

    i_x \\in [\\lfloor (x_{min} - o_x) / c \\rfloor, \\lfloor (x_{max} - o_x) / c \\rfloor],

likewise for z, with ``o`` the stage's lowest corner. The cell lists are one CSR table:
``cell_start (n_cells + 1,)`` offsets into ``cell_triangles``.

Query (:meth:`StageGrid.candidates`): for boxes ``lo, hi (b, 3)`` (bodies' world AABBs,
grown by the speculative distance), the cells each box covers, the triangles filed there,
and of those the ones whose own box overlaps the query box in all three axes (so Y, which
the grid does not cut, is tested too). The answer is exactly the brute-force AABB test
:func:`candidate_triangles_reference` (tested), only faster: a body meets a few cells of a
few triangles instead of all of them. A triangle that touches the body's hull (or its
probe, grown by ``STAGE_SPECULATIVE_DISTANCE``) always overlaps its box, so the candidates
hold every triangle fcl would report (tested against fcl) when the boxes are grown by
``STAGE_NEAR_DISTANCE`` (the probe's reach).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.settings import (
    STAGE_CORNER_COSINE,
    STAGE_CROSSING_TOLERANCE,
    STAGE_GRID_CELL,
    STAGE_GRID_MAX_CELLS,
    TINY,
)

#: the grid's two axes, x and z, as columns of a point
XZ = [0, 2]


@dataclass
class StageGrid:
    """A uniform X-Z grid of a static mesh's triangles (see the module docstring).

    ``tri_lo, tri_hi (T, 3)`` world AABBs of the triangles, m; ``origin (2,)`` the grid's
    lowest (x, z) corner, m; ``cell`` its cell side, m; ``shape (n_x, n_z)`` cells;
    ``cell_start (n_x n_z + 1,)`` and ``cell_triangles (E,)``: the triangles of cell
    ``k = i_x n_z + i_z`` are ``cell_triangles[cell_start[k]:cell_start[k + 1]]``;
    ``corner_free``: no two triangles meet at a corner (:func:`corner_free`);
    ``one_plane``: all triangles lie in one plane (:func:`one_plane`).
    """

    tri_lo: np.ndarray
    tri_hi: np.ndarray
    origin: np.ndarray
    cell: float
    shape: tuple[int, int]
    cell_start: np.ndarray
    cell_triangles: np.ndarray
    corner_free: bool = False
    one_plane: bool = False

    @classmethod
    def build(cls, triangles: np.ndarray, cell: float = STAGE_GRID_CELL) -> StageGrid:
        """The grid of ``triangles (T, 3, 3)`` (world corners, m)."""
        tri_lo, tri_hi = triangles.min(axis=1), triangles.max(axis=1)
        origin = tri_lo[:, [0, 2]].min(axis=0)
        extent = tri_hi[:, [0, 2]].max(axis=0) - origin
        # grow the cell until the grid stays under STAGE_GRID_MAX_CELLS cells
        while np.prod(np.floor(extent / cell) + 1) > STAGE_GRID_MAX_CELLS:
            cell *= 2.0
        n_x, n_z = (np.floor(extent / cell) + 1).astype(np.int64)
        first, last = cls._cell_range(tri_lo, tri_hi, origin, cell, (int(n_x), int(n_z)))
        # every (triangle, cell) it covers, then grouped by cell (stable: triangles ascending)
        owner, cell_id = _cells_of_boxes(first, last, int(n_z))
        order = np.argsort(cell_id, kind="stable")
        counts = np.bincount(cell_id, minlength=int(n_x * n_z))
        cell_start = np.concatenate([[0], np.cumsum(counts)])
        shape = (int(n_x), int(n_z))
        flat = corner_free(triangles)
        planar = one_plane(triangles)
        return cls(tri_lo, tri_hi, origin, cell, shape, cell_start, owner[order], flat, planar)

    @staticmethod
    def _cell_range(lo, hi, origin, cell, shape):
        """First and last cell ``(i_x, i_z)`` covered by boxes ``lo, hi (b, 3)``, each
        ``(b, 2)`` int, clipped to the grid (a box beyond it gets an empty range)."""
        # both corners at once: floor((corner - origin) / cell) along x and z, (2, b, 2)
        first, last = np.floor((np.stack((lo, hi))[:, :, XZ] - origin) / cell).astype(np.int64)
        return np.maximum(first, 0), np.minimum(last, (shape[0] - 1, shape[1] - 1))

    def candidates(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Triangles whose AABB overlaps box ``k`` of ``lo, hi (b, 3)``, as flat pairs
        ``(box (p,), triangle (p,))`` sorted by box, then triangle (no duplicates).

        Reference: :func:`candidate_triangles_reference` (all triangles, one box at a time).
        """
        empty = np.zeros(0, dtype=np.int64)
        if len(lo) == 0:
            return empty, empty
        first, last = self._cell_range(lo, hi, self.origin, self.cell, self.shape)
        box, cell_id = _cells_of_boxes(first, last, self.shape[1])
        # every triangle filed under those cells: a CSR gather
        start, stop = self.cell_start[cell_id], self.cell_start[cell_id + 1]
        owner, offset = _expand(stop - start)
        box, tri = box[owner], self.cell_triangles[start[owner] + offset]
        # the triangle's own box must overlap the query box on all three axes (the three
        # written out: .all over a length-3 axis pays per row)
        each = (self.tri_lo[tri] <= hi[box]) & (self.tri_hi[tri] >= lo[box])  # (e, 3)
        overlap = each[:, 0] & each[:, 1] & each[:, 2]
        # one pair per (box, triangle): a triangle may share several cells with a box
        n_tri = len(self.tri_lo)
        key = np.unique(box[overlap] * n_tri + tri[overlap])
        return key // n_tri, key % n_tri


def corner_free(triangles: np.ndarray) -> bool:
    """Whether no two of ``triangles (T, 3, 3)`` are turned far enough from each other to
    form a corner for the stage-hull rule (``|n_s . n_t| < STAGE_CORNER_COSINE``, about 45
    degrees): every triangle's normal line lies within half that angle of the first's, so
    any two lie within the whole angle (a flat floor; the rule's corner pass has nothing to
    find). A small margin keeps rounding on the safe side; a degenerate triangle (no
    normal) answers False.
    """
    e0, e1 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    normal = np.cross(e0, e1)
    length = np.linalg.norm(normal, axis=1)
    if len(normal) == 0 or (length <= TINY).any():
        return False
    normal /= length[:, None]
    half = 0.5 * np.arccos(STAGE_CORNER_COSINE) - 1e-6  # rad, half the corner angle
    return bool((np.abs(normal @ normal[0]) >= np.cos(half)).all())


def one_plane(triangles: np.ndarray) -> bool:
    """Whether every corner of ``triangles (T, 3, 3)`` lies within a tenth of
    ``STAGE_CROSSING_TOLERANCE`` of the first triangle's plane (a floor): no vertex's way
    out of one triangle can cross another (:mod:`stage_crossings`); a degenerate first
    triangle answers False."""
    e0, e1 = triangles[0, 1] - triangles[0, 0], triangles[0, 2] - triangles[0, 0]
    normal = np.cross(e0, e1)
    length = float(np.linalg.norm(normal))
    if length <= TINY:
        return False
    offset = (triangles - triangles[0, 0]) @ (normal / length)  # (T, 3) heights
    return bool((np.abs(offset) <= 0.1 * STAGE_CROSSING_TOLERANCE).all())


def _expand(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For ``counts (k,)``: ``owner`` repeating ``i`` counts[i] times and ``offset``
    counting ``0 .. counts[i] - 1`` within each run (the flat index of a ragged table)."""
    owner = np.repeat(np.arange(len(counts)), counts)
    run_start = np.cumsum(counts) - counts
    return owner, np.arange(len(owner)) - run_start[owner]


def _cells_of_boxes(first: np.ndarray, last: np.ndarray, n_z: int):
    """``(box (e,), cell (e,))``: every cell ``i_x n_z + i_z`` in the ranges ``first ..
    last (b, 2)`` of each box (empty where ``last < first``)."""
    span = np.maximum(last - first + 1, 0)  # (b, 2) cells along x and z
    box, offset = _expand(span.prod(axis=1))  # cells along x times cells along z
    step_x, step_z = np.divmod(offset, np.maximum(span[box, 1], 1))
    cell = (first[box, 0] + step_x) * n_z + first[box, 1] + step_z
    return box, cell


def stage_grid(mesh_shape) -> StageGrid:
    """The grid of a static mesh shape's ``ray_triangles``, built once and kept on it."""
    grid = getattr(mesh_shape, "_stage_grid", None)
    if grid is None:
        grid = StageGrid.build(mesh_shape.ray_triangles)
        mesh_shape._stage_grid = grid
    return grid


def candidate_triangles_reference(triangles: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Plain version of :meth:`StageGrid.candidates`: for each box ``lo[k], hi[k]``, every
    triangle of ``triangles (T, 3, 3)`` whose AABB overlaps it; a list of ascending id
    arrays, one per box."""
    tri_lo, tri_hi = triangles.min(axis=1), triangles.max(axis=1)
    out = []
    for box_lo, box_hi in zip(lo, hi, strict=True):
        # boxes overlap when they overlap on every axis: lo_t <= hi_b and hi_t >= lo_b
        overlap = np.all((tri_lo <= box_hi) & (tri_hi >= box_lo), axis=1)
        out.append(np.flatnonzero(overlap))
    return out
