"""Culling and near-plane clipping: which triangles reach the rasterizer, and in what pieces.

Layout: a batch of T triangles is one array ``tri`` of shape ``(3, 3, T)`` indexed
``tri[corner, coordinate, triangle]`` (camera frame, meters), so every ``tri[k, c]`` is a
contiguous ``(T,)`` array. NumPy is fast on long 1-D arrays and slow on small axes
(a reduction over an axis of length 3 costs ~40 ns per row), so all per-triangle math here
and in ``render.raster`` is written on these 1-D columns.

Stages 2-3 (numbered as in ``render_frame``, ``render/__init__.py``)
--------------------------------------------------------------------
2. ``vertex_outcodes`` / ``triangles_in_frustum``: Cohen-Sutherland outcodes. Each vertex
   gets one bit per frustum plane it lies outside of; a triangle whose three corners share
   a bit lies entirely outside that plane and is dropped. Pinhole side planes pass through
   the eye: ``px < 0 <=> cx + fx x / z < 0 <=> fx x + cx z < 0`` with z = -z_camera.

3. ``front_facing`` (optional back-face culling): counter-clockwise corners seen from the
   eye, i.e. ``n . (P0 - eye) < 0`` with ``n = (P1 - P0) x (P2 - P0)``.

3. ``clip_near``: Sutherland-Hodgman against the plane ``z_camera = -near`` for one plane:
   one corner in front -> 1 triangle, two corners in front -> a quad = 2 triangles.
"""

from __future__ import annotations

import numpy as np

from render.camera import Camera

OUT_NEAR, OUT_FAR, OUT_LEFT, OUT_RIGHT, OUT_TOP, OUT_BOTTOM = (1 << i for i in range(6))


def cross(a: tuple, b: tuple) -> tuple:
    """Cross product of two vectors given as 3 coordinate arrays each: ``a x b``."""
    ax, ay, az = a
    bx, by, bz = b
    return (ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)


def vertex_outcodes(vertices_camera: np.ndarray, camera: Camera) -> np.ndarray:
    """Frustum outcodes of vertices.

    Parameters
    ----------
    vertices_camera : (3, V) float64, camera-frame coordinates (rows x, y, z).
    camera : the camera.

    Returns
    -------
    (V,) uint8, bit ``OUT_*`` set when the vertex is outside that plane.
    """
    x, y, z = vertices_camera
    depth = -z  # z-depth
    scale = depth if camera.is_pinhole else np.ones_like(depth)  # ortho planes are fixed
    fx_x, fy_y = camera.fx * x, camera.fy * y
    tests = (
        (OUT_NEAR, depth < camera.near),
        (OUT_FAR, depth > camera.far),
        (OUT_LEFT, fx_x + camera.cx * scale < 0.0),  # px < 0
        (OUT_RIGHT, fx_x - camera.cx * scale > 0.0),  # px > W
        (OUT_TOP, fy_y - camera.cy * scale > 0.0),  # py < 0
        (OUT_BOTTOM, -fy_y - camera.cy * scale > 0.0),  # py > H
    )
    code = np.zeros(len(depth), dtype=np.uint8)
    for bit, outside in tests:
        code |= outside.view(np.uint8) * np.uint8(bit)
    return code


def triangles_in_frustum(outcodes: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """``(T,)`` bool: False when all 3 corners are outside one common plane.

    ``faces`` is ``(3, T)`` vertex ids (corner-major).
    """
    common = outcodes[faces[0]] & outcodes[faces[1]] & outcodes[faces[2]]  # shared out-bits
    return common == 0


def front_facing(tri: np.ndarray, camera: Camera) -> np.ndarray:
    """``(T,)`` bool: the counter-clockwise front face of each triangle faces the camera."""
    normal = cross(tri[1] - tri[0], tri[2] - tri[0])
    if camera.is_pinhole:
        p0 = tri[0]
        return normal[0] * p0[0] + normal[1] * p0[1] + normal[2] * p0[2] < 0.0  # n . P0 < 0
    return normal[2] > 0.0  # n . (0, 0, -1) < 0


def clip_near(tri: np.ndarray, source: np.ndarray, near: float) -> tuple[np.ndarray, np.ndarray]:
    """Clip triangles against the near plane ``z_camera = -near``.

    Parameters
    ----------
    tri : (3, 3, T) float64, camera-frame corners (corner, coordinate, triangle).
    source : (T,) int64, index each triangle reports as its source.
    near : float, near distance in meters.

    Returns
    -------
    clipped : (3, 3, T') float64, corners all with z_camera <= -near.
    clipped_source : (T',) int64. Triangles fully in front pass unchanged, fully behind ones
        are dropped, one corner in front -> 1 triangle, two corners in front -> 2 triangles.
        Winding order is preserved.
    """
    inside = tri[:, 2, :] <= -near  # (3, T): corner in front of the near plane
    n_inside = inside[0].astype(np.int8) + inside[1] + inside[2]
    all_in = np.flatnonzero(n_inside == 3)
    if len(all_in) == len(source):
        return tri, source  # the common case: nothing crosses the near plane
    pieces, sources = [tri[:, :, all_in]], [source[all_in]]
    for count in (1, 2):
        sel = np.flatnonzero(n_inside == count)
        if len(sel) == 0:
            continue
        # roll the corners so the odd one (lone inside / lone outside corner) comes first
        odd = inside[:, sel] if count == 1 else ~inside[:, sel]
        first = np.where(odd[0], 0, np.where(odd[1], 1, 2))
        order = (first[None, :] + np.arange(3)[:, None]) % 3  # (3, n)
        a, b, c = np.take_along_axis(tri[:, :, sel], order[:, None, :], axis=0)
        if count == 1:  # a inside, b and c outside: triangle (a, ab, ac)
            ab, ac = _near_point(a, b, near), _near_point(a, c, near)
            pieces.append(np.stack([a, ab, ac]))
            sources.append(source[sel])
        else:  # a outside, b and c inside: quad (ab, b, c, ac) = 2 triangles
            ab, ac = _near_point(b, a, near), _near_point(c, a, near)
            pieces += [np.stack([ab, b, c]), np.stack([ab, c, ac])]
            sources += [source[sel], source[sel]]
    return np.concatenate(pieces, axis=2), np.concatenate(sources)


def _near_point(p_in: np.ndarray, p_out: np.ndarray, near: float) -> np.ndarray:
    """Where segment inside->outside crosses z = -near, ``(3, n)``.

    Always parameterized from the inside corner, so the two triangles sharing an edge
    compute the same point bit for bit: ``t = (-near - z_in) / (z_out - z_in)``.
    """
    t = (-near - p_in[2]) / (p_out[2] - p_in[2])
    point = p_in + t * (p_out - p_in)  # p = p_in + t (p_out - p_in)
    point[2] = -near
    return point
