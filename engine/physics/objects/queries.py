"""Queries on the collision world: ray casts, contact tests, contact records, static meshes
and a state hash (the functions behind ``PhysicsWorld.cast_ray``, ``contact_test``,
``get_physics_contact_points``, ``static_meshes_world`` and ``state_hash``). Each takes the
world's parts it reads (``Bodies``, ``ManifoldStore``, ``CollisionObjects``) explicitly.

Ray-triangle intersection is Moller & Trumbore (1997), vectorized over all triangles of a
shape: with edges ``e1 = b - a``, ``e2 = c - a``, ``p = d x e2``, ``det = e1 . p``,
``s = o - a``, ``u = s . p / det``, ``q = s x e1``, ``v = d . q / det``, the hit parameter is
``t = e2 . q / det`` when ``u >= 0, v >= 0, u + v <= 1``. Spheres are intersected exactly
(``|o + t d - c|^2 = r^2``). Rays are tested in each body's frame.

Distances are in units of the ray direction's length (Habitat's ``ray_distance``).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import fcl
import numpy as np

from engine import mn
from engine.mn.vectors import stable_norm

from ..collision.collide import world_aabbs
from ..collision.collision_groups import CollisionGroups, filter_pairs, interacts_with_group
from ..collision.contacts import ManifoldStore
from ..core.bodies import DYNAMIC, STATIC, Bodies
from ..core.quaternions import quat_to_matrix
from ..core.settings import RAY_PARALLEL_DETERMINANT, RAY_SPHERE_MARGIN, TINY
from ..solver.contact_batch import tangent_basis

if TYPE_CHECKING:
    from ..collision.collision_objects import CollisionObjects

_TEST_REQUEST = fcl.CollisionRequest()


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
    ok = np.abs(det) > RAY_PARALLEL_DETERMINANT
    inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - a
    u = np.sum(s * p, axis=1) * inv_det
    q = np.cross(s, e1)
    v = (q @ direction) * inv_det
    t = np.sum(e2 * q, axis=1) * inv_det
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0)
    normal = np.cross(e1, e2)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), TINY)
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
    return t, normal / max(np.linalg.norm(normal), TINY)


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


# -- world queries (behind PhysicsWorld's query methods) -----------------------------------
def cast_ray(bodies: Bodies, ray: Any, max_distance: float = 100.0) -> RaycastResults:
    """All hits of ``ray`` with collidable bodies up to ``max_distance`` (units of
    ``|ray.direction|``), sorted by distance. The stage reports object id 0."""
    if not (hasattr(ray, "origin") and hasattr(ray, "direction")):
        raise TypeError(f"ray must be a geo.Ray (with origin and direction), got {ray!r}")
    if isinstance(max_distance, bool) or not isinstance(
        max_distance, int | float | np.integer | np.floating
    ):
        raise TypeError(f"max_distance must be a number, got {max_distance!r}")
    max_distance = float(max_distance)
    if not np.isfinite(max_distance) or max_distance < 0:
        raise ValueError(f"max_distance must be finite and >= 0, got {max_distance!r}")
    origin = np.asarray(mn.to_vector3(ray.origin, "ray.origin"))
    direction = np.asarray(mn.to_vector3(ray.direction, "ray.direction"))
    results = RaycastResults(ray)
    scale = float(stable_norm(direction))  # |direction| without overflow
    if scale == 0.0:
        return results
    unit = direction / scale
    with np.errstate(over="ignore"):
        reach = max_distance * scale  # meters (inf when it overflows: no limit)
    b, n = bodies, bodies.count
    candidates = np.nonzero(b.body_alive[:n] & b.body_collidable[:n])[0]
    # rays are in the Default collision group (Habitat / Bullet's ray filter)
    candidates = candidates[interacts_with_group(b, candidates, CollisionGroups.Default)]
    hits = []
    for index in [i for i in candidates.tolist() if b.shapes[i]]:
        shift = ray_shift(bodies, index, origin, unit, reach)
        if shift is None:
            continue  # the ray misses the body's bounding sphere
        start = origin + shift * unit  # march to the sphere first: no huge squares
        for t, _, _, normal in cast_ray_bodies(b, [index], start, unit, reach - shift):
            meters = shift + t
            hits.append((meters / scale, index, origin + meters * unit, normal))
    hits.sort(key=lambda hit: (hit[0], hit[1]))
    for t, index, point, normal in hits:
        results.hits.append(RayHitInfo(index, mn.Vector3(point), mn.Vector3(normal), t))
    return results


def ray_shift(
    bodies: Bodies, index: int, origin: np.ndarray, unit: np.ndarray, reach: float
) -> float | None:
    """Meters the unit ray can travel before it nears body ``index``'s bounding sphere,
    or None when it misses the sphere within ``reach`` (Ericson, Real-Time Collision
    Detection, 5.3.2). Keeps far rays (origin 1e300) from squaring huge numbers."""
    b = bodies
    center = (
        b.body_position[index] + quat_to_matrix(b.body_rotation[index]) @ b.body_shape_center[index]
    )
    radius = float(stable_norm(b.body_shape_half[index])) + RAY_SPHERE_MARGIN
    offset = center - origin
    along = float(offset @ unit)  # distance along the ray to the closest approach
    if along < -radius or along - radius > reach:
        return None
    if float(stable_norm(offset - along * unit)) > radius:
        return None
    return max(0.0, along - radius)


def contact_test(bodies: Bodies, collision_objects: CollisionObjects, index: int) -> bool:
    """True when body ``index`` overlaps another collidable body it can collide with.

    As in Bullet's collision filtering, STATIC and KINEMATIC bodies (and the stage) never
    collide with each other, so a pair counts only if one of the two is DYNAMIC. Moves the
    fcl objects it tests to the bodies' current poses.
    """
    b, n = bodies, bodies.count
    if not (b.body_alive[index] and b.body_collidable[index] and b.shapes[index]):
        return False
    self_dynamic = b.body_motion_type[index] == DYNAMIC
    rotation = quat_to_matrix(b.body_rotation[:n])
    lo, hi = world_aabbs(
        b.body_shape_center[:n], b.body_shape_half[:n], b.body_position[:n], b.body_rotation[:n]
    )
    overlap = np.all((lo <= hi[index]) & (hi >= lo[index]), axis=1)
    overlap &= b.body_alive[:n] & b.body_collidable[:n]
    if not self_dynamic:
        overlap &= b.body_motion_type[:n] == DYNAMIC
    overlap[index] = False
    others = np.nonzero(overlap)[0]
    pairs = np.stack([np.full(len(others), index), others], axis=1)
    overlap[:] = False
    overlap[filter_pairs(b, pairs)[:, 1]] = True  # collision groups and masks
    collision_objects.move(b, np.array([index]), rotation[index][None])
    for other in np.nonzero(overlap)[0].tolist():
        if not b.shapes[other]:
            continue
        if other != 0:
            collision_objects.move(b, np.array([other]), rotation[other][None])
        for obj_a in collision_objects.shape_objects[index]:
            for obj_b in collision_objects.shape_objects[other]:
                if fcl.collide(obj_a, obj_b, _TEST_REQUEST, fcl.CollisionResult()):
                    return True
    return False


def is_moving(bodies: Bodies, index: int) -> bool:
    """True for an awake DYNAMIC body (what Habitat calls an active body)."""
    return bool(bodies.body_awake[index] and bodies.body_motion_type[index] == DYNAMIC)


def contact_points(bodies: Bodies, manifolds: ManifoldStore, h: float) -> list[ContactPointData]:
    """Contact points of every manifold; forces are the last step's impulses over the solver
    step ``h`` (s) they were applied in."""
    b, n, store = bodies, bodies.count, manifolds
    rows = np.array([store.row(key) for key in sorted(store)], dtype=np.int64)
    rows = rows[store.count[rows] > 0]
    points_a, points_c, normals = store.world_points(
        rows, quat_to_matrix(b.body_rotation[:n]), b.body_position[:n]
    )
    points = []
    for row, pa, pc, normal in zip(rows.tolist(), points_a, points_c, normals, strict=True):
        a, c = store.bodies[row].tolist()
        t1, t2 = tangent_basis(normal)
        active = is_moving(b, a) or is_moving(b, c)
        for k in range(store.count[row]):
            impulse = store.impulse[row, k]
            points.append(
                ContactPointData(
                    a,
                    c,
                    0,
                    0,
                    mn.Vector3(pa[k]),
                    mn.Vector3(pc[k]),
                    mn.Vector3(-normal[k]),
                    float(-(pa[k] - pc[k]) @ normal[k]),
                    float(impulse[0] / h),
                    float(impulse[1] / h),
                    float(impulse[2] / h),
                    mn.Vector3(t1[k]),
                    mn.Vector3(t2[k]),
                    active,
                )
            )
    return points


def active_contact_point_count(bodies: Bodies, manifolds: ManifoldStore) -> int:
    """Number of manifold points touching at least one awake dynamic body."""
    return sum(
        int(len(m))
        for (a, c), m in manifolds.items()
        if is_moving(bodies, a) or is_moving(bodies, c)
    )


def static_meshes_world(
    bodies: Bodies, object_ids: Any, render_meshes: dict[int, list]
) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(vertices (V, 3), faces (F, 3))`` of the STATIC objects' render meshes, world frame;
    ``object_ids``: the ids of the world's objects (visited in sorted order)."""
    b, meshes = bodies, []
    for index in sorted(object_ids):
        if not (b.body_alive[index] and b.body_motion_type[index] == STATIC):
            continue
        rotation = quat_to_matrix(b.body_rotation[index])
        for mesh in render_meshes.get(index, []):
            vertices = np.asarray(mesh.vertices) @ rotation.T + b.body_position[index]
            meshes.append((vertices, np.asarray(mesh.faces, dtype=np.int64)))
    return meshes


def state_hash(
    bodies: Bodies, manifolds: ManifoldStore, time: float, accumulator: float, gravity: np.ndarray
) -> str:
    """SHA-256 of every body's full state, the manifolds, world time (s), the step
    accumulator (s) and gravity (m/s^2): equal hashes mean bit-identical worlds."""
    digest = hashlib.sha256(bodies.state_bytes())
    digest.update(np.array([time, accumulator, *gravity]).tobytes())
    for key, manifold in sorted(manifolds.items()):
        digest.update(np.array(key).tobytes())
        for array in (
            manifold.local_a,
            manifold.local_b,
            manifold.normal_local,
            manifold.impulse,
        ):
            digest.update(array.tobytes())
    return digest.hexdigest()
