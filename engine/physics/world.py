"""The physics world: bodies, the fixed-step loop and Habitat's ``step_physics`` accumulator.

``World.step`` (here :meth:`PhysicsWorld._step`) reads top to bottom on one screen, one
stage per banner, after box2d-lite's ``World::Step`` and Box2D v3's stage list. Each stage is
a function of explicit arguments; data flows one way. With ``n`` bodies, ``k`` awake dynamic
ones, ``m`` manifolds of ``S = 4`` point slots:

1. **forces** ``integrate_velocities`` (:mod:`integrate`)

   - reads: Bodies mass (n,), inertia (n, 3), force/torque (n, 3), damping (n,); moving
     (k,) awake dynamic indices; gravity (3,); h
   - writes: Bodies linear/angular_velocity of ``moving`` (k, 3). Before it the step copies
     ``start_velocity (n, 6)`` for restitution.

2. **collision** ``collision_stage`` (:mod:`collision_stage`)

   - reads: Bodies poses (n, 3)/(n, 4), shapes; CollisionObjects; ManifoldStore; settings
   - writes: Bodies aabb_min/max (n, 3); fcl poses; ManifoldStore rows (m, S, 3) refreshed,
     created and deleted; returns the broad-phase pair count

3. **solve** ``solve_stage`` (:mod:`solve_stage`)

   - reads: Bodies poses, velocities, masses; ManifoldStore (m, S); moving (k,);
     start_velocity (n, 6); h; settings
   - writes: Bodies velocities of ``moving``; ManifoldStore.impulse (m, S, 3); returns
     SolveResult(pseudo_velocity (n, 6), overlapping_bodies (j,))

4. **integrate** ``integrate_stage`` (:mod:`integrate`)

   - reads: Bodies velocities, inertia; moving (k,); pseudo_velocity (n, 6); h
   - writes: Bodies position (k, 3), rotation (k, 4), angular_velocity (k, 3) (speeds
     clamped, fast bodies swept against static geometry)

5. **sleep** ``update_sleep`` (:mod:`sleeping`)

   - reads: Bodies velocities, sleep_time; ManifoldStore (who touches whom); h;
     overlapping_bodies (j,)
   - writes: Bodies awake (n,), sleep_time (n,), velocities of bodies falling asleep

``settings.use_vectorized`` (:class:`SolverSettings`) routes stages 2 and 3 through the
batched NumPy code or through the plain per-pair / per-point reference code
(:mod:`reference_contacts`, :mod:`reference_solver`); tests prove both give the same
contacts and trajectories to rounding. Wall time per stage is summed by
:class:`profiling.StageTimer` (``world.profile``), outside the stage functions.

**Composition.** The world owns its parts and hands them to plain functions: ``bodies``
(:class:`Bodies`, every per-body array), ``manifolds`` (:class:`ManifoldStore`),
``collision_objects`` (:class:`CollisionObjects`, fcl), ``constraints``
(:class:`ConstraintStore`), ``node_sync`` (:class:`NodeSync`, bodies <-> scene nodes) and
the per-object dictionaries ``nodes``, ``velocity_controls``, ``render_meshes``,
``creation_state``. Its methods are of three kinds, each a few lines: the step above;
body bookkeeping that must touch several parts at once (:meth:`add_body`,
:meth:`remove_body`, :meth:`~PhysicsWorld.set_body_pose`, :meth:`~PhysicsWorld.reset`,
:meth:`set_stage`); and Habitat's world API (time, gravity, ray casts, contact points),
one-line calls of :mod:`queries` and :mod:`sleeping` functions that take the parts they
read explicitly. A reader looking for what ``cast_ray`` does opens one function in one
module, with every input in its signature; no method is inherited.

``step_physics(dt)`` wraps it the way Habitat wraps ``btDiscreteDynamicsWorld::
stepSimulation``: it accumulates ``dt`` and runs whole fixed steps of ``timestep`` (0.008 s
default), so world time lags the requested time by less than one step; ``dt <= 0`` runs
one step. Velocity control acts once per call; applied forces act on every fixed step of
the call and are cleared at its end. Object poses are written to their scene nodes after
the call (:mod:`node_sync`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine import mn

from .collision.collision_groups import assign_group
from .collision.collision_objects import CollisionObjects
from .collision.contacts import ManifoldStore
from .core.bodies import DYNAMIC, KINEMATIC, STAGE_ID, STATIC, Bodies
from .core.profiling import StageTimer
from .core.quaternions import quat_to_matrix
from .core.settings import MAX_STEPS_PER_CALL, SolverSettings
from .core.shapes import mesh_shape
from .objects import queries
from .objects.constraints import ConstraintStore
from .objects.kinematic_motion import KinematicPoses, implied_velocities
from .objects.node_sync import NodeSync
from .objects.queries import ContactPointData, RaycastResults
from .pipeline.collision_stage import collision_stage, update_world_aabbs
from .pipeline.solve_stage import solve_stage
from .solver.integrate import (
    awake_dynamic_bodies,
    body_velocities,
    integrate_stage,
    integrate_velocities,
)
from .solver.sleeping import update_sleep, wake_body, wake_island, wake_touched
from .solver.soft_step import check_soft_settings

__all__ = ["STAGE_ID", "PhysicsWorld"]


class PhysicsWorld:
    """The rigid-body world behind ``Simulator`` (see the module docstring): it owns the
    state, runs the step, and answers Habitat's world queries."""

    def __init__(
        self, physics_attributes, root_node, object_template_manager, asset_template_manager=None
    ) -> None:
        from .objects.rigid_object_manager import RigidObjectManager

        self._timestep = float(physics_attributes.timestep)
        if not (math.isfinite(self._timestep) and self._timestep > 0):
            raise ValueError(f"physics timestep must be > 0, got {self._timestep!r}")
        self._gravity = np.asarray(mn.to_vector3(physics_attributes.gravity, "gravity"))
        self._default_friction = float(physics_attributes.friction_coefficient)
        self._default_restitution = float(physics_attributes.restitution_coefficient)
        self.settings = SolverSettings()
        self.root_node = root_node
        self.asset_template_manager = asset_template_manager
        self.bodies = Bodies()
        self.bodies.add(STAGE_ID)
        self.bodies.body_collidable[STAGE_ID] = False
        self.bodies.body_motion_type[STAGE_ID] = STATIC
        assign_group(self.bodies, STAGE_ID)
        self.collision_objects = CollisionObjects()
        self.manifolds = ManifoldStore()
        self.nodes: dict[int, Any] = {}
        self.velocity_controls: dict[int, Any] = {}
        #: bodies already warned of a mass ratio beyond what the solver holds (mass_ratio.py)
        self.mass_ratio_warned: set[int] = set()
        self.render_meshes: dict[int, list] = {}
        self.creation_state: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self.node_sync = NodeSync(self.bodies, self.nodes)
        self._time = 0.0  # s, whole fixed steps since creation or reset
        self._accumulator = 0.0  # s, requested time not yet stepped (< one fixed step)
        self.n_overlapping_pairs = 0  # broad-phase pairs of the last collision pass
        self.timer = StageTimer()
        self.profile = self.timer.seconds  # {stage name: wall seconds}, read by benchmarks
        self.rigid_object_manager = RigidObjectManager(self, object_template_manager, root_node)
        self.constraints = ConstraintStore()
        self.kinematic_poses = KinematicPoses()  # kinematic poses after the last step

    # ------------------------------------------------------------------------------------
    # stage
    # ------------------------------------------------------------------------------------
    def set_stage(self, meshes, stage_attributes) -> None:
        """Use ``meshes`` (world frame, list of MeshData) as the static stage, id 0."""
        b = self.bodies
        if not meshes:
            b.shapes[STAGE_ID], b.body_collidable[STAGE_ID] = [], False
            self.collision_objects.remove(STAGE_ID)
            return
        vertices, faces, offset = [], [], 0
        for i, mesh in enumerate(meshes):
            v = np.asarray(mesh.vertices, dtype=np.float64)
            f = np.asarray(mesh.faces, dtype=np.int64)
            if len(v) == 0 or len(f) == 0:
                continue
            vertices.append(v)
            faces.append(f + offset)
            offset += len(v)
            if not np.all(np.isfinite(v)):
                raise ValueError(f"stage mesh {i} has NaN or inf vertices")
        if not faces:
            raise ValueError("stage meshes hold no triangles")
        shape = mesh_shape(np.concatenate(vertices), np.concatenate(faces), "stage")
        self._install_shapes(STAGE_ID, [shape])
        friction, restitution = self._default_friction, self._default_restitution
        if stage_attributes is not None:
            friction = float(stage_attributes.friction_coefficient)
            restitution = float(stage_attributes.restitution_coefficient)
        b.body_friction[STAGE_ID], b.body_restitution[STAGE_ID] = friction, restitution
        b.body_collidable[STAGE_ID] = True

    def _install_shapes(self, index: int, shapes: list) -> None:
        """Attach shapes to a body: fcl objects, body-frame AABB, smallest half extent."""
        b = self.bodies
        b.shapes[index] = shapes
        self.collision_objects.install(index, shapes)
        points = np.concatenate([s.hull_vertices for s in shapes])
        lo, hi = points.min(0), points.max(0)
        b.body_shape_center[index] = 0.5 * (lo + hi)
        b.body_shape_half[index] = 0.5 * (hi - lo)
        b.body_min_half_extent[index] = min(s.min_half_extent for s in shapes)
        self._update_fcl(index)

    def _update_fcl(self, index: int, rotation: np.ndarray | None = None) -> None:
        """Move body ``index``'s fcl objects to its pose (``rotation``: its matrix, if known)."""
        r = quat_to_matrix(self.bodies.body_rotation[index]) if rotation is None else rotation
        self.collision_objects.move(self.bodies, np.array([index]), r[None])

    def get_stage_is_collidable(self) -> bool:
        return bool(self.bodies.body_collidable[STAGE_ID] and self.bodies.shapes[STAGE_ID])

    def set_stage_is_collidable(self, collidable: bool) -> None:
        """Turn the stage's collisions (contacts, ray hits, contact tests) on or off."""
        if not isinstance(collidable, bool | np.bool_):
            raise TypeError(f"collidable must be a bool, got {collidable!r}")
        b = self.bodies
        b.body_collidable[STAGE_ID] = bool(collidable) and bool(b.shapes[STAGE_ID])
        for key in [k for k in self.manifolds if STAGE_ID in k]:
            wake_body(b, key[1])
            del self.manifolds[key]

    # ------------------------------------------------------------------------------------
    # bodies: bookkeeping across the world's parts
    # ------------------------------------------------------------------------------------
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
        # a template may store damping above 1 (as Habitat's); Bullet clamps it to [0, 1]
        b.body_linear_damping[index] = min(float(template.linear_damping), 1.0)
        b.body_angular_damping[index] = min(float(template.angular_damping), 1.0)
        b.body_collidable[index] = bool(template.is_collidable)
        self._install_shapes(index, description.shapes)
        self.creation_state[index] = (b.body_position[index].copy(), b.body_rotation[index].copy())
        return index

    def remove_body(self, index: int) -> None:
        """Remove body ``index`` and wake its neighbors; its slot (cleared, ``body_alive``
        False) is recycled for the next new body, and no part of the world keeps it."""
        wake_island(self.bodies, self.manifolds, index)
        self.constraints.drop_body(index)
        for key in [k for k in self.manifolds if index in k]:
            del self.manifolds[key]
        self.bodies.release(index)
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
            wake_body(b, index)
            wake_island(b, self.manifolds, index)

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
        for array in (
            b.body_linear_velocity,
            b.body_angular_velocity,
            b.body_force,
            b.body_torque,
            b.body_solver_velocity,
            b.body_solver_angular_velocity,
        ):
            array[:n] = 0.0
        b.body_sleep_time[:n] = 0.0
        self.manifolds.clear()
        self.kinematic_poses.clear()  # the jump back is no motion
        self._time = 0.0
        self._accumulator = 0.0

    # ------------------------------------------------------------------------------------
    # time and gravity
    # ------------------------------------------------------------------------------------
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

    # ------------------------------------------------------------------------------------
    # stepping
    # ------------------------------------------------------------------------------------
    def step_physics(self, dt: float = 1.0 / 60.0) -> None:
        """Advance by ``dt`` seconds in whole fixed steps (see the module docstring)."""
        if isinstance(dt, bool) or not isinstance(dt, int | float | np.integer | np.floating):
            raise TypeError(f"dt must be a number, got {dt!r}")
        dt = float(dt)
        if not math.isfinite(dt):
            raise ValueError(f"dt must be finite, got {dt!r}")
        if dt <= 0.0:
            dt = self._timestep
        accumulated = self._accumulator + dt
        n_steps = int(accumulated / self._timestep)
        if n_steps > MAX_STEPS_PER_CALL:
            raise ValueError(
                f"dt={dt!r} needs {n_steps} fixed steps of {self._timestep} s; "
                f"the limit per call is {MAX_STEPS_PER_CALL}"
            )
        if self.settings.soft_step:  # its settings are checked before anything moves
            check_soft_settings(self.settings)
        self._read_user_moves()  # raises ValueError before it changes anything
        active = [(index, c) for index, c in self.velocity_controls.items() if c.is_active]
        self._apply_velocity_control(dt, active)
        self._accumulator = accumulated - n_steps * self._timestep
        if n_steps:  # Bullet's saveKinematicState: user-moved kinematic bodies get velocities
            controlled = {index for index, _ in active}
            implied_velocities(
                self.bodies, self.kinematic_poses, controlled, n_steps * self._timestep
            )
        for _ in range(n_steps):
            for _ in range(self._substeps()):
                self._step(self._timestep / self._substeps())
            self._time += self._timestep
        if n_steps:
            self.kinematic_poses.record(self.bodies)
        self.bodies.body_force[:] = 0.0
        self.bodies.body_torque[:] = 0.0
        self.node_sync.write_nodes()

    def _read_user_moves(self) -> None:
        """Bodies of KINEMATIC/STATIC objects whose nodes the user moved take those poses."""
        for index in self.node_sync.read_user_moves():
            self._update_fcl(index)
            wake_island(self.bodies, self.manifolds, index)

    def _substeps(self) -> int:
        return max(1, int(self.settings.substeps))

    def _step(self, h: float) -> None:
        """One fixed step of length ``h`` seconds: the five stages of the module docstring.

        Every stage is a function of explicit arguments; ``timed`` only adds up wall time.
        """
        bodies, store, settings, timed = self.bodies, self.manifolds, self.settings, self.timer.run
        if self._nothing_to_simulate():
            update_world_aabbs(bodies)  # the broad phase's only effect without dynamic bodies
            self.n_overlapping_pairs = 0  # (its pairs need a dynamic body)
            return
        self.constraints.wake_bodies(bodies)  # constrained bodies never sleep
        # ---- 1. forces: v += h (g + F/m), w += h I^-1 tau, damping -------------------------
        moving = awake_dynamic_bodies(bodies)  # (k,) body indices
        start_velocity = body_velocities(bodies)  # (n, 6) [v, w] before this step's forces
        timed("forces", integrate_velocities, bodies, moving, self._gravity, h)
        # ---- 2. collision: broad phase pairs, narrow phase contacts, persistent manifolds --
        self.n_overlapping_pairs = timed(
            "collide", collision_stage, bodies, self.collision_objects, store, settings, self.timer
        )
        if wake_touched(bodies, store):  # a body hit this step must be able to move
            moving = awake_dynamic_bodies(bodies)
        # ---- 3. solve: warm start, sequential impulses by color, restitution, split impulses
        solved = timed("solve", solve_stage, bodies, store, moving, start_velocity, h, settings)
        timed("constraints", self.constraints.solve, bodies, moving, h, settings)
        # ---- 4. integrate: clamp speeds, x += h v, rotate, sweep fast bodies ---------------
        timed("integrate", integrate_stage, bodies, moving, solved.pseudo_velocity, h)
        # ---- 5. sleep: resting islands fall asleep, disturbed ones wake --------------------
        timed("sleep", update_sleep, bodies, store, h, solved.overlapping_bodies)

    def _nothing_to_simulate(self) -> bool:
        """No live DYNAMIC body, no contact manifold and no constraint: every stage of a step
        would find nothing to move or touch (pairs need a dynamic body; KINEMATIC and STATIC
        bodies move only by the user or their velocity control, outside ``_step``), so the
        step is skipped: a robot driven over the navmesh costs no collision pass."""
        n = self.bodies.count
        dynamic = self.bodies.body_alive[:n] & (self.bodies.body_motion_type[:n] == DYNAMIC)
        return not dynamic.any() and len(self.manifolds) == 0 and len(self.constraints) == 0

    # ------------------------------------------------------------------------------------
    # queries (Habitat's world API): the functions of queries.py on the world's parts
    # ------------------------------------------------------------------------------------
    def perform_discrete_collision_detection(self) -> None:
        """Run the collision stage without stepping (refreshes contact points)."""
        self._read_user_moves()
        self.n_overlapping_pairs = collision_stage(
            self.bodies, self.collision_objects, self.manifolds, self.settings, self.timer
        )

    def cast_ray(self, ray, max_distance: float = 100.0) -> RaycastResults:
        """All hits of ``ray`` up to ``max_distance`` (:func:`queries.cast_ray`)."""
        return queries.cast_ray(self.bodies, ray, max_distance)

    def get_physics_contact_points(self) -> list[ContactPointData]:
        """Contact points of every manifold, last step's impulses as forces."""
        h = self._timestep / self._substeps()  # the impulses were applied over one solver step
        return queries.contact_points(self.bodies, self.manifolds, h)

    def get_physics_num_active_contact_points(self) -> int:
        """Number of manifold points touching at least one awake dynamic body."""
        return queries.active_contact_point_count(self.bodies, self.manifolds)

    def get_physics_num_active_overlapping_pairs(self) -> int:
        """Broad-phase pairs found by the last collision pass."""
        return self.n_overlapping_pairs

    def static_meshes_world(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """``(vertices (V, 3), faces (F, 3))`` of the STATIC objects' render meshes, world frame."""
        return queries.static_meshes_world(self.bodies, self.nodes, self.render_meshes)

    def state_hash(self) -> str:
        """SHA-256 of every body's full state, the manifolds, world time and gravity."""
        return queries.state_hash(
            self.bodies, self.manifolds, self._time, self._accumulator, self._gravity
        )

    # ------------------------------------------------------------------------------------
    # velocity control
    # ------------------------------------------------------------------------------------
    def _apply_velocity_control(self, dt: float, active: list[tuple[int, Any]]) -> None:
        """Kinematic: integrate the pose once by ``dt``; dynamic: overwrite the velocity.

        Every kinematic pose is computed first (a non-finite one raises ValueError before
        any body moves), then committed. ``active``: ``(body index, control)`` of the
        controls that are on (``VelocityControl.is_active``), listed once per call."""
        from .objects.velocity_control import RigidState

        b = self.bodies
        new_poses = {}
        for index, control in active:
            if b.body_alive[index] and b.body_motion_type[index] == KINEMATIC:
                state = RigidState(
                    mn.Quaternion.from_xyzw(b.body_rotation[index]), b.body_position[index]
                )
                new_poses[index] = control.integrate_transform(dt, state)
        b.body_solver_velocity[:] = 0.0
        b.body_solver_angular_velocity[:] = 0.0
        for index, control in active:
            if not b.body_alive[index]:
                continue
            motion = b.body_motion_type[index]
            linear, angular = control.world_velocities(b.body_rotation[index])
            if motion == KINEMATIC:
                new = new_poses[index]
                self.set_body_pose(index, new._translation, new._rotation, wake=True)
                if linear is not None:
                    b.body_solver_velocity[index] = linear
                if angular is not None:
                    b.body_solver_angular_velocity[index] = angular
            elif motion == DYNAMIC:
                if linear is not None:
                    b.body_linear_velocity[index] = linear
                if angular is not None:
                    b.body_angular_velocity[index] = angular
                wake_body(b, index)
