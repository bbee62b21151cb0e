"""Queries on the collision world: ray casts and the records Habitat returns.

Ray-triangle intersection is Moller & Trumbore (1997), vectorized over all triangles of a
shape: with edges ``e1 = b - a``, ``e2 = c - a``, ``p = d x e2``, ``det = e1 . p``,
``s = o - a``, ``u = s . p / det``, ``q = s x e1``, ``v = d . q / det``, the hit parameter is
``t = e2 . q / det`` when ``u >= 0, v >= 0, u + v <= 1``. Spheres are intersected exactly
(``|o + t d - c|^2 = r^2``). Rays are tested in each body's frame.

Distances are in units of the ray direction's length (Habitat's ``ray_distance``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine import mn

from . import settings


@dataclass
class RayHitInfo:
    """One ray hit: ``object_id`` (stage = 0), world ``point`` and unit ``normal``,
    ``ray_distance`` in units of the ray direction's length."""

    object_id: int
    point: mn.Vector3
    normal: mn.Vector3
    ray_distance: float


@dataclass
class RaycastResults:
    """All hits of a ray, sorted by distance (``hits``), and the ``ray`` itself."""

    ray: Any
    hits: list = field(default_factory=list)

    def has_hits(self) -> bool:
        return len(self.hits) > 0


@dataclass
class ContactPointData:
    """One contact point (Habitat's ``ContactPointData``); positions/normal in world frame.

    ``contact_normal_on_b_in_ws`` points from B towards A (Bullet's convention, as Habitat
    reports it); ``contact_distance`` is negative when penetrating; forces in newtons.
    """

    object_id_a: int
    object_id_b: int
    link_id_a: int
    link_id_b: int
    position_on_a_in_ws: mn.Vector3
    position_on_b_in_ws: mn.Vector3
    contact_normal_on_b_in_ws: mn.Vector3
    contact_distance: float
    normal_force: float
    linear_friction_force1: float
    linear_friction_force2: float
    linear_friction_direction1: mn.Vector3
    linear_friction_direction2: mn.Vector3
    is_active: bool


def ray_triangles(origin: np.ndarray, direction: np.ndarray, triangles: np.ndarray):
    """Moller-Trumbore: hit parameters ``(t,)`` (inf for misses) and unit normals ``(t, 3)``.

    Parameters
    ----------
    origin, direction : (3,) in the triangles' frame. triangles : (t, 3, 3).
    """
    a = triangles[:, 0]
    e1, e2 = triangles[:, 1] - a, triangles[:, 2] - a
    p = np.cross(direction, e2)
    det = np.sum(e1 * p, axis=1)
    ok = np.abs(det) > 1e-14
    inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - a
    u = np.sum(s * p, axis=1) * inv_det
    q = np.cross(s, e1)
    v = (q @ direction) * inv_det
    t = np.sum(e2 * q, axis=1) * inv_det
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0)
    normal = np.cross(e1, e2)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), settings.TINY)
    # face the ray: n . d < 0
    normal *= np.where(normal @ direction > 0, -1.0, 1.0)[:, None]
    return np.where(hit, t, np.inf), normal


def ray_sphere(origin: np.ndarray, direction: np.ndarray, center: np.ndarray, radius: float):
    """Entry parameter ``t`` (inf if missed or behind) and the unit normal at the hit."""
    rel = origin - center
    a, b, c = direction @ direction, 2 * rel @ direction, rel @ rel - radius * radius
    disc = b * b - 4 * a * c
    if disc < 0 or a == 0:
        return np.inf, np.zeros(3)
    t = (-b - np.sqrt(disc)) / (2 * a)
    if t < 0:
        t = (-b + np.sqrt(disc)) / (2 * a) if c > 0 else 0.0  # origin inside: hit at t = 0
        if t < 0:
            return np.inf, np.zeros(3)
    normal = rel + t * direction
    return t, normal / max(np.linalg.norm(normal), settings.TINY)


def ray_shape(origin_body, direction_body, shape):
    """Hits ``(t (k,), normals_body (k, 3))`` of a ray with one shape, in the body frame.

    Like Bullet's all-hits ray callback: a triangle mesh (the stage) reports every triangle
    the ray crosses (a crossing through a shared edge counts once), a convex shape only
    its nearest hit.
    """
    if shape.kind == "sphere":
        t, normal = ray_sphere(
            origin_body, direction_body, shape.body_from_shape[:3, 3], shape.radius
        )
        return np.array([t]), normal[None]
    t, normal = ray_triangles(origin_body, direction_body, shape.ray_triangles)
    if shape.kind != "mesh":
        best = int(np.argmin(t))
        return t[best : best + 1], normal[best : best + 1]
    hit = np.flatnonzero(np.isfinite(t))
    _, first = np.unique(t[hit], return_index=True)  # sorted by t, one per distance
    return t[hit[first]], normal[hit[first]]


def cast_ray_bodies(bodies, candidates, origin, direction, max_distance):
    """All hits ``[(t, body, point_world, normal_world)]`` of a world ray, sorted by t.

    A ray starting inside a convex shape reports the exit face (Bullet reports no hit; we
    keep the hit so thin-wall sweeps are safe).
    """
    from .quaternions import quat_to_matrix

    hits = []
    for index in candidates:
        rotation = quat_to_matrix(bodies.body_rotation[index])
        position = bodies.body_position[index]
        origin_body = (origin - position) @ rotation  # R^T (o - x)
        direction_body = direction @ rotation
        for shape in bodies.shapes[index]:
            distances, normals = ray_shape(origin_body, direction_body, shape)
            for t, normal in zip(distances.tolist(), normals, strict=True):
                if t <= max_distance:
                    hits.append((t, int(index), origin + t * direction, rotation @ normal))
    hits.sort(key=lambda hit: (hit[0], hit[1]))
    return hits
