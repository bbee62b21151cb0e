"""The textbook rasterizer, one triangle and one pixel at a time: a reference for the tests.

``render.frame.render_frame`` is fast because it works on whole arrays (spans, chunks,
64-bit z-buffer keys, packed 8-bit colors); this module computes the same color, depth and
semantic-id images with the plain loops and float arithmetic of graphics textbooks (and of
tinyrenderer's shaders), so that the two can be compared on small images. It is slow (pure
Python) and is not used by the engine. Its steps carry the numbers of ``render_frame``'s
stages (``render/__init__.py``):

1. vertex stage: ``P = camera_from_world @ world_from_mesh @ p``;

3. Sutherland-Hodgman clipping of the polygon against the near plane ``z_camera <= -near``,
   then a fan of triangles. Every corner carries its barycentric coordinates ``beta`` in the
   *original* triangle (the unit vectors for its own corners, interpolated along clipped
   edges), so attributes stay those of the unclipped triangle;
4. projection ``px = cx + fx x / z``, ``py = cy - fy y / z`` (``z`` = z-depth; orthographic:
   ``px = cx + s x``, ``py = cy - s y``);
5. for every pixel center ``p`` of the bounding box, the edge functions
   ``e_i(p) = (b - a) x (p - a)`` of the three edges ``(a, b)``; the center is inside when
   every ``e_i`` has the sign of the triangle's area, or is 0 on a *top* or *left* edge
   (top-left fill rule: the interior lies below a horizontal edge, or right of the edge);
6. screen-space barycentrics ``l_i = e_i / area``, the perspective-correct depth
   ``1 / z = sum_i l_i / z_i`` (orthographic: ``z = sum_i l_i z_i``) and z-test: the pixel
   keeps the smaller depth; on equal depths the earlier triangle stays;
7. per face its flat light factor (:func:`face_light`), per vertex of a Gouraud-shaded mesh
   its own (:func:`vertex_light`);
8. the fragment shader (:func:`fragment_color`) of the pixel that passed, with the
   perspective-correct barycentrics ``b = z sum_i l_i beta_i / z_i`` (orthographic:
   ``b = sum_i l_i beta_i``)::

       color = base * (sum_k b_k c_k) * texture(sum_k b_k uv_k) * light

   ``texture`` is bilinear between the four nearest texel centers in floats, wrapping;
   ``light = clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)`` with the face normal (or,
   for meshes with vertex normals, that formula per vertex, interpolated with ``b``).
   Stored as ``round(255 color)``; alpha 255.

The fast path quantizes on the way (8-bit texel weights, packed 8-bit products); the tests
hold it to this reference within a few levels of 255 per channel (``docs/rendering.md``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from render.camera import Camera, invert_rigid
from render.lights import DEFAULT_LIGHTS, Lights
from render.scene import RenderMesh

#: a polygon corner: camera-frame point and its barycentric coordinates in the source face
Corner = tuple[np.ndarray, np.ndarray]


def reference_frame(
    meshes: Sequence[RenderMesh], camera: Camera, world_from_camera: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Color ``(H, W, 4)`` uint8, depth ``(H, W)`` float64 (0 = nothing) and semantic ids
    ``(H, W)`` uint32, like ``render_frame`` (background opaque black)."""
    height, width = camera.resolution
    color = np.zeros((height, width, 3))
    depth = np.full((height, width), math.inf)
    ids = np.zeros((height, width), dtype=np.uint32)
    camera_from_world = invert_rigid(world_from_camera)
    for mesh in meshes:
        camera_from_mesh = camera_from_world @ mesh.world_from_mesh
        points = mesh.vertices @ camera_from_mesh[:3, :3].T + camera_from_mesh[:3, 3]
        face_lights = [face_light(mesh, f, world_from_camera) for f in range(len(mesh.faces))]
        vertex_lights = vertex_light(mesh, world_from_camera)
        for face_index, face in enumerate(mesh.faces):
            corners = [(points[i], np.eye(3)[k]) for k, i in enumerate(face)]
            polygon = _clip_near(corners, camera.near)
            for k in range(1, len(polygon) - 1):  # fan triangulation
                triangle = [polygon[0], polygon[k], polygon[k + 1]]
                for row, col, d, b in _fragments(triangle, camera):
                    if d < depth[row, col]:  # z-test; ties keep the earlier triangle
                        depth[row, col], ids[row, col] = d, mesh.semantic_id
                        color[row, col] = fragment_color(
                            mesh, face_index, b, face_lights[face_index], vertex_lights
                        )
    drawn = depth <= camera.far
    rgba = np.zeros((height, width, 4), dtype=np.uint8)
    rgba[..., :3] = np.where(drawn[..., None], np.rint(255.0 * color), 0.0)
    rgba[..., 3] = 255
    ids[~drawn] = 0
    depth[~drawn] = 0.0
    return rgba, depth, ids


def reference_depth_and_ids(
    meshes: Sequence[RenderMesh], camera: Camera, world_from_camera: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Depth ``(H, W)`` float64 (0 = nothing) and semantic ids ``(H, W)`` uint32."""
    _, depth, ids = reference_frame(meshes, camera, world_from_camera)
    return depth, ids


def fragment_color(
    mesh: RenderMesh,
    face_index: int,
    b: np.ndarray,
    face_light: float = 1.0,
    vertex_lights: np.ndarray | None = None,
) -> np.ndarray:
    """Stage 8 for one pixel: RGB in [0, 1] of ``mesh``'s face ``face_index`` at the
    perspective-correct barycentrics ``b`` (3,). ``face_light``: the face's flat light
    factor (1: unlit); ``vertex_lights`` (V,): the light factors of the vertices of a
    Gouraud-shaded mesh, which replace it (see the module docstring)."""
    face = mesh.faces[face_index]
    color = mesh.base_color[:3] / 255.0
    if mesh.vertex_colors is not None:
        color = color * (b @ (mesh.vertex_colors[face, :3] / 255.0))  # sum_k b_k c_k
    if mesh.texture is not None and mesh.uvs is not None:
        u, v = b @ mesh.uvs[face].astype(np.float64)  # sum_k b_k uv_k
        color = color * bilinear_texel(mesh.texture, u, v, mesh.uv_origin)
    if vertex_lights is not None:  # Gouraud: the vertices' light, interpolated
        return color * min(max(float(b @ vertex_lights[face]), 0.0), 1.0)
    return color * face_light


def bilinear_texel(texture: np.ndarray, u: float, v: float, uv_origin: str) -> np.ndarray:
    """RGB in [0, 1] between the four texel centers around ``(u, v)``, wrapping (REPEAT).

    Texel ``(i, j)`` is centered at ``x = j + 0.5``, ``y = i + 0.5`` with ``x = u w`` and
    ``y = (1 - v) h`` (``uv_origin="bottom"``) or ``y = v h`` (``"top"``).
    """
    h, w = texture.shape[:2]
    if uv_origin == "bottom":
        v = 1.0 - v  # image rows go down
    x, y = (u - math.floor(u)) * w - 0.5, (v - math.floor(v)) * h - 0.5
    j0, i0 = math.floor(x), math.floor(y)
    fx, fy = x - j0, y - i0  # weights of the right column and the lower row

    def texel(i: int, j: int) -> np.ndarray:
        return texture[i % h, j % w, :3] / 255.0

    top = (1 - fx) * texel(i0, j0) + fx * texel(i0, j0 + 1)
    bottom = (1 - fx) * texel(i0 + 1, j0) + fx * texel(i0 + 1, j0 + 1)
    return (1 - fy) * top + fy * bottom


def lambert(
    normal: np.ndarray, point: np.ndarray, lights: Lights, world_vectors: np.ndarray
) -> float:
    """``clamp(ambient + sum_k c_k max(0, n . l_k), 0, 1)`` at one world point (unit ``n``);
    ``l_k`` is the direction of a directional light or towards a point light."""
    if lights.is_flat:
        return 1.0
    length = np.linalg.norm(normal)
    n = normal / length if length > 0 else normal
    total = lights.ambient
    for (x, y, z, w), intensity in zip(world_vectors, lights.intensities, strict=True):
        to_light = np.array([x, y, z]) - (point if w == 1.0 else 0.0)
        distance = np.linalg.norm(to_light)
        if distance > 0:
            total += intensity * max(0.0, float(n @ to_light) / distance)
    return min(max(total, 0.0), 1.0)


def face_light(mesh: RenderMesh, face_index: int, world_from_camera: np.ndarray) -> float:
    """The flat light factor of a face (1 when unlit): :func:`lambert` at its centroid,
    normal ``(p1 - p0) x (p2 - p0)`` in the world frame."""
    if not mesh.lit:
        return 1.0
    lights = DEFAULT_LIGHTS if mesh.lights is None else mesh.lights
    corners = mesh.vertices[mesh.faces[face_index]] @ mesh.world_from_mesh[:3, :3].T
    corners = corners + mesh.world_from_mesh[:3, 3]
    normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    world = lights.in_world(world_from_camera, mesh.world_from_mesh)
    return lambert(normal, corners.mean(axis=0), lights, world)


def vertex_light(mesh: RenderMesh, world_from_camera: np.ndarray) -> np.ndarray | None:
    """Light factor per vertex ``(V,)`` of a lit mesh with normals (Gouraud), else None.
    Normals go to the world with the normal matrix ``(R^-1)^T``."""
    if not mesh.lit or mesh.normals is None:
        return None
    lights = DEFAULT_LIGHTS if mesh.lights is None else mesh.lights
    rotation, translation = mesh.world_from_mesh[:3, :3], mesh.world_from_mesh[:3, 3]
    normals = mesh.normals @ np.linalg.inv(rotation)  # rows: (R^-1)^T n
    points = mesh.vertices @ rotation.T + translation
    world = lights.in_world(world_from_camera, mesh.world_from_mesh)
    return np.array([lambert(n, p, lights, world) for n, p in zip(normals, points, strict=True)])


def _clip_near(polygon: list[Corner], near: float) -> list[Corner]:
    """Stage 3, Sutherland-Hodgman: the part of a convex polygon with ``z <= -near``;
    a crossing point gets the interpolated barycentrics of its edge."""
    clipped = []
    for i, (current, current_beta) in enumerate(polygon):
        previous, previous_beta = polygon[i - 1]
        current_in, previous_in = current[2] <= -near, previous[2] <= -near
        if current_in != previous_in:  # the edge crosses the plane: add the crossing
            t = (-near - previous[2]) / (current[2] - previous[2])
            crossing = previous + t * (current - previous)
            crossing[2] = -near
            clipped.append((crossing, previous_beta + t * (current_beta - previous_beta)))
        if current_in:
            clipped.append((current, current_beta))
    return clipped


def _fragments(triangle: list[Corner], camera: Camera):
    """Stages 4-6 for one camera-frame triangle: yields ``(row, col, depth, b)`` of every
    covered pixel center, ``b`` the perspective-correct barycentrics in the source face."""
    z = [-p[2] for p, _ in triangle]
    betas = [beta for _, beta in triangle]
    if camera.is_pinhole:
        screen = [
            (camera.cx + camera.fx * p[0] / d, camera.cy - camera.fy * p[1] / d)
            for (p, _), d in zip(triangle, z, strict=True)
        ]
    else:
        screen = [(camera.cx + camera.fx * p[0], camera.cy - camera.fy * p[1]) for p, _ in triangle]
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
                b = d * sum(w / zi * beta for w, zi, beta in zip(weights, z, betas, strict=True))
            else:
                d = sum(w * zi for w, zi in zip(weights, z, strict=True))
                b = sum(w * beta for w, beta in zip(weights, betas, strict=True))
            yield row, col, d, b


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
