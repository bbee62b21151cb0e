"""Small mesh-building kit for the generated demo dataset (boxes, lathes, GLB export).

The demo apartment and objects are assembled from colored parts. A :class:`Part` is one
triangle mesh with either per-vertex RGBA colors or a texture with UVs; parts that share
a color style are merged, and :func:`write_glb` writes them as one binary glTF file with
``trimesh``, byte-for-byte the same on every run (no randomness, no timestamps).

Stages are drawn unlit (Habitat draws the stage flat), so stage parts may *bake* a fixed
light into their vertex colors: each face is multiplied by a factor that depends on the
direction its normal points (:data:`BAKED_LIGHT`), which keeps corners and edges legible.

Conventions: Y up, meters, faces counter-clockwise seen from outside. UVs use the
OpenGL convention of ``engine.scene.assets``: texel row = ``(1 - v) * (h - 1)``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import trimesh
from numpy.typing import ArrayLike
from PIL import Image

from engine.scene.primitives import box_geometry, concatenate_geometry, lathe

# Brightness factor of a face whose unit normal is mostly +X, -X, +Y, -Y, +Z, -Z.
BAKED_LIGHT = {(0, 1): 0.88, (0, -1): 0.80, (1, 1): 1.0, (1, -1): 0.72, (2, 1): 0.94, (2, -1): 0.84}


@dataclasses.dataclass
class Part:
    """One mesh piece: ``vertices (V, 3)``, ``faces (F, 3)`` and its appearance.

    Exactly one of ``colors`` (``(V, 4)`` uint8) or ``uvs`` (``(V, 2)``) + ``texture``
    (``(h, w, 3 or 4)`` uint8 image) is set.
    """

    vertices: np.ndarray
    faces: np.ndarray
    colors: np.ndarray | None = None
    uvs: np.ndarray | None = None
    texture: np.ndarray | None = None
    name: str = "part"


def rgba(color: tuple[int, ...]) -> np.ndarray:
    """``(r, g, b)`` or ``(r, g, b, a)`` bytes -> ``(4,)`` uint8 with alpha 255 by default."""
    out = np.full(4, 255, dtype=np.uint8)
    out[: len(color)] = color
    return out


def box(
    lo: tuple[float, float, float] | np.ndarray,
    hi: tuple[float, float, float] | np.ndarray,
    color: tuple[int, ...],
    bake_light: bool = False,
    name: str = "box",
) -> Part:
    """Axis-aligned box between corners ``lo`` and ``hi`` (meters), one flat color."""
    lo_arr, hi_arr = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    if np.any(hi_arr <= lo_arr):
        raise ValueError(f"box {name!r}: hi {hi} must exceed lo {lo} on every axis")
    vertices, faces = box_geometry(0.5 * (lo_arr + hi_arr), hi_arr - lo_arr)
    colors = np.tile(rgba(color), (len(vertices), 1))
    part = Part(vertices, faces, colors=colors, name=name)
    return bake(part) if bake_light else part


def quad(corners: np.ndarray, color: tuple[int, ...], name: str = "quad") -> Part:
    """One flat quad from 4 corners ``(4, 3)`` in counter-clockwise order (front side)."""
    corners = np.asarray(corners, dtype=np.float64)
    faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
    return Part(corners, faces, colors=np.tile(rgba(color), (4, 1)), name=name)


def horizontal_quad(
    x0: float, x1: float, z0: float, z1: float, y: float, color: tuple[int, ...], up: bool = True
) -> Part:
    """Quad in the plane ``y`` over ``[x0, x1] x [z0, z1]``, facing +Y (or -Y)."""
    corners = np.array([[x0, y, z1], [x1, y, z1], [x1, y, z0], [x0, y, z0]])  # CCW from +Y
    return quad(corners if up else corners[::-1], color, name="floor" if up else "ceiling")


def lathe_part(
    radii: ArrayLike,
    heights: ArrayLike,
    segments: int,
    color: tuple[int, ...],
    center: tuple[float, float, float] = (0.0, 0.0, 0.0),
    axis: str = "y",
    name: str = "lathe",
) -> Part:
    """Surface of revolution (see ``engine.scene.primitives.lathe``) around an axis through
    ``center``; ``axis`` "y" keeps it vertical, "x" or "z" lays it along that axis."""
    vertices, faces = lathe(np.asarray(radii, float), np.asarray(heights, float), segments)
    vertices = vertices @ _AXIS_FROM_Y[axis].T + np.asarray(center, dtype=np.float64)
    return Part(vertices, faces, colors=np.tile(rgba(color), (len(vertices), 1)), name=name)


def cylinder(
    center: tuple[float, float, float],
    radius: float,
    half_length: float,
    color: tuple[int, ...],
    segments: int = 24,
    axis: str = "y",
    name: str = "cylinder",
) -> Part:
    """Closed cylinder (side and both caps) of ``radius`` around ``axis`` through ``center``."""
    r = np.array([0.0, radius, radius, radius, radius, 0.0])
    h = np.array([-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]) * half_length
    # bottom cap (0 -> r), side (-h -> h), top cap (r -> 0): separate rings keep edges sharp
    parts = [
        lathe_part(r[k : k + 2], h[k : k + 2], segments, color, center, axis) for k in (0, 2, 4)
    ]
    return merge_parts(parts, name=name)


# Rotations taking the lathe's +Y axis to the requested axis (right-handed, det +1).
_AXIS_FROM_Y = {
    "y": np.eye(3),
    "x": np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),  # y -> x
    "z": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),  # y -> z
}


def bake(part: Part) -> Part:
    """Multiply each face's color by :data:`BAKED_LIGHT` for its dominant normal axis.

    Faces must not share vertices across differently lit sides (boxes from :func:`box`
    own 4 vertices per side), since the factor is written per vertex.
    """
    if part.colors is None:
        return part
    triangles = part.vertices[part.faces]  # (F, 3, 3)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    axis = np.argmax(np.abs(normals), axis=1)
    sign = np.sign(normals[np.arange(len(normals)), axis]).astype(int)
    light = np.array([BAKED_LIGHT[(int(a), int(s) or 1)] for a, s in zip(axis, sign, strict=True)])
    vertex_light = np.ones(len(part.vertices))
    vertex_light[part.faces.ravel()] = np.repeat(light, 3)  # each vertex takes its face's light
    colors = part.colors.astype(np.float64)
    colors[:, :3] = np.round(colors[:, :3] * vertex_light[:, None])  # c' = round(c * light)
    return dataclasses.replace(part, colors=colors.astype(np.uint8))


def merge_parts(parts: list[Part], name: str) -> Part:
    """Merge vertex-colored parts into one part (faces re-indexed)."""
    if any(p.colors is None for p in parts):
        raise ValueError(f"merge_parts {name!r}: only vertex-colored parts can be merged")
    vertices, faces = concatenate_geometry([(p.vertices, p.faces) for p in parts])
    colors = np.concatenate([p.colors for p in parts]).astype(np.uint8)
    return Part(vertices, faces, colors=colors, name=name)


def tube(
    spine: np.ndarray,
    radii: np.ndarray,
    plane_normal: tuple[float, float, float],
    segments: int,
    color: tuple[int, ...],
    name: str = "tube",
) -> Part:
    """Closed tube of varying radius swept along a planar polyline.

    Ring ``i`` is the circle ``p_i + r_i (cos(phi) n_i + sin(phi) b)`` where ``b`` is the unit
    ``plane_normal`` of the spine's plane, ``t_i`` the spine tangent and ``n_i = t_i x b``.
    The ends are closed by triangle fans around the end points.

    Parameters
    ----------
    spine : (N, 3) float, points in the plane, N >= 2, meters.
    radii : (N,) float, tube radius at each point, meters (> 0).
    """
    spine = np.asarray(spine, dtype=np.float64)
    b = np.asarray(plane_normal, dtype=np.float64) / np.linalg.norm(plane_normal)
    tangent = np.gradient(spine, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.cross(tangent, b)  # n_i = t_i x b, in the plane
    phi = 2.0 * np.pi * np.arange(segments) / segments
    offsets = np.cos(phi)[None, :, None] * normal[:, None, :] + np.sin(phi)[None, :, None] * b
    rings = spine[:, None, :] + np.asarray(radii)[:, None, None] * offsets  # (N, S, 3)
    n_rings = len(spine)
    vertices = np.concatenate([rings.reshape(-1, 3), spine[[0, -1]]])
    j, j_next = np.arange(segments), (np.arange(segments) + 1) % segments
    faces = []
    for i in range(n_rings - 1):
        lo, hi = i * segments, (i + 1) * segments
        faces.append(np.stack([lo + j, hi + j, hi + j_next], 1))
        faces.append(np.stack([lo + j, hi + j_next, lo + j_next], 1))
    start, end = n_rings * segments, n_rings * segments + 1
    last = (n_rings - 1) * segments
    faces += [np.stack([np.full(segments, start), j_next, j], 1)]
    faces += [np.stack([np.full(segments, end), last + j, last + j_next], 1)]
    colors = np.tile(rgba(color), (len(vertices), 1))
    return Part(vertices, np.concatenate(faces).astype(np.int64), colors=colors, name=name)


def write_glb(parts: list[Part], path: Path) -> None:
    """Write parts as one binary glTF (one node and mesh per part, named after it).

    Vertex-colored parts become ``COLOR_0`` with a white unlit-friendly PBR material;
    textured parts carry their image as the base-color texture. The bytes depend only on
    the parts, so generation is reproducible.
    """
    scene = trimesh.Scene()
    names: set[str] = set()
    for index, part in enumerate(parts):
        name = part.name if part.name not in names else f"{part.name}_{index}"
        names.add(name)
        mesh = trimesh.Trimesh(part.vertices, part.faces, process=False, visual=_visual(part))
        scene.add_geometry(mesh, node_name=name, geom_name=name)
    path.write_bytes(scene.export(file_type="glb"))


def _visual(part: Part) -> trimesh.visual.ColorVisuals | trimesh.visual.TextureVisuals:
    """trimesh appearance of a part: vertex colors, or a PBR material with a texture."""
    if part.texture is not None and part.uvs is not None:
        material = trimesh.visual.material.PBRMaterial(
            baseColorTexture=Image.fromarray(np.asarray(part.texture, dtype=np.uint8)),
            baseColorFactor=[255, 255, 255, 255],
            metallicFactor=0.0,
            roughnessFactor=1.0,
        )
        return trimesh.visual.TextureVisuals(uv=np.asarray(part.uvs), material=material)
    if part.colors is None:
        raise ValueError(f"part {part.name!r} has neither colors nor a texture")
    return trimesh.visual.ColorVisuals(vertex_colors=np.asarray(part.colors, dtype=np.uint8))
