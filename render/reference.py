"""The textbook rasterizer, one triangle and one pixel at a time: a reference for the tests.

``render.frame.render_frame`` is fast because it works on whole arrays (spans, chunks,
64-bit z-buffer keys); this module computes the same depth and semantic-id images with the
plain loops found in graphics textbooks, so that the two can be compared on small images.
It is slow (pure Python) and is not used by the engine.

Per triangle:

1. camera frame: ``P = camera_from_world @ world_from_mesh @ p``;
2. Sutherland-Hodgman clipping of the polygon against the near plane ``z_camera <= -near``,
   then a fan of triangles;
3. projection ``px = cx + fx x / z``, ``py = cy - fy y / z`` (``z`` = z-depth; orthographic:
   ``px = cx + s x``, ``py = cy - s y``);
4. for every pixel center ``p`` of the bounding box, the edge functions
   ``e_i(p) = (b - a) x (p - a)`` of the three edges ``(a, b)``; the center is inside when
   every ``e_i`` has the sign of the triangle's area, or is 0 on a *top* or *left* edge
   (top-left fill rule: the interior lies below a horizontal edge, or right of the edge);
5. screen-space barycentrics ``l_i = e_i / area`` and the perspective-correct depth
   ``1 / z = sum_i l_i / z_i`` (orthographic: ``z = sum_i l_i z_i``);
6. z-test: the pixel keeps the smaller depth; on equal depths the earlier triangle stays.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from render.camera import Camera, invert_rigid
from render.scene import RenderMesh


def reference_depth_and_ids(
    meshes: Sequence[RenderMesh], camera: Camera, world_from_camera: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Depth ``(H, W)`` float64 (0 = nothing) and semantic ids ``(H, W)`` uint32."""
    height, width = camera.resolution
    depth = np.full((height, width), math.inf)
    ids = np.zeros((height, width), dtype=np.uint32)
    camera_from_world = invert_rigid(world_from_camera)
    for mesh in meshes:
        camera_from_mesh = camera_from_world @ mesh.world_from_mesh
        points = mesh.vertices @ camera_from_mesh[:3, :3].T + camera_from_mesh[:3, 3]
        for face in mesh.faces:
            polygon = _clip_near([points[i] for i in face], camera.near)
            for k in range(1, len(polygon) - 1):  # fan triangulation
                corners = [polygon[0], polygon[k], polygon[k + 1]]
                _draw_triangle(corners, camera, mesh.semantic_id, depth, ids)
    depth[depth > camera.far] = math.inf
    ids[np.isinf(depth)] = 0
    depth[np.isinf(depth)] = 0.0
    return depth, ids


def _clip_near(polygon: list[np.ndarray], near: float) -> list[np.ndarray]:
    """Sutherland-Hodgman: the part of a convex polygon with ``z <= -near``."""
    clipped = []
    for i, current in enumerate(polygon):
        previous = polygon[i - 1]
        current_in, previous_in = current[2] <= -near, previous[2] <= -near
        if current_in != previous_in:  # the edge crosses the plane: add the crossing
            t = (-near - previous[2]) / (current[2] - previous[2])
            crossing = previous + t * (current - previous)
            crossing[2] = -near
            clipped.append(crossing)
        if current_in:
            clipped.append(current)
    return clipped


def _draw_triangle(corners, camera: Camera, semantic_id: int, depth, ids) -> None:
    """Steps 3-6 of the module docstring for one camera-frame triangle."""
    z = [-p[2] for p in corners]
    if camera.is_pinhole:
        screen = [
            (camera.cx + camera.fx * p[0] / d, camera.cy - camera.fy * p[1] / d)
            for p, d in zip(corners, z, strict=True)
        ]
    else:
        screen = [(camera.cx + camera.fx * p[0], camera.cy - camera.fy * p[1]) for p in corners]
    area = _edge(screen[0], screen[1], screen[2])
    if area == 0.0:
        return
    edges = [(screen[i], screen[(i + 1) % 3], screen[(i + 2) % 3]) for i in range(3)]
    inclusive = [_is_top_or_left(a, b, c) for a, b, c in edges]
    xs, ys = [s[0] for s in screen], [s[1] for s in screen]
    rows = range(max(0, math.ceil(min(ys) - 0.5)), min(camera.height, math.ceil(max(ys) - 0.5)))
    cols = range(max(0, math.ceil(min(xs) - 0.5)), min(camera.width, math.ceil(max(xs) - 0.5)))
    for row in rows:
        for col in cols:
            p = (col + 0.5, row + 0.5)
            e = [_edge(a, b, p) * math.copysign(1.0, area) for a, b, _ in edges]
            if not all(v > 0 or (v == 0 and inc) for v, inc in zip(e, inclusive, strict=True)):
                continue
            weights = [e[(i + 1) % 3] / abs(area) for i in range(3)]  # l_i: opposite edge
            if camera.is_pinhole:
                d = 1.0 / sum(w / zi for w, zi in zip(weights, z, strict=True))  # 1/z interp
            else:
                d = sum(w * zi for w, zi in zip(weights, z, strict=True))
            if d < depth[row, col]:
                depth[row, col], ids[row, col] = d, semantic_id


def _edge(a, b, p) -> float:
    """Edge function ``(b - a) x (p - a)`` (twice the signed area of a, b, p)."""
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])


def _is_top_or_left(a, b, c) -> bool:
    """True when the triangle (with third corner ``c``) lies below a horizontal edge
    ``(a, b)`` (a top edge, y down) or right of a non-horizontal one (a left edge)."""
    if a[1] == b[1]:
        return c[1] > a[1]
    x_on_edge = a[0] + (c[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
    return c[0] > x_on_edge
