"""The public, non-stepping half of :class:`~engine.physics.world.PhysicsWorld`.

Body lifetime (add, remove, pose writes, waking), world settings (gravity, time), and the
queries Habitat exposes on the simulator: ray casts, contact points, contact tests, static
meshes for the navmesh, and a state hash for determinism tests.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import fcl
import numpy as np

from engine import mn
from engine.mn.vectors import stable_norm

from .bodies import DYNAMIC, STATIC, Bodies
from .collision_groups import (
    CollisionGroups,
    assign_group,
    filter_pairs,
    interacts_with_group,
)
from .contacts import ManifoldStore
from .quaternions import quat_to_matrix
from .queries import ContactPointData, RaycastResults, RayHitInfo, cast_ray_bodies

if TYPE_CHECKING:
    from .collision_stage import CollisionObjects
    from .constraints import ConstraintStore
    from .node_sync import NodeSync

_TEST_REQUEST = fcl.CollisionRequest()


class WorldApiMixin:
    """Methods of :class:`PhysicsWorld` that do not step (see the module docstring).

    The world's state they use, declared for readers and the type checker (set by
    ``PhysicsWorld.__init__``):
    """

    bodies: Bodies
    manifolds: ManifoldStore
    constraints: ConstraintStore
    collision_objects: CollisionObjects
    node_sync: NodeSync
    nodes: dict[int, Any]
    velocity_controls: dict[int, Any]
    render_meshes: dict[int, list]
    creation_state: dict[int, tuple[np.ndarray, np.ndarray]]
    n_overlapping_pairs: int
    _timestep: float
    _time: float
    _accumulator: float
    _gravity: np.ndarray
    # methods of PhysicsWorld used here: move a body's fcl objects, attach its shapes, and
    # the number of solver substeps per fixed step
    _update_fcl: Callable[..., None]
    _install_shapes: Callable[[int, list], None]
    _substeps: Callable[[], int]

    # -- time and gravity ----------------------------------------------------------------
    def get_world_time(self) -> float:
        """Simulated seconds: a whole number of fixed steps since creation or reset."""
        return self._time

    def get_physics_time_step(self) -> float:
        """The fixed step, seconds (0.008 by default)."""
        return self._timestep

    def get_gravity(self) -> mn.Vector3:
        return mn.Vector3(self._gravity)

    def set_gravity(self, gravity: Any) -> None:
        """Set gravity (m/s^2, world frame) and wake every dynamic body."""
        self._gravity = np.asarray(mn.to_vector3(gravity, "gravity"))
        n = self.bodies.count
        self.bodies.body_awake[:n] |= self.bodies.body_alive[:n]
        self.bodies.body_sleep_time[:n] = 0.0

    # -- bodies ----------------------------------------------------------------------------
    def add_body(self, description, template) -> int:
        """Create a DYNAMIC body from a BodyDescription and its template; returns its id."""
        b = self.bodies
        index = b.allocate()  # a recycled slot if any (Habitat's recycled object ids)
        b.body_mass[index] = description.mass
        b.body_inertia[index] = description.inertia
        b.body_motion_type[index] = DYNAMIC
        b.body_friction[index] = float(template.friction_coefficient)
        b.body_rolling_friction[index] = float(template.rolling_friction_coefficient)
        b.body_spinning_friction[index] = float(template.spinning_friction_coefficient)
        assign_group(b, index)  # the group of its motion type, until overridden
        b.body_restitution[index] = float(template.restitution_coefficient)
        b.body_linear_damping[index] = float(template.linear_damping)
        b.body_angular_damping[index] = float(template.angular_damping)
        b.body_collidable[index] = bool(template.is_collidable)
        self._install_shapes(index, description.shapes)
        self.creation_state[index] = (b.body_position[index].copy(), b.body_rotation[index].copy())
        return index

    def remove_body(self, index: int) -> None:
        """Remove body ``index`` and wake its neighbors; its slot (cleared, ``body_alive``
        False) is recycled for the next new body, and nothing else keeps a reference to it."""
        self.wake_neighbors(index)
        self.constraints.drop_body(index)
        b = self.bodies
        for key in [k for k in self.manifolds if index in k]:
            del self.manifolds[key]
        b.release(index)
        self.collision_objects.remove(index)
        self.render_meshes.pop(index, None)
        self.node_sync.forget(index)
        self.nodes.pop(index, None)
        self.velocity_controls.pop(index, None)
        self.creation_state.pop(index, None)

    def set_body_pose(
        self, index: int, position: np.ndarray, rotation: np.ndarray, wake: bool = True
    ) -> None:
        """Teleport body ``index`` (position (3,), rotation [x, y, z, w]); node follows."""
        b = self.bodies
        b.body_position[index] = position
        b.body_rotation[index] = rotation / np.linalg.norm(rotation)
        if index in self.collision_objects:
            self._update_fcl(index)
        self.node_sync.write_node(index)
        if wake:
            self.wake(index)
            self.wake_neighbors(index)

    def wake(self, index: int) -> None:
        """Wake body ``index`` (a no-op for non-dynamic bodies)."""
        if self.bodies.body_motion_type[index] == DYNAMIC:
            self.bodies.body_awake[index] = True
            self.bodies.body_sleep_time[index] = 0.0

    def wake_neighbors(self, index: int) -> None:
        """Wake the islands touching ``index``: every dynamic body connected to it through
        contact manifolds (a support removed or moved lets the whole stack above move)."""
        b = self.bodies
        neighbors: dict[int, list[int]] = {}
        for a, c in self.manifolds:
            neighbors.setdefault(a, []).append(c)
            neighbors.setdefault(c, []).append(a)
        frontier, seen = [index], {index}
        while frontier:
            current = frontier.pop()
            for other in neighbors.get(current, []):
                if other in seen or b.body_motion_type[other] != DYNAMIC:
                    continue  # static and kinematic bodies do not join islands
                seen.add(other)
                self.wake(other)
                frontier.append(other)

    def reset(self) -> None:
        """World time 0; every object back to its creation pose, at rest, awake."""
        b = self.bodies
        for index, (position, rotation) in self.creation_state.items():
            b.body_position[index] = position
            b.body_rotation[index] = rotation
            b.body_awake[index] = True
            self._update_fcl(index)
            self.node_sync.write_node(index)
        n = b.count
        for name in (
            "body_linear_velocity",
            "body_angular_velocity",
            "body_force",
            "body_torque",
            "body_solver_velocity",
            "body_solver_angular_velocity",
        ):
            getattr(b, name)[:n] = 0.0
        b.body_sleep_time[:n] = 0.0
        self.manifolds.clear()
        self._time = 0.0
        self._accumulator = 0.0

    def get_stage_is_collidable(self) -> bool:
        return bool(self.bodies.body_collidable[0] and self.bodies.shapes[0])

    def set_stage_is_collidable(self, collidable: bool) -> None:
        """Turn the stage's collisions (contacts, ray hits, contact tests) on or off."""
        if not isinstance(collidable, bool | np.bool_):
            raise TypeError(f"collidable must be a bool, got {collidable!r}")
        self.bodies.body_collidable[0] = bool(collidable) and bool(self.bodies.shapes[0])
        for key in [k for k in self.manifolds if 0 in k]:
            self.wake(key[1])
            del self.manifolds[key]

    # -- queries ---------------------------------------------------------------------------
    def cast_ray(self, ray, max_distance: float = 100.0) -> RaycastResults:
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
        b, n = self.bodies, self.bodies.count
        candidates = np.nonzero(b.body_alive[:n] & b.body_collidable[:n])[0]
        # rays are in the Default collision group (Habitat / Bullet's ray filter)
        candidates = candidates[interacts_with_group(b, candidates, CollisionGroups.Default)]
        hits = []
        for index in [i for i in candidates.tolist() if b.shapes[i]]:
            shift = self._ray_shift(index, origin, unit, reach)
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

    def _ray_shift(
        self, index: int, origin: np.ndarray, unit: np.ndarray, reach: float
    ) -> float | None:
        """Meters the unit ray can travel before it nears body ``index``'s bounding sphere,
        or None when it misses the sphere within ``reach`` (Ericson, Real-Time Collision
        Detection, 5.3.2). Keeps far rays (origin 1e300) from squaring huge numbers."""
        b = self.bodies
        center = (
            b.body_position[index]
            + quat_to_matrix(b.body_rotation[index]) @ b.body_shape_center[index]
        )
        radius = float(stable_norm(b.body_shape_half[index])) + 1e-3
        offset = center - origin
        along = float(offset @ unit)  # distance along the ray to the closest approach
        if along < -radius or along - radius > reach:
            return None
        if float(stable_norm(offset - along * unit)) > radius:
            return None
        return max(0.0, along - radius)

    def contact_test(self, index: int) -> bool:
        """True when body ``index`` overlaps another collidable body it can collide with.

        As in Bullet's collision filtering, STATIC and KINEMATIC bodies (and the stage) never
        collide with each other, so a pair counts only if one of the two is DYNAMIC.
        """
        b, n = self.bodies, self.bodies.count
        if not (b.body_alive[index] and b.body_collidable[index] and b.shapes[index]):
            return False
        self_dynamic = b.body_motion_type[index] == DYNAMIC
        rotation = quat_to_matrix(b.body_rotation[:n])
        from .collide import world_aabbs

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
        self._update_fcl(index, rotation[index])
        for other in np.nonzero(overlap)[0].tolist():
            if not b.shapes[other]:
                continue
            if other != 0:
                self._update_fcl(other, rotation[other])
            for obj_a in self.collision_objects.shape_objects[index]:
                for obj_b in self.collision_objects.shape_objects[other]:
                    if fcl.collide(obj_a, obj_b, _TEST_REQUEST, fcl.CollisionResult()):
                        return True
        return False

    def get_physics_contact_points(self) -> list[ContactPointData]:
        """Contact points of every manifold (last step's impulses as forces)."""
        from .solver import tangent_basis

        h = self._timestep / self._substeps()  # the impulses were applied over one solver step
        b, n, store = self.bodies, self.bodies.count, self.manifolds
        rows = np.array([store.row(key) for key in sorted(store)], dtype=np.int64)
        rows = rows[store.count[rows] > 0]
        points_a, points_c, normals = store.world_points(
            rows, quat_to_matrix(b.body_rotation[:n]), b.body_position[:n]
        )
        points = []
        for row, pa, pc, normal in zip(rows.tolist(), points_a, points_c, normals, strict=True):
            a, c = store.bodies[row].tolist()
            t1, t2 = tangent_basis(normal)
            active = self._is_moving(a) or self._is_moving(c)
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

    def get_physics_num_active_contact_points(self) -> int:
        """Number of manifold points touching at least one awake dynamic body."""
        return sum(
            int(len(m))
            for (a, c), m in self.manifolds.items()
            if self._is_moving(a) or self._is_moving(c)
        )

    def _is_moving(self, index: int) -> bool:
        b = self.bodies
        return bool(b.body_awake[index] and b.body_motion_type[index] == DYNAMIC)

    def get_physics_num_active_overlapping_pairs(self) -> int:
        """Broad-phase pairs found by the last collision pass."""
        return self.n_overlapping_pairs

    def static_meshes_world(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """``(vertices (V, 3), faces (F, 3))`` of the STATIC objects' render meshes, world frame."""
        b, meshes = self.bodies, []
        for index in sorted(self.nodes):
            if not (b.body_alive[index] and b.body_motion_type[index] == STATIC):
                continue
            rotation = quat_to_matrix(b.body_rotation[index])
            for mesh in self.render_meshes.get(index, []):
                vertices = np.asarray(mesh.vertices) @ rotation.T + b.body_position[index]
                meshes.append((vertices, np.asarray(mesh.faces, dtype=np.int64)))
        return meshes

    def state_hash(self) -> str:
        """SHA-256 of every body's full state, the manifolds, world time and accumulator."""
        digest = hashlib.sha256(self.bodies.state_bytes())
        digest.update(np.array([self._time, self._accumulator, *self._gravity]).tobytes())
        for key, manifold in sorted(self.manifolds.items()):
            digest.update(np.array(key).tobytes())
            for array in (
                manifold.local_a,
                manifold.local_b,
                manifold.normal_local,
                manifold.impulse,
            ):
                digest.update(array.tobytes())
        return digest.hexdigest()
