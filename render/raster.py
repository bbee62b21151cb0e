"""Triangle rasterization with a z-buffer: culling, near clipping, scanline spans, depth test.

Stages (each a function below, called in this order by ``render.frame.render_frame``)
---------------------------------------------------------------------------------------
1. ``frustum_keep_mask``: drop triangles whose three corners lie outside the same frustum
   plane (Cohen-Sutherland outcodes), and optionally back faces.
2. ``clip_near``: clip the triangles crossing the near plane ``z_camera = -near``. A triangle
   with one corner in front becomes one triangle, with two corners in front a quad = two
   triangles. Each piece remembers its ``source`` triangle.
3. ``plane_coefficients``: per source triangle, three functions that are *affine in pixel
   coordinates* (the key fact of perspective-correct interpolation)::

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
4. ``scanline_spans``: for every pixel row a triangle touches, the run of covered columns.
5. ``depth_test_spans``: expand spans to fragments in cache-sized chunks (16k), compute each
   fragment's depth and keep, per pixel, the smallest key ``(depth bits << 32) | triangle``
   with ``np.minimum.at`` (depth test and tie break in one pass: equal depths keep the
   lower triangle index, so the result is deterministic).
6. ``resolve_depth`` and ``AttributePlanes``: the winning triangle and depth per pixel,
   then perspective-correct vertex attributes (uvs, colors) for deferred shading (each
   visible pixel is shaded exactly once).

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

#: fragments per chunk: temporaries of 16k elements stay in the CPU cache (3x faster than 200k)
FRAGMENT_CHUNK = 16_384
#: an empty z-buffer key: larger than any (depth bits << 32) | triangle
EMPTY_KEY = np.uint64(0xFFFFFFFFFFFFFFFF)
_LOW32 = np.uint64(0xFFFFFFFF)


def frustum_keep_mask(
    tri_camera: np.ndarray, camera: Camera, cull_back_faces: bool = False
) -> np.ndarray:
    """Which triangles may be visible: not entirely outside one frustum plane.

    Parameters
    ----------
    tri_camera : (T, 3, 3) float64, triangle corners in the camera frame (meters).
    camera : the camera (its near, far and image bounds define the frustum).
    cull_back_faces : also drop triangles whose counter-clockwise front faces away.

    Returns
    -------
    keep : (T,) bool.
    """
    x, y, z = tri_camera[..., 0], tri_camera[..., 1], tri_camera[..., 2]
    depth = -z  # z-depth of each corner
    if camera.is_pinhole:
        # px < 0  <=>  cx + fx x / d < 0  <=>  fx x + cx d < 0 (half-spaces through the eye)
        scaled_x, scaled_y, scale = camera.fx * x, camera.fy * y, depth
    else:
        scaled_x, scaled_y, scale = camera.fx * x, camera.fy * y, np.ones_like(depth)
    outside = [
        depth < camera.near,  # behind the near plane
        depth > camera.far,  # beyond the far plane
        scaled_x + camera.cx * scale < 0.0,  # left of the image: px < 0
        scaled_x - camera.cx * scale > 0.0,  # right of the image: px > W
        scaled_y - camera.cy * scale > 0.0,  # above the image: py < 0
        -scaled_y - camera.cy * scale > 0.0,  # below the image: py > H
    ]
    keep = np.ones(len(tri_camera), dtype=bool)
    for plane_outside in outside:
        keep &= ~np.all(plane_outside, axis=1)  # culled if all 3 corners are out
    if cull_back_faces:
        normal = np.cross(tri_camera[:, 1] - tri_camera[:, 0], tri_camera[:, 2] - tri_camera[:, 0])
        if camera.is_pinhole:
            facing = np.einsum("ij,ij->i", normal, tri_camera[:, 0]) < 0.0  # n . (P0 - eye) < 0
        else:
            facing = normal[:, 2] > 0.0  # n . (0, 0, -1) < 0
        keep &= facing
    return keep


def clip_near(
    tri_camera: np.ndarray, source: np.ndarray, near: float
) -> tuple[np.ndarray, np.ndarray]:
    """Clip triangles against the near plane ``z_camera = -near``.

    Parameters
    ----------
    tri_camera : (T, 3, 3) float64, camera-frame corners.
    source : (T,) int64, index each triangle reports as its source.
    near : float, near distance in meters.

    Returns
    -------
    clipped : (T', 3, 3) float64, corners all with z_camera <= -near.
    clipped_source : (T',) int64. Triangles fully in front pass unchanged, fully behind ones
        are dropped, one corner in front -> 1 triangle, two corners in front -> 2 triangles.
        Winding order is preserved.
    """
    inside = tri_camera[..., 2] <= -near  # (T, 3) corner in front of the near plane
    n_inside = inside.sum(axis=1)
    pieces, sources = [tri_camera[n_inside == 3]], [source[n_inside == 3]]
    for count in (1, 2):
        sel = np.flatnonzero(n_inside == count)
        if len(sel) == 0:
            continue
        # roll corners so the odd one (the lone inside / lone outside corner) comes first
        odd_flag = inside[sel] if count == 1 else ~inside[sel]
        first = np.argmax(odd_flag, axis=1)
        order = (first[:, None] + np.arange(3)[None, :]) % 3
        a, b, c = np.moveaxis(np.take_along_axis(tri_camera[sel], order[:, :, None], axis=1), 1, 0)
        if count == 1:  # a inside, b and c outside
            ab, ac = _near_point(a, b, near), _near_point(a, c, near)
            pieces.append(np.stack([a, ab, ac], axis=1))
            sources.append(source[sel])
        else:  # a outside, b and c inside: quad (ab, b, c, ac)
            ab, ac = _near_point(b, a, near), _near_point(c, a, near)
            pieces += [np.stack([ab, b, c], axis=1), np.stack([ab, c, ac], axis=1)]
            sources += [source[sel], source[sel]]
    return np.concatenate(pieces), np.concatenate(sources)


def _near_point(p_in: np.ndarray, p_out: np.ndarray, near: float) -> np.ndarray:
    """Point where segment inside->outside crosses z = -near, shape (n, 3).

    Always parameterized from the inside corner, so the two triangles sharing an edge
    compute the same point bit for bit: ``t = (-near - z_in) / (z_out - z_in)``.
    """
    t = (-near - p_in[:, 2]) / (p_out[:, 2] - p_in[:, 2])
    point = p_in + t[:, None] * (p_out - p_in)  # p = p_in + t (p_out - p_in)
    point[:, 2] = -near
    return point


def plane_coefficients(tri_camera: np.ndarray, camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """Affine screen functions ``(q_0, q_1, w)`` of each triangle (see module docstring).

    Each function is ``f(px, py) = A (px - cx) + B (py - cy) + C``.

    Returns
    -------
    planes : (T, 3, 3) float64, ``planes[t, f] = (A, B, C)`` for f in (q_0, q_1, w).
    valid : (T,) bool, False for edge-on triangles (plane through the eye, or zero area).
    """
    p0, p1, p2 = tri_camera[:, 0], tri_camera[:, 1], tri_camera[:, 2]
    if camera.is_pinhole:
        corners = (p0, p1, p2)
    else:  # orthographic: 2D homogeneous corners (x, y, 1)
        corners = tuple(np.column_stack([p[:, 0], p[:, 1], np.ones(len(p))]) for p in (p0, p1, p2))
    rows = [np.cross(corners[1], corners[2]), np.cross(corners[2], corners[0])]
    rows.append(np.cross(corners[0], corners[1]))
    det = np.einsum("ij,ij->i", corners[0], rows[0])  # det M = P0 . (P1 x P2)
    scale = np.prod([np.linalg.norm(c, axis=1) for c in corners], axis=0)
    valid = np.abs(det) > 1e-12 * scale
    inv_det = np.divide(1.0, det, out=np.zeros_like(det), where=valid)
    m = np.stack(rows, axis=1) * inv_det[:, None, None]  # (T, 3, 3) rows of M^-1
    planes = np.empty((len(tri_camera), 3, 3))
    if camera.is_pinhole:
        # q_k = m_k . r,  r = ((px - cx) / fx, -(py - cy) / fy, -1)
        coeffs = np.stack([m[..., 0] / camera.fx, -m[..., 1] / camera.fy, -m[..., 2]], axis=-1)
        planes[:, :2] = coeffs[:, :2]
        planes[:, 2] = coeffs.sum(axis=1)  # w = 1 / z = q_0 + q_1 + q_2
    else:
        # b_k = m_k . (u, v, 1),  u = (px - cx) / s,  v = -(py - cy) / s
        coeffs = np.stack([m[..., 0] / camera.fx, -m[..., 1] / camera.fy, m[..., 2]], axis=-1)
        planes[:, :2] = coeffs[:, :2]
        depth = -tri_camera[..., 2]  # (T, 3) corner z-depths
        planes[:, 2] = np.einsum("tkc,tk->tc", coeffs, depth)  # w = z = sum_k b_k z_k
    return planes, valid


def project_triangles(tri_camera: np.ndarray, camera: Camera) -> np.ndarray:
    """Continuous pixel coordinates of triangle corners, ``(T, 3, 2)`` float64."""
    pixels, _ = camera.project(tri_camera.reshape(-1, 3))
    return pixels.reshape(-1, 3, 2)


@dataclass
class Spans:
    """Horizontal pixel runs: row ``row[i]`` covers columns ``[col_first[i], +n_pixels[i])``.

    ``triangle[i]`` is the index (into the rasterized triangle list) owning the run.
    """

    triangle: np.ndarray
    row: np.ndarray
    col_first: np.ndarray
    n_pixels: np.ndarray


def scanline_spans(screen: np.ndarray, height: int, width: int) -> Spans:
    """Pixel rows and column runs covered by each triangle under the top-left rule.

    Parameters
    ----------
    screen : (T, 3, 2) float64, corner pixel coordinates ``(px, py)``.
    height, width : image size in pixels.
    """
    order = np.argsort(screen[:, :, 1], axis=1, kind="stable")
    v = np.take_along_axis(screen, order[:, :, None], axis=1)  # corners sorted top to bottom
    (x0, y0), (x1, y1), (x2, y2) = v[:, 0].T, v[:, 1].T, v[:, 2].T
    with np.errstate(divide="ignore", invalid="ignore"):
        slope02, slope01, slope12 = (
            (x2 - x0) / (y2 - y0),
            (x1 - x0) / (y1 - y0),
            (x2 - x1) / (y2 - y1),
        )
    # long edge 0->2 is on the left when the middle corner is right of it (cross < 0, y down)
    long_is_left = (x2 - x0) * (y1 - y0) - (y2 - y0) * (x1 - x0) < 0.0
    row_first = np.clip(np.ceil(y0 - 0.5), 0, height).astype(np.int64)  # first yc >= y0
    row_end = np.clip(np.ceil(y2 - 0.5), 0, height).astype(np.int64)  # first yc >= y2
    n_rows = np.maximum(row_end - row_first, 0)
    tri = np.repeat(np.arange(len(screen)), n_rows)
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


def depth_test_spans(
    spans: Spans,
    planes: np.ndarray,
    key_triangle: np.ndarray,
    camera: Camera,
    zkey: np.ndarray,
) -> int:
    """Expand spans into fragments and depth-test them into ``zkey`` in place.

    Parameters
    ----------
    spans : runs from ``scanline_spans``; ``spans.triangle`` indexes ``planes``.
    planes : (T, 3, 3) plane coefficients (of the rasterized triangles' sources).
    key_triangle : (T,) int, the triangle index stored in the z-buffer key.
    camera : the camera (pinhole: depth = 1 / w; ortho: depth = w).
    zkey : (H * W,) uint64, the z-buffer ``(float32 depth bits << 32) | triangle``.

    Returns
    -------
    n_fragments : int, number of fragments generated (for profiling).
    """
    width = camera.width
    w_plane = planes[spans.triangle, 2]  # (S, 3) coefficients of w
    xc = spans.col_first + 0.5 - camera.cx
    yc = spans.row + 0.5 - camera.cy
    w_first = (w_plane[:, 0] * xc + w_plane[:, 1] * yc + w_plane[:, 2]).astype(np.float32)
    w_step = w_plane[:, 0].astype(np.float32)  # dw / dpx along the row
    pixel_first = spans.row * width + spans.col_first
    tri_key = key_triangle[spans.triangle].astype(np.uint64)
    ends = np.cumsum(spans.n_pixels)
    cuts = np.searchsorted(
        ends, np.arange(FRAGMENT_CHUNK, ends[-1] if len(ends) else 0, FRAGMENT_CHUNK)
    )
    bounds = np.concatenate([[0], np.unique(cuts), [len(ends)]])
    for s0, s1 in zip(bounds[:-1], bounds[1:], strict=True):
        if s1 <= s0:
            continue
        counts = spans.n_pixels[s0:s1]
        starts = ends[s0:s1] - counts - (ends[s0 - 1] if s0 > 0 else 0)
        local = np.arange(int(counts.sum()), dtype=np.int64) - np.repeat(starts, counts)
        pixel = np.repeat(pixel_first[s0:s1], counts) + local  # pixel = row W + col
        w = np.repeat(w_step[s0:s1], counts) * local.astype(np.float32)  # float32 throughout
        w += np.repeat(w_first[s0:s1], counts)  # w(col) = w(col_first) + dw/dpx (col - col_first)
        depth = np.float32(1.0) / w if camera.is_pinhole else w  # z = 1 / w  or  z = w
        ok = (depth > 0.0) & (depth <= camera.far)
        key = depth.view(np.uint32).astype(np.uint64) << np.uint64(32)
        key |= np.repeat(tri_key[s0:s1], counts)
        np.minimum.at(zkey, pixel[ok], key[ok])  # z-test: keep the nearest per pixel
    return int(ends[-1]) if len(ends) else 0


@dataclass
class VisiblePixels:
    """The resolved z-buffer: one entry per covered pixel.

    pixel : (n,) int64 flat index ``row * W + col``.
    winner : (n,) int64 index of the nearest triangle (into the rasterized source list).
    depth : (n,) float32 z-depth in meters.
    xc, yc : (n,) float32 pixel-center coordinates relative to the principal point,
        ``col + 0.5 - cx`` and ``row + 0.5 - cy``.
    """

    pixel: np.ndarray
    winner: np.ndarray
    depth: np.ndarray
    xc: np.ndarray
    yc: np.ndarray

    def subset(self, sel: np.ndarray) -> VisiblePixels:
        """The entries ``sel`` (an index array)."""
        return VisiblePixels(
            *(getattr(self, f)[sel] for f in ("pixel", "winner", "depth", "xc", "yc"))
        )


def resolve_depth(zkey: np.ndarray, camera: Camera, band: slice | None = None) -> VisiblePixels:
    """Read the z-buffer back: covered pixels, winning triangle (low 32 bits of the key)
    and its depth (high 32 bits: the float32 depth's bit pattern).

    ``band`` restricts the read to a slice of flat pixel indices (a band of rows).
    """
    start = 0 if band is None else band.start
    keys = zkey if band is None else zkey[band]
    pixel = np.flatnonzero(keys != EMPTY_KEY)
    key = keys[pixel]
    pixel += start
    winner = (key & _LOW32).astype(np.int64)
    depth = (key >> np.uint64(32)).astype(np.uint32).view(np.float32)
    row, col = np.divmod(pixel.astype(np.int32), np.int32(camera.width))
    xc = col.astype(np.float32) + np.float32(0.5 - camera.cx)  # px - cx at the pixel center
    yc = row.astype(np.float32) + np.float32(0.5 - camera.cy)  # py - cy
    return VisiblePixels(pixel, winner, depth, xc, yc)


class AttributePlanes:
    """Perspective-correct interpolation of per-vertex attributes at pixel centers.

    Any attribute ``a`` with corner values ``a_k`` satisfies ``a / z = sum_k q_k a_k`` with
    ``q_k = b_k / z`` affine in pixel coordinates (module docstring), and
    ``q_2 = w - q_0 - q_1``, so ``a / z`` is itself affine::

        plane(a / z) = (a_0 - a_2) plane(q_0) + (a_1 - a_2) plane(q_1) + a_2 plane(w)

    and ``a = plane(a / z)(px, py) * z``. Orthographic: ``q_k = b_k``, ``sum_k b_k = 1`` so
    ``plane(1) = (0, 0, 1)`` replaces ``plane(w)`` and no multiplication by z is needed.

    Parameters
    ----------
    planes : (K, 3, 3) float64 plane functions ``(q_0, q_1, w)`` of K triangles.
    corner_values : (K, 3, C) float, the attribute at each triangle's 3 corners.
    camera : the camera (pinhole or orthographic).
    """

    def __init__(self, planes: np.ndarray, corner_values: np.ndarray, camera: Camera) -> None:
        a0, a1, a2 = (corner_values[:, k, :, None] for k in range(3))  # (K, C, 1)
        sum_plane = planes[:, None, 2] if camera.is_pinhole else np.array([0.0, 0.0, 1.0])
        attr = (a0 - a2) * planes[:, None, 0] + (a1 - a2) * planes[:, None, 1] + a2 * sum_plane
        # (C, 3, K) float32: each coefficient column contiguous for fast 1-D gathers
        self.coefficients = np.ascontiguousarray(np.moveaxis(attr, 0, -1), dtype=np.float32)
        self.multiply_by_depth = camera.is_pinhole

    def evaluate(self, visible: VisiblePixels) -> np.ndarray:
        """Attribute values at the visible pixels, ``(n, C)`` float32."""
        n_channels = self.coefficients.shape[0]
        out = np.empty((len(visible.pixel), n_channels), dtype=np.float32)
        for c in range(n_channels):
            a, b, k = (self.coefficients[c, j][visible.winner] for j in range(3))
            out[:, c] = a * visible.xc + b * visible.yc + k  # a/z = A (px-cx) + B (py-cy) + C
        if self.multiply_by_depth:
            out *= visible.depth[:, None]  # a = (a / z) * z
        return out
