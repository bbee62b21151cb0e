"""The physics world: bodies, the fixed-step loop and Habitat's ``step_physics`` accumulator.

``World.step`` (here :meth:`PhysicsWorld._step`) reads top to bottom, one stage per banner,
after box2d-lite's ``World::Step`` and Box2D v3's stage list:

1. forces: gravity, applied forces/torques and damping change the velocities;
2. collision: broad phase (AABB pairs), narrow phase (fcl + our manifolds);
3. solve: warm start, sequential impulses by graph color, restitution, split impulses;
4. integrate: positions and rotations, speed clamps, swept tests of fast bodies (CCD);
5. sleep: islands at rest fall asleep, disturbed ones wake.

``step_physics(dt)`` wraps it the way Habitat wraps ``btDiscreteDynamicsWorld::
stepSimulation``: it accumulates ``dt`` and runs whole fixed steps of ``timestep`` (0.008 s
default), so world time lags the requested time by less than one step; ``dt <= 0`` runs
one step. Velocity control acts once per call; applied forces act on every fixed step of
the call and are cleared at its end. Object poses are written to their scene nodes after
the call (:mod:`node_sync`).
"""

from __future__ import annotations

import math
import time as timer
from collections import defaultdict
from typing import Any

import numpy as np

from engine import mn

from . import settings as constants
from .bodies import DYNAMIC, KINEMATIC, STATIC, Bodies
from .collide import boxes_separated, overlapping_pairs, world_aabbs
from .collision_groups import assign_group, filter_pairs
from .constraints import ConstraintStore
from .contacts import FreshPoints, ManifoldStore, feature_length
from .integrate import clamp_speeds, integrate_positions, integrate_velocities
from .narrow_phase import narrow_phase
from .node_sync import NodeSyncMixin
from .quaternions import live_rotations, quat_to_matrix
from .settings import SolverSettings
from .shapes import mesh_shape, probe_geometry
from .sleeping import moving_kinematic_mask, update_sleep, wake_touched
from .solve_stage import solve_stage
from .sweep import sweep_fast_bodies
from .world_api import WorldApiMixin

#: object id of the stage (Habitat's ``RIGID_STAGE_ID`` in rigidsim's numbering).
STAGE_ID = 0
#: m, broad-phase AABB inflation of every body (keeps touching pairs found).
AABB_MARGIN = 0.005
#: pairs, fewest candidate pairs for which the oriented-box pre-test pays for its NumPy calls.
MIN_PAIRS_FOR_BOX_TEST = 8


class PhysicsWorld(WorldApiMixin, NodeSyncMixin):
    """The rigid-body world behind ``Simulator`` (see the module docstring)."""

    def __init__(self, physics_attributes, root_node, object_template_manager,
                 asset_template_manager=None, seed: int = 0) -> None:
        from .objects import RigidObjectManager

        self._timestep = float(physics_attributes.timestep)
        if not (math.isfinite(self._timestep) and self._timestep > 0):
            raise ValueError(f"physics timestep must be > 0, got {self._timestep!r}")
        self._gravity = np.asarray(mn.to_vector3(physics_attributes.gravity, "gravity"))
        self._default_friction = float(physics_attributes.friction_coefficient)
        self._default_restitution = float(physics_attributes.restitution_coefficient)
        self.settings = SolverSettings()
        self.seed = int(seed)
        self.root_node = root_node
        self.asset_template_manager = asset_template_manager
        self.bodies = Bodies()
        self.bodies.add(STAGE_ID)
        self.bodies.body_collidable[STAGE_ID] = False
        self.bodies.body_motion_type[STAGE_ID] = STATIC
        assign_group(self.bodies, STAGE_ID)
        self.fcl_objects: dict[int, list] = {}
        self.probe_objects: dict[int, list] = {}
        self.manifolds = ManifoldStore()
        self.nodes: dict[int, Any] = {}
        self.velocity_controls: dict[int, Any] = {}
        self.render_meshes: dict[int, list] = {}
        self.creation_state: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._init_node_sync()
        self._time = 0.0
        self._accumulator = 0.0
        self.n_overlapping_pairs = 0
        self.last_step = 0.0
        self.last_batch = None  # the solver's last ContactBatch (see solve_stage)
        self.profile: dict[str, float] = defaultdict(float)
        self.rigid_object_manager = RigidObjectManager(self, object_template_manager, root_node)
        self.constraints = ConstraintStore()

    # ------------------------------------------------------------------------------------
    # stage
    # ------------------------------------------------------------------------------------
    def set_stage(self, meshes, stage_attributes) -> None:
        """Use ``meshes`` (world frame, list of MeshData) as the static stage, id 0."""
        b = self.bodies
        if not meshes:
            b.shapes[STAGE_ID], b.body_collidable[STAGE_ID] = [], False
            self.fcl_objects.pop(STAGE_ID, None)
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
        import fcl

        b = self.bodies
        b.shapes[index] = shapes
        self.fcl_objects[index] = [fcl.CollisionObject(s.geometry, fcl.Transform())
                                   for s in shapes]
        self.probe_objects[index] = [
            None if s.kind == "mesh" else fcl.CollisionObject(
                probe_geometry(s, constants.STAGE_SPECULATIVE_DISTANCE), fcl.Transform())
            for s in shapes]
        points = np.concatenate([s.hull_vertices for s in shapes])
        lo, hi = points.min(0), points.max(0)
        b.body_shape_center[index] = 0.5 * (lo + hi)
        b.body_shape_half[index] = 0.5 * (hi - lo)
        b.body_min_half_extent[index] = min(s.min_half_extent for s in shapes)
        self._update_fcl(index)

    def _update_fcl(self, index: int, rotation: np.ndarray | None = None) -> None:
        """Move body ``index``'s fcl objects to its pose (``rotation``: its matrix, if known)."""
        r = quat_to_matrix(self.bodies.body_rotation[index]) if rotation is None else rotation
        self._update_fcl_many(np.array([index]), r[None])

    def _update_fcl_many(self, indices: np.ndarray, rotations: np.ndarray) -> None:
        """Move the fcl objects of bodies ``indices`` (rotation matrices ``(k, 3, 3)``):
        all shape poses ``world_from_shape = pose @ body_from_shape`` in one batch."""
        b = self.bodies
        owners, objects, offsets = [], [], []
        for k, index in enumerate(indices.tolist()):
            for shape, obj, probe in zip(b.shapes[index], self.fcl_objects[index],
                                         self.probe_objects[index], strict=True):
                owners.append(k)
                objects.append((obj, probe))
                offsets.append(shape.body_from_shape)
        if not owners:
            return
        offset = np.array(offsets)
        r = rotations[owners]
        # world_from_shape = [R R_off | R t_off + x] for every shape at once
        shape_rotation = r @ offset[:, :3, :3]
        shape_position = (r @ offset[:, :3, 3:])[..., 0] + b.body_position[indices[owners]]
        for (obj, probe), rot, pos in zip(objects, shape_rotation, shape_position,
                                          strict=True):
            obj.setRotation(rot)
            obj.setTranslation(pos)
            if probe is not None:
                probe.setRotation(rot)
                probe.setTranslation(pos)

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
        if n_steps > constants.MAX_STEPS_PER_CALL:
            raise ValueError(f"dt={dt!r} needs {n_steps} fixed steps of {self._timestep} s; "
                             f"the limit per call is {constants.MAX_STEPS_PER_CALL}")
        self._sync_from_nodes()  # each raises ValueError before it changes anything
        self._apply_velocity_control(dt)
        self._accumulator = accumulated - n_steps * self._timestep
        for _ in range(n_steps):
            for _ in range(max(1, int(self.settings.substeps))):
                self._step(self._timestep / max(1, int(self.settings.substeps)))
            self._time += self._timestep
        self.bodies.body_force[:] = 0.0
        self.bodies.body_torque[:] = 0.0
        self._write_nodes()

    def _step(self, h: float) -> None:
        """One fixed step of length ``h`` seconds (the five stages of the module docstring)."""
        b, clock = self.bodies, timer.perf_counter
        start = clock()
        self.constraints.wake_bodies(self)  # constrained bodies never sleep
        # ---- 1. forces: v += h (g + F/m), w += h I^-1 tau, damping -------------------------
        moving = self._awake_dynamic()
        self.step_start_velocity = np.hstack([b.body_linear_velocity[: b.count],
                                              b.body_angular_velocity[: b.count]])
        integrate_velocities(b, moving, self._gravity, h)
        t_forces = clock()
        # ---- 2. collision: broad phase pairs, narrow phase contacts, persistent manifolds --
        self._update_contacts()
        if wake_touched(b, self.manifolds):  # a body hit this step must be able to move
            moving = self._awake_dynamic()
        t_collide = clock()
        # ---- 3. solve: warm start, sequential impulses by color, restitution, split impulses
        pseudo = solve_stage(self, moving, h)
        self.constraints.solve(self, moving, h)  # rigid constraints (constraints.py)
        t_solve = clock()
        # ---- 4. integrate: clamp speeds, x += h v, rotate, sweep fast bodies -------------
        clamp_speeds(b, moving, constants.MAX_LINEAR_SPEED, constants.MAX_ANGULAR_SPEED)
        old_position = b.body_position[moving].copy()
        extra_lin = None if pseudo is None else pseudo[moving, :3]
        extra_ang = None if pseudo is None else pseudo[moving, 3:]
        integrate_positions(b, moving, h, extra_lin, extra_ang)
        sweep_fast_bodies(self, moving, old_position)
        # ---- 5. sleep: resting islands fall asleep, disturbed ones wake --------------------
        update_sleep(b, self.manifolds, h, self._overlapping_bodies())
        end = clock()
        for name, t0, t1 in (("forces", start, t_forces), ("collide", t_forces, t_collide),
                             ("solve", t_collide, t_solve), ("integrate+sleep", t_solve, end)):
            self.profile[name] += t1 - t0
        self.last_step = end - start

    def _overlapping_bodies(self) -> np.ndarray | None:
        """Bodies of this step's solved contacts deeper than ``SLEEP_MAX_PENETRATION``."""
        batch = self.last_batch
        if batch is None:
            return None
        deep = batch.depth.max(axis=1) > constants.SLEEP_MAX_PENETRATION
        return batch.pair_index[deep].ravel()

    def _awake_dynamic(self) -> np.ndarray:
        b, n = self.bodies, self.bodies.count
        mask = b.body_alive[:n] & b.body_awake[:n] & (b.body_motion_type[:n] == DYNAMIC)
        return np.nonzero(mask)[0]

    # ------------------------------------------------------------------------------------
    # collision stage
    # ------------------------------------------------------------------------------------
    def _update_contacts(self) -> None:
        """Broad phase over all collidable bodies, then refresh the manifolds of each pair."""
        b, n = self.bodies, self.bodies.count
        start = timer.perf_counter()
        # every live object has shapes; the stage without shapes is not collidable
        candidates = np.nonzero(b.body_alive[:n] & b.body_collidable[:n])[0]
        rotation = live_rotations(b)
        live = np.flatnonzero(b.body_alive[:n])  # freed slots cost nothing
        lo, hi = world_aabbs(b.body_shape_center[live], b.body_shape_half[live],
                             b.body_position[live], b.body_rotation[live])
        b.body_aabb_min[live], b.body_aabb_max[live] = lo - AABB_MARGIN, hi + AABB_MARGIN
        # the stage also covers the speculative distance of its contacts
        b.body_aabb_min[STAGE_ID] -= constants.STAGE_SPECULATIVE_DISTANCE
        b.body_aabb_max[STAGE_ID] += constants.STAGE_SPECULATIVE_DISTANCE
        dynamic = b.body_motion_type[:n] == DYNAMIC
        active = (dynamic & b.body_awake[:n]) | moving_kinematic_mask(b, n)
        pairs = overlapping_pairs(b.body_aabb_min[:n], b.body_aabb_max[:n], candidates, active)
        pairs = pairs[dynamic[pairs[:, 0]] | dynamic[pairs[:, 1]]]
        pairs = filter_pairs(b, pairs)  # collision groups and masks
        self.n_overlapping_pairs = len(pairs)
        pair_list = pairs.tolist()
        apart = self._apart_without_manifold(pairs, pair_list, rotation)
        self.profile["broad phase"] += timer.perf_counter() - start
        touching = [pair for k, pair in enumerate(pair_list) if k not in apart]
        if touching:
            involved = np.unique(np.array(touching))
            involved = involved[involved != STAGE_ID]
            self._update_fcl_many(involved, rotation[involved])
        self._update_manifolds(touching, rotation)
        self._drop_stale_manifolds(pairs, active)

    def _drop_stale_manifolds(self, pairs: np.ndarray, active: np.ndarray) -> None:
        """Delete the manifolds of pairs that left the broad phase while one of them moved
        (or died); a sleeping pair keeps its manifold for when it wakes."""
        b, n, store = self.bodies, self.bodies.count, self.manifolds
        rows = store.rows()
        a, c = store.bodies[rows, 0], store.bodies[rows, 1]
        # a pair (a, c) as the single integer a n + c, to test membership in one call
        listed = np.isin(a * n + c, pairs[:, 0] * n + pairs[:, 1])
        moved = active[a] | active[c] | ~b.body_alive[a] | ~b.body_alive[c]
        for key in store.bodies[rows[~listed & moved]].tolist():
            del store[tuple(key)]

    def _apart_without_manifold(self, pairs: np.ndarray, pair_list: list,
                                rotation: np.ndarray) -> set:
        """Positions in ``pairs`` of body pairs without a manifold whose boxes are disjoint.

        The box test costs a fixed ~40 NumPy calls, so it runs only when enough pairs could
        be skipped to pay for it (``MIN_PAIRS_FOR_BOX_TEST``).
        """
        check = [k for k, (a, c) in enumerate(pair_list)
                 if a != STAGE_ID and (a, c) not in self.manifolds]
        if len(check) < MIN_PAIRS_FOR_BOX_TEST:
            return set()
        apart = self._boxes_apart(pairs[check], rotation)
        return {check[k] for k in np.nonzero(apart)[0].tolist()}

    def _boxes_apart(self, pairs: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """(p,) bool: body pairs (stage excluded) whose body-frame AABBs cannot touch.

        Every body's shapes lie inside its body-frame AABB (center ``c``, half extents ``h``),
        an oriented box in the world. Rotated boxes' world AABBs overlap long before the
        boxes touch, so this exact oriented-box test skips many narrow-phase calls that could
        only answer "no contact".
        """
        b = self.bodies
        a, c = pairs[:, 0], pairs[:, 1]
        # box center in the world: x + R c
        center_a = b.body_position[a] + (rotation[a] @ b.body_shape_center[a][:, :, None])[..., 0]
        center_c = b.body_position[c] + (rotation[c] @ b.body_shape_center[c][:, :, None])[..., 0]
        apart = boxes_separated(center_a, rotation[a], b.body_shape_half[a] + AABB_MARGIN,
                                center_c, rotation[c], b.body_shape_half[c] + AABB_MARGIN)
        return apart & (a != STAGE_ID)

    def _update_manifolds(self, pairs: list, rotation: np.ndarray) -> None:
        """Narrow phase for ``pairs``, then refresh/merge/reduce their manifolds in one batch.

        A pair gets a manifold row when it first has contact points; pairs with a sphere
        keep a single (rolling) point.
        """
        b = self.bodies
        pair_position, point_a, point_b, normal = narrow_phase(self, pairs, rotation)
        has_points = np.bincount(pair_position, minlength=len(pairs)) > 0
        rows, updated = [], []
        for k, key in enumerate(pairs):
            row = self.manifolds.row(tuple(key))
            if row is None:
                if not has_points[k]:
                    continue
                rolling = any(s.kind == "sphere" for s in b.shapes[key[0]] + b.shapes[key[1]])
                thickness = [math.inf if i == STAGE_ID else 2.0 * b.body_min_half_extent[i]
                             for i in key]
                row = self.manifolds.add(tuple(key),
                                         1 if rolling else constants.MAX_MANIFOLD_POINTS,
                                         feature_length(*thickness))
            rows.append(row)
            updated.append(k)
        row_position = np.full(len(pairs), -1, dtype=np.int64)
        row_position[updated] = np.arange(len(updated))  # pair position -> row position
        fresh = FreshPoints(len(rows), row_position[pair_position], point_a, point_b, normal)
        self.manifolds.update(np.array(rows, dtype=np.int64), rotation, b.body_position,
                              fresh)

    def perform_discrete_collision_detection(self) -> None:
        """Run the collision stage without stepping (refreshes contact points)."""
        self._sync_from_nodes()
        self._update_contacts()

    # ------------------------------------------------------------------------------------
    # velocity control
    # ------------------------------------------------------------------------------------
    def _apply_velocity_control(self, dt: float) -> None:
        """Kinematic: integrate the pose once by ``dt``; dynamic: overwrite the velocity.

        Every kinematic pose is computed first (a non-finite one raises ValueError before
        any body moves), then committed."""
        from .velocity_control import RigidState

        b = self.bodies
        new_poses = {}
        for index, control in self.velocity_controls.items():
            if (b.body_alive[index] and b.body_motion_type[index] == KINEMATIC
                    and (control.controlling_lin_vel or control.controlling_ang_vel)):
                state = RigidState(mn.Quaternion.from_xyzw(b.body_rotation[index]),
                                   b.body_position[index])
                new_poses[index] = control.integrate_transform(dt, state)
        b.body_solver_velocity[:] = 0.0
        b.body_solver_angular_velocity[:] = 0.0
        for index, control in self.velocity_controls.items():
            if not b.body_alive[index]:
                continue
            if not (control.controlling_lin_vel or control.controlling_ang_vel):
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
                self.wake(index)
