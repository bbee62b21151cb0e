"""Triangle rasterization with a z-buffer: setup, scanline spans, depth test.

Stages 4-6 (numbered as in ``render_frame``, ``render/__init__.py``)
--------------------------------------------------------------------

Each stage is a function below; culling and near clipping, stages 2-3, are in
``render.cull``; triangle batches use the corner-major ``(3, 3, T)`` layout described there.

4. ``plane_coefficients`` (triangle setup, beside ``project_triangles``): per source
   triangle, three functions that are *affine in pixel coordinates* (the key fact of
   perspective-correct interpolation)::

       pinhole: q_k = b_k / z  (k = 0, 1),   w = 1 / z = q_0 + q_1 + q_2
       ortho:   q_k = b_k,                   w = z = sum_k b_k z_k

   where ``b_k`` are the barycentric coordinates of the 3D point seen through the pixel and
   ``z`` its z-depth. With ``M = [P0 P1 P2]`` (camera-frame corners as columns) and the
   pixel ray ``r = ((px - cx) / fx, -(py - cy) / fy, -1)``, the point ``z r`` has
   barycentrics ``b = z M^-1 r``, so ``b / z = M^-1 r`` is linear in ``(px, py)`` and
   ``sum_k b_k = 1`` gives ``1 / z = 1^T M^-1 r``. The rows of ``M^-1`` are
   ``(P1 x P2, P2 x P0, P0 x P1) / det M``: signed volumes of tetrahedra with the eye.
   These functions are computed from the *unclipped* triangle, so clipping never distorts
   attributes. Coordinates are centered on the principal point for float32 accuracy.
5. ``scanline_spans``: for every pixel row a triangle touches, the run of covered columns.
6. ``depth_test_spans``: expand spans to fragments in cache-sized chunks (16k), compute each
   fragment's depth and keep, per pixel, the smallest key ``(depth bits << 32) | triangle``
   with ``np.minimum.at`` (depth test and tie break in one pass: the bit patterns of
   positive float32 numbers sort like the numbers, and equal depths keep the lower
   triangle index, so the result is deterministic).

Reading the z-buffer back and interpolating attributes at the visible pixels (stages 7-8)
are in ``render.resolve``.

Fill rule (top-left, at pixel centers)
--------------------------------------
Pixel ``(row, col)`` with center ``(xc, yc) = (col + 0.5, row + 0.5)`` is covered by a
triangle when ``y_top <= yc < y_bottom`` and ``x_left(yc) <= xc < x_right(yc)``: top and
left edges are inclusive, bottom and right edges exclusive. Each edge's crossing ``x(yc)``
is computed by one formula from its endpoints ordered top to bottom, so two triangles
sharing an edge compute bit-identical crossings and a pixel center exactly on the shared
edge belongs to exactly one of them: no gaps, no pixel drawn twice.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from render.camera import Camera
from render.cull import cross
from render.resolve import (
    EMPTY_KEY,
    AttributePlanes,
    VisiblePixels,
    pixel_center_tables,
    resolve_depth,
    visible_from_keys,
    winning_triangles,
)
from render.settings import DEFAULT_SETTINGS

__all__ = [  # and, re-exported from render.resolve, what reads the z-buffer back
    "EMPTY_KEY",
    "AttributePlanes",
    "Spans",
    "VisiblePixels",
    "bounding_box_has_pixel_centers",
    "depth_test_spans",
    "pixel_center_tables",
    "plane_coefficients",
    "project_triangles",
    "resolve_depth",
    "scanline_spans",
    "visible_from_keys",
    "winning_triangles",
]


def plane_coefficients(tri: np.ndarray, camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """Affine screen functions ``(q_0, q_1, w)`` of each triangle (see module docstring).

    Each function is ``f(px, py) = A (px - cx) + B (py - cy) + C``.

    Parameters
    ----------
    tri : (3, 3, T) float64, camera-frame corners (corner, coordinate, triangle).

    Returns
    -------
    planes : (3, 3, T) float64, ``planes[f, :, t] = (A, B, C)`` for f in (q_0, q_1, w).
    valid : (T,) bool, False for edge-on triangles (plane through the eye, or zero area).
    """
    if camera.is_pinhole:  # 3D corners (x, y, z)
        corners = tuple((tri[k, 0], tri[k, 1], tri[k, 2]) for k in range(3))
    else:  # orthographic: 2D homogeneous corners (x, y, 1)
        one = np.ones(tri.shape[2])
        corners = tuple((tri[k, 0], tri[k, 1], one) for k in range(3))
    rows = [cross(corners[1], corners[2]), cross(corners[2], corners[0])]
    rows.append(cross(corners[0], corners[1]))  # rows of det(M) M^-1
    det = sum(corners[0][c] * rows[0][c] for c in range(3))  # det M = P0 . (P1 x P2)
    scale = np.ones_like(det)
    for corner in corners:
        scale *= np.sqrt(corner[0] ** 2 + corner[1] ** 2 + corner[2] ** 2)
    valid = np.abs(det) > 1e-12 * scale
    inv_det = np.divide(1.0, det, out=np.zeros_like(det), where=valid)
    sign_c = -1.0 if camera.is_pinhole else 1.0  # r = (u, v, -1) or (u, v, 1)
    coeffs = [  # q_k = (m_k . r): A = m_x / fx, B = -m_y / fy, C = +-m_z
        np.stack([m[0] / camera.fx, -m[1] / camera.fy, sign_c * m[2]]) * inv_det for m in rows
    ]
    planes = np.empty((3, 3, tri.shape[2]))
    planes[0], planes[1] = coeffs[0], coeffs[1]
    if camera.is_pinhole:
        planes[2] = coeffs[0] + coeffs[1] + coeffs[2]  # w = 1 / z = q_0 + q_1 + q_2
    else:
        depth = -tri[:, 2]  # (3, T) corner z-depths
        planes[2] = coeffs[0] * depth[0] + coeffs[1] * depth[1] + coeffs[2] * depth[2]  # z
    return planes, valid


def project_triangles(tri: np.ndarray, camera: Camera) -> np.ndarray:
    """Continuous pixel coordinates of triangle corners, ``(3, 2, T)`` (corner, px/py, t)."""
    depth = -tri[:, 2]  # (3, T)
    if camera.is_pinhole:
        inv_depth = 1.0 / depth  # corners are in front of the near plane after clipping
        px = camera.cx + camera.fx * tri[:, 0] * inv_depth  # px = cx + fx x / z
        py = camera.cy - camera.fy * tri[:, 1] * inv_depth  # py = cy - fy y / z
    else:
        px = camera.cx + camera.fx * tri[:, 0]  # px = cx + s x
        py = camera.cy - camera.fy * tri[:, 1]  # py = cy - s y
    return np.stack([px, py], axis=1)


def bounding_box_has_pixel_centers(screen: np.ndarray, height: int, width: int) -> np.ndarray:
    """``(T,)`` bool: the triangle's bounding box, clipped to the image, holds a pixel center.

    A cheap, conservative pre-test (a triangle may still miss every center): sub-pixel and
    off-screen triangles skip the setup and span stages. Rows with centers in
    ``[y_min, y_max)`` are ``ceil(y_min - 1/2) .. ceil(y_max - 1/2) - 1``; same for columns.
    """
    x, y = screen[:, 0], screen[:, 1]  # (3, T) each
    ok = np.ones(screen.shape[2], dtype=bool)
    for coord, size in ((y, height), (x, width)):
        low = np.maximum(np.ceil(np.minimum(np.minimum(coord[0], coord[1]), coord[2]) - 0.5), 0)
        high = np.minimum(np.ceil(np.maximum(np.maximum(coord[0], coord[1]), coord[2]) - 0.5), size)
        ok &= low < high  # at least one row (column) center inside
    return ok


@dataclass
class Spans:
    """Horizontal pixel runs: row ``row[i]`` covers columns ``[col_first[i], +n_pixels[i])``.

    ``triangle[i]`` is the index (into the rasterized triangle list) owning the run.
    """

    triangle: np.ndarray
    row: np.ndarray
    col_first: np.ndarray
    n_pixels: np.ndarray


def scanline_spans(
    screen: np.ndarray, height: int, width: int, rows: tuple[int, int] | None = None
) -> Spans:
    """Pixel rows and column runs covered by each triangle under the top-left rule.

    Parameters
    ----------
    screen : (3, 2, T) float64, corner pixel coordinates ``(px, py)``.
    height, width : image size in pixels.
    rows : ``(first, end)``: only the spans on image rows ``first .. end - 1`` (each row's
        span is computed on its own, so these are exactly the spans of the whole image on
        those rows); None: all rows.
    """
    first_row, end_row = (0, height) if rows is None else rows
    (x0, y0), (x1, y1), (x2, y2) = _sort_corners_by_y(screen)  # top, middle, bottom
    with np.errstate(divide="ignore", invalid="ignore"):
        slope02 = (x2 - x0) / (y2 - y0)  # dx/dy of the long edge
        slope01 = (x1 - x0) / (y1 - y0)  # upper short edge
        slope12 = (x2 - x1) / (y2 - y1)  # lower short edge
    # long edge 0->2 is on the left when the middle corner is right of it (cross < 0, y down)
    long_is_left = (x2 - x0) * (y1 - y0) - (y2 - y0) * (x1 - x0) < 0.0
    row_first = np.clip(np.ceil(y0 - 0.5), first_row, end_row).astype(np.int64)  # first yc >= y0
    row_end = np.clip(np.ceil(y2 - 0.5), first_row, end_row).astype(np.int64)  # first yc >= y2
    n_rows = np.maximum(row_end - row_first, 0)
    tri = np.repeat(np.arange(screen.shape[2]), n_rows)
    row = np.arange(len(tri)) - np.repeat(np.cumsum(n_rows) - n_rows - row_first, n_rows)
    yc = row + 0.5
    with np.errstate(invalid="ignore"):
        x_long = x0[tri] + (yc - y0[tri]) * slope02[tri]  # x(yc) = x_top + (yc - y_top) dx/dy
        upper = yc < y1[tri]
        x_short = np.where(
            upper, x0[tri] + (yc - y0[tri]) * slope01[tri], x1[tri] + (yc - y1[tri]) * slope12[tri]
        )
    left = np.where(long_is_left[tri], x_long, x_short)
    right = np.where(long_is_left[tri], x_short, x_long)
    col_first = np.clip(np.ceil(left - 0.5), 0, width).astype(np.int64)  # first xc >= x_left
    col_end = np.clip(np.ceil(right - 0.5), 0, width).astype(np.int64)  # first xc >= x_right
    n_pixels = col_end - col_first
    keep = n_pixels > 0
    return Spans(tri[keep], row[keep], col_first[keep], n_pixels[keep])


def _sort_corners_by_y(screen: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Corners ``(x, y)`` ordered by increasing y with a 3-element sorting network.

    The order of corners with equal y does not matter: only non-horizontal edges are ever
    intersected, and their endpoints are ordered by y unambiguously.
    """
    corners = [(screen[k, 0], screen[k, 1]) for k in range(3)]
    for i, j in ((0, 1), (1, 2), (0, 1)):
        (xi, yi), (xj, yj) = corners[i], corners[j]
        swap = yj < yi
        corners[i] = (np.where(swap, xj, xi), np.where(swap, yj, yi))
        corners[j] = (np.where(swap, xi, xj), np.where(swap, yi, yj))
    return corners


def depth_test_spans(
    spans: Spans,
    planes: np.ndarray,
    key_triangle: np.ndarray,
    camera: Camera,
    zkey: np.ndarray,
    key_id: np.ndarray | None = None,
    far_test: bool = True,
    fragment_chunk: int = DEFAULT_SETTINGS.fragment_chunk,
) -> int:
    """Expand spans into fragments and depth-test them into ``zkey`` in place.

    Parameters
    ----------
    spans : runs from ``scanline_spans``; ``spans.triangle`` indexes ``key_triangle``.
    planes : (3, 3, S) plane coefficients of the source triangles.
    key_triangle : (T,) int, source triangle of each rasterized triangle (indexes ``planes``).
    camera : the camera (pinhole: depth = 1 / w; ortho: depth = w).
    zkey : (H * W,) uint64, the z-buffer ``(float32 depth bits << 32) | triangle``.
    key_id : (S,) int, the id stored in the key for each source triangle (default: its
        index into ``planes``).
    far_test : discard fragments beyond ``camera.far``; pass False when no triangle reaches
        past the far plane (saves two passes over the fragments).
    fragment_chunk : fragments per chunk (``RenderSettings.fragment_chunk``).

    Returns
    -------
    n_fragments : int, number of fragments generated (for profiling).
    """
    width = camera.width
    source = key_triangle[spans.triangle]  # source triangle of each span
    w_a, w_b, w_c = (planes[2, j][source] for j in range(3))  # plane of w per span
    xc = spans.col_first + 0.5 - camera.cx
    yc = spans.row + 0.5 - camera.cy
    w_first = (w_a * xc + w_b * yc + w_c).astype(np.float32)  # w at the first pixel center
    w_step = w_a.astype(np.float32)  # dw / dpx along the row
    pixel_first = (spans.row * width + spans.col_first).astype(np.int32)  # H W < 2^31
    tri_key = (source if key_id is None else key_id[source]).astype(np.uint64)
    ends = np.cumsum(spans.n_pixels)  # fragment count up to and including each span
    cuts = np.searchsorted(
        ends, np.arange(fragment_chunk, ends[-1] if len(ends) else 0, fragment_chunk)
    )
    bounds = np.concatenate([[0], np.unique(cuts), [len(ends)]])
    for s0, s1 in zip(bounds[:-1], bounds[1:], strict=True):
        if s1 > s0:  # spans s0..s1-1 form one cache-sized chunk of fragments
            chunk = slice(s0, s1)
            pixel, depth = _chunk_fragments(
                spans.n_pixels[chunk], pixel_first[chunk], w_first[chunk], w_step[chunk], camera
            )
            key = depth.view(np.uint32).astype(np.uint64)
            key <<= np.uint64(32)
            key |= np.repeat(tri_key[chunk], spans.n_pixels[chunk])  # (depth bits << 32) | id
            if far_test:
                keep = depth <= camera.far
                pixel, key = pixel[keep], key[keep]
            np.minimum.at(zkey, pixel, key)  # z-test: keep the nearest per pixel
    return int(ends[-1]) if len(ends) else 0


def _chunk_fragments(
    counts: np.ndarray,
    pixel_first: np.ndarray,
    w_first: np.ndarray,
    w_step: np.ndarray,
    camera: Camera,
) -> tuple[np.ndarray, np.ndarray]:
    """Fragments of a run of spans: flat pixel index (int32) and z-depth (float32).

    In-place int32 / float32 arithmetic: half the memory traffic of int64 / float64
    (measured faster overall, although ``np.minimum.at`` converts int32 indices).
    """
    starts = (np.cumsum(counts) - counts).astype(np.int32)  # first fragment of each span
    local = np.arange(int(counts.sum()), dtype=np.int32)
    local -= np.repeat(starts, counts)  # column offset inside the span
    pixel = np.repeat(pixel_first, counts)
    pixel += local  # pixel = row W + col
    depth = local.astype(np.float32)
    depth *= np.repeat(w_step, counts)
    depth += np.repeat(w_first, counts)  # w(col) = w(col_first) + dw/dpx (col - col_first)
    if camera.is_pinhole:
        np.divide(np.float32(1.0), depth, out=depth)  # z = 1 / w  (orthographic: z = w)
    return pixel, depth
