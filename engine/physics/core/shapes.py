"""Collision shapes: python-fcl geometry plus the few arrays our own contact code needs.

A body owns one or more :class:`Shape` objects. Each shape stores

* ``geometry``: the fcl geometry used by the narrow phase (exact ``Box``, ``Sphere``,
  ``Cylinder``, ``Cone``, ``Capsule`` for primitive collision assets, ``Convex`` hulls for
  mesh objects, a ``BVHModel`` triangle mesh for the static stage);
* ``body_from_shape``: ``(4, 4)`` pose of the shape in the body frame (fcl's round shapes
  are built along their local Z axis, Habitat's primitives along Y, so round primitives get
  a fixed -90 degree rotation about X);
* ``hull_vertices``: ``(m, 3)`` support points in the body frame (meters) used for AABBs
  and for vertex-versus-triangle contacts with the stage;
* ``ray_triangles``: ``(t, 3, 3)`` triangles in the body frame used by ray casts (spheres
  are intersected analytically instead).

Mass properties follow the textbook formulas for a uniform density body
(e.g. box: ``I_xx = m (b^2 + c^2) / 3`` with half extents a, b, c); hulls use trimesh's
exact polyhedral integrals (Mirtich 1996). Frames: Y up, meters, kilograms.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

import fcl
import numpy as np
import trimesh

from .settings import (
    FLAT_HULL_RATIO,
    FLAT_HULL_THICKNESS,
    MIN_HULL_VOLUME,
    MIN_INERTIA_VOLUME,
    PROBE_MIN_OFFSET,
)

#: segments used to tessellate round primitives for ray casts and vertex contacts.
ROUND_SEGMENTS = 24

#: rotation taking fcl's Z-axis round shapes to Habitat's Y-axis primitives.
Z_TO_Y = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


class ShapeKind(str, Enum):
    """What a collision shape is; the contact pair table (:mod:`pair_table`) picks a pair's
    contact rule by the two kinds. A member equals its string (``ShapeKind.BOX == "box"``)."""

    MESH = "mesh"  # the static stage: a triangle mesh (fcl BVHModel)
    BOX = "box"
    CONVEX = "convex"  # a convex hull (mesh objects, non-uniformly scaled round primitives)
    CYLINDER = "cylinder"
    CONE = "cone"
    SPHERE = "sphere"
    CAPSULE = "capsule"


#: the kinds with hull vertices and face planes (vertex and face contacts)
POLYHEDRA: frozenset[ShapeKind] = frozenset(
    {ShapeKind.BOX, ShapeKind.CONVEX, ShapeKind.CYLINDER, ShapeKind.CONE}
)
#: the kinds described by a radius around a point or a segment
ROUND: frozenset[ShapeKind] = frozenset({ShapeKind.SPHERE, ShapeKind.CAPSULE})


@dataclass
class Shape:
    """One collision shape of a body (see the module docstring for the fields)."""

    kind: ShapeKind
    geometry: Any  # an fcl geometry (Box, Sphere, Cylinder, Cone, Capsule, Convex, BVHModel)
    body_from_shape: np.ndarray
    hull_vertices: np.ndarray
    ray_triangles: np.ndarray
    radius: float = 0.0
    faces: np.ndarray | None = field(default=None, repr=False)
    plane_normals: np.ndarray | None = field(default=None, repr=False)
    plane_offsets: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        """Plain float64 arrays (trimesh's tracked arrays are slow to index), and the hull's
        outward face planes ``n . x <= c`` (body frame), for containment tests."""
        self.kind = ShapeKind(self.kind)  # ValueError naming an unknown kind
        self.hull_vertices = np.array(self.hull_vertices, dtype=np.float64)
        self.ray_triangles = np.array(self.ray_triangles, dtype=np.float64)
        if self.kind == ShapeKind.MESH or self.kind in ROUND:
            return
        hull = trimesh.convex.convex_hull(self.hull_vertices)
        self.plane_normals = np.array(hull.face_normals, dtype=np.float64)
        # c_f = n_f . (a vertex of face f)
        corner = np.array(hull.vertices, dtype=np.float64)[hull.faces[:, 0]]
        self.plane_offsets = np.sum(self.plane_normals * corner, axis=1)

    @property
    def min_half_extent(self) -> float:
        """Smallest half extent of the shape's body-frame AABB, meters."""
        extent = self.hull_vertices.max(0) - self.hull_vertices.min(0)
        return float(extent.min() / 2.0)


def probe_geometry(shape: Shape, margin: float):
    """fcl geometry of ``shape`` grown by ``margin`` meters (same frame as the shape).

    Used only to *find* stage triangles within ``margin`` of the body (speculative contacts);
    the contact points themselves are computed exactly. Hulls grow radially from their
    centroid (a conservative approximation).
    """
    g = shape.geometry
    if shape.kind == ShapeKind.BOX:
        return fcl.Box(*(np.asarray(g.side, dtype=np.float64) + 2 * margin))
    if shape.kind == ShapeKind.SPHERE:
        return fcl.Sphere(shape.radius + margin)
    if shape.kind in (ShapeKind.CYLINDER, ShapeKind.CONE):
        extent = shape.hull_vertices.max(0) - shape.hull_vertices.min(0)
        radius, length = extent[0] / 2 + margin, extent[1] + 2 * margin
        return (fcl.Cylinder if shape.kind == ShapeKind.CYLINDER else fcl.Cone)(radius, length)
    if shape.kind == ShapeKind.CAPSULE:
        return fcl.Capsule(g.radius + margin, g.lz)
    center = shape.hull_vertices.mean(0)
    offset = shape.hull_vertices - center
    grown = shape.hull_vertices + margin * offset / np.maximum(
        np.linalg.norm(offset, axis=1, keepdims=True), PROBE_MIN_OFFSET
    )
    return convex_shape(grown, "probe").geometry


def validate_mesh(vertices: np.ndarray, faces: np.ndarray, name: str) -> tuple:
    """Check a triangle mesh before it reaches fcl (empty meshes crash the interpreter).

    Parameters
    ----------
    vertices : (V, 3) float, meters.
    faces : (F, 3) int, indices into ``vertices``.
    name : str, used in the error message.

    Returns
    -------
    (vertices float64 (V, 3), faces int64 (F, 3))
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or len(vertices) < 3:
        raise ValueError(f"{name}: vertices must be (V>=3, 3), got shape {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) < 1:
        raise ValueError(f"{name}: faces must be (F>=1, 3), got shape {faces.shape}")
    if not np.all(np.isfinite(vertices)):
        raise ValueError(f"{name}: vertices contain NaN or inf")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise ValueError(f"{name}: face index out of range [0, {len(vertices)})")
    return vertices, faces


def _pose(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = translation
    return pose


def _round_shape(kind: ShapeKind, geometry, mesh: trimesh.Trimesh, center: np.ndarray) -> Shape:
    """Wrap an fcl round shape built along Z; ``mesh`` is its Y-axis tessellation."""
    return Shape(
        kind,
        geometry,
        _pose(Z_TO_Y, center),
        mesh.vertices + center,
        mesh.vertices[mesh.faces] + center,
    )


def primitive_shape(handle: str, scale: np.ndarray, center: np.ndarray) -> Shape:
    """Exact fcl primitive for a Magnum primitive handle (``cubeSolid``, ``icosphereSolid_*``...).

    Magnum's unit primitives: cube [-1, 1]^3, sphere radius 1, cylinder/cone/capsule of
    radius 1 along Y with the half length in ``halfLen_<x>`` (1 when absent). A non-uniform
    scale of a round primitive is not a primitive any more: it becomes a convex hull.

    Parameters
    ----------
    handle : str, Magnum primitive handle.
    scale : (3,) float, template scale.
    center : (3,) float, shape center in the body frame (meters), usually ``-COM``.
    """
    scale = np.asarray(scale, dtype=np.float64)
    match = re.search(r"halfLen_([0-9.]+)", handle)
    half_length = float(match.group(1)) if match else 1.0
    if handle.startswith("cube"):
        half = scale.copy()
        mesh = trimesh.creation.box(extents=2 * half)
        return Shape(
            ShapeKind.BOX,
            fcl.Box(*(2 * half)),
            _pose(np.eye(3), center),
            mesh.vertices + center,
            mesh.vertices[mesh.faces] + center,
        )
    uniform = np.allclose(scale, scale[0])
    if handle.startswith(("icosphere", "uvSphere")) and uniform:
        radius = float(scale[0])
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=radius)
        shape = Shape(
            ShapeKind.SPHERE,
            fcl.Sphere(radius),
            _pose(np.eye(3), center),
            mesh.vertices + center,
            mesh.vertices[mesh.faces] + center,
            radius,
        )
        return shape
    radius, half_y = float(scale[0]), half_length * float(scale[1])
    if handle.startswith("cylinder") and np.isclose(scale[0], scale[2]):
        mesh = trimesh.creation.cylinder(radius, 2 * half_y, sections=ROUND_SEGMENTS)
        mesh.apply_transform(_pose(Z_TO_Y, np.zeros(3)))
        return _round_shape(ShapeKind.CYLINDER, fcl.Cylinder(radius, 2 * half_y), mesh, center)
    if handle.startswith("cone") and np.isclose(scale[0], scale[2]):
        mesh = trimesh.creation.cone(radius, 2 * half_y, sections=ROUND_SEGMENTS)
        mesh.apply_translation([0, 0, -half_y])  # trimesh's cone starts at z = 0
        mesh.apply_transform(_pose(Z_TO_Y, np.zeros(3)))
        return _round_shape(ShapeKind.CONE, fcl.Cone(radius, 2 * half_y), mesh, center)
    if handle.startswith("capsule") and uniform:
        mesh = trimesh.creation.capsule(2 * half_y, radius, count=[ROUND_SEGMENTS, 8])
        mesh.apply_transform(_pose(Z_TO_Y, np.zeros(3)))
        return _round_shape(ShapeKind.CAPSULE, fcl.Capsule(radius, 2 * half_y), mesh, center)
    # non-uniformly scaled round primitive: hull of its scaled unit tessellation
    unit = _unit_primitive_mesh(handle, half_length)
    return convex_shape(unit.vertices * scale + center, f"primitive {handle}")


def _unit_primitive_mesh(handle: str, half_length: float) -> trimesh.Trimesh:
    if handle.startswith(("icosphere", "uvSphere")):
        return trimesh.creation.icosphere(subdivisions=2, radius=1.0)
    if handle.startswith("cylinder"):
        mesh = trimesh.creation.cylinder(1.0, 2 * half_length, sections=ROUND_SEGMENTS)
    elif handle.startswith("cone"):
        mesh = trimesh.creation.cone(1.0, 2 * half_length, sections=ROUND_SEGMENTS)
        mesh.apply_translation([0, 0, -half_length])
    elif handle.startswith("capsule"):
        mesh = trimesh.creation.capsule(2 * half_length, 1.0, count=[ROUND_SEGMENTS, 8])
    else:
        raise ValueError(f"unknown primitive collision handle {handle!r}")
    mesh.apply_transform(_pose(Z_TO_Y, np.zeros(3)))
    return mesh


def convex_shape(points: np.ndarray, name: str) -> Shape:
    """Convex hull of body-frame points ``(n, 3)`` as an fcl ``Convex`` shape."""
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 4:
        raise ValueError(f"{name}: need at least 4 points (n, 3) for a hull, got {points.shape}")
    if not np.all(np.isfinite(points)):
        raise ValueError(f"{name}: hull points contain NaN or inf")
    points = _thicken_if_flat(points)
    hull = trimesh.convex.convex_hull(points)
    if hull.volume <= MIN_HULL_VOLUME or len(hull.faces) < 4:
        raise ValueError(
            f"{name}: degenerate (empty or collinear) collision mesh, volume {hull.volume}"
        )
    vertices, faces = np.asarray(hull.vertices), np.asarray(hull.faces, dtype=np.int64)
    fcl_faces = np.hstack([np.full((len(faces), 1), 3), faces]).ravel()
    geometry = fcl.Convex(vertices, len(faces), fcl_faces)
    return Shape(ShapeKind.CONVEX, geometry, np.eye(4), vertices, vertices[faces])


def _thicken_if_flat(points: np.ndarray) -> np.ndarray:
    """A planar point set (a single quad face, as in ``transform_box.glb``) becomes a slab
    ``FLAT_HULL_THICKNESS`` thick, like Bullet's collision margin gives it thickness."""
    centered = points - points.mean(0)
    _, singular, axes = np.linalg.svd(centered, full_matrices=False)
    if singular[0] <= 0 or singular[-1] > FLAT_HULL_RATIO * singular[0]:
        return points
    offset = 0.5 * FLAT_HULL_THICKNESS * axes[-1]  # along the plane normal
    return np.concatenate([points + offset, points - offset])


def box_shape(half_extents: np.ndarray, center: np.ndarray) -> Shape:
    """Exact fcl box of half extents ``(3,)`` centered at ``center`` in the body frame."""
    return primitive_shape("cubeSolid", np.asarray(half_extents, dtype=np.float64), center)


def mesh_shape(vertices: np.ndarray, faces: np.ndarray, name: str) -> Shape:
    """Static triangle mesh (fcl ``BVHModel``), exact, for the stage and static meshes."""
    vertices, faces = validate_mesh(vertices, faces, name)
    model = fcl.BVHModel()
    model.beginModel(len(vertices), len(faces))
    model.addSubModel(vertices, faces)
    model.endModel()
    shape = Shape(ShapeKind.MESH, model, np.eye(4), vertices, vertices[faces])
    shape.faces = faces
    return shape


def unit_mass_inertia(shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """Center of mass ``(3,)`` (body frame) and diagonal inertia ``(3,)`` per kilogram.

    The diagonal of the inertia tensor about the center of mass, in the body axes
    (off-diagonal products are dropped, as Habitat's ``inertia`` vector does).
    """
    center = shape.body_from_shape[:3, 3]
    if shape.kind == ShapeKind.BOX:
        half = np.asarray(shape.geometry.side, dtype=np.float64) / 2.0
        a2, b2, c2 = half**2
        return center, np.array([b2 + c2, a2 + c2, a2 + b2]) / 3.0  # I = m (b^2 + c^2) / 3
    if shape.kind == ShapeKind.SPHERE:
        return center, np.full(3, 0.4 * shape.radius**2)  # I = 2/5 m r^2
    hull = trimesh.convex.convex_hull(shape.hull_vertices)
    inertia = np.asarray(hull.moment_inertia) / max(hull.volume, MIN_INERTIA_VOLUME)  # per kg
    return np.asarray(hull.center_mass), np.diag(inertia).copy()
