"""``ManagedRigidObject``: one rigid object's dynamics (Habitat's ``ManagedRigidBase`` and
``ManagedRigidObject``, including the spelling ``intertia``) on top of
:class:`~engine.physics.objects.physics_object.ManagedPhysicsObject` (identity, nodes, motion type,
pose, sleep state).

Velocities world frame (m/s, rad/s); forces world frame (N) at a world-frame offset from
the COM. Every setter validates first, including overflow (:mod:`object_checks`), then
writes the world's ``body_*`` arrays and wakes the body. KINEMATIC objects store velocities
without moving; forces and impulses act only on DYNAMIC objects.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine import mn
from engine.templates.attributes import check_inertia

from ..collision.collision_groups import assign_group
from ..core.bodies import DYNAMIC, KINEMATIC, STATIC
from ..solver.integrate import world_inverse_inertia
from .mass_ratio import warn_beyond_stable_ratio
from .object_checks import DeadObjectError, finite_result, number_argument, quiet_overflow
from .physics_object import ManagedPhysicsObject

__all__ = ["KINEMATIC", "DeadObjectError", "ManagedRigidObject"]


class ManagedRigidObject(ManagedPhysicsObject):
    """A rigid object in the world (Habitat's ``ManagedRigidObject``); see the module
    docstring and :class:`ManagedPhysicsObject` for what it inherits."""

    # -- rigid-body properties -------------------------------------------------------------
    @property
    def velocity_control(self):
        """The object's own :class:`VelocityControl` (by reference)."""
        return self._world.velocity_controls[self._check()]

    @property
    def margin(self) -> float:
        self._check()
        return float(self._template.margin)

    @property
    def aabb(self) -> mn.Range3D:
        """Render-mesh AABB in the object's local (COM) frame."""
        self._check()
        return mn.Range3D(self._description.aabb_min, self._description.aabb_max)

    @property
    def collision_shape_aabb(self) -> mn.Range3D:
        """AABB of the collision shapes in the object's local (COM) frame."""
        index = self._check()
        b = self._world.bodies
        center, half = b.body_shape_center[index], b.body_shape_half[index]
        return mn.Range3D(center - half, center + half)

    @property
    def is_articulated(self) -> bool:
        """Always False: rigid objects are not articulated (Habitat's flag)."""
        self._check()
        return False

    def override_collision_group(self, group: Any) -> None:
        """Put the object in collision ``group`` (a ``CollisionGroups`` bit) for good, instead
        of the group of its motion type; its mask is the group's (CollisionGroupHelper)."""
        from ..collision.collision_groups import CollisionGroupHelper

        value = CollisionGroupHelper._check(group)  # ValueError for non-groups
        index = self._check()
        self._wake_island(index)
        assign_group(self._world.bodies, index, value)
        self._wake(index)

    @property
    def collision_group(self):
        """The object's current collision group (override, or from its motion type)."""
        from ..collision.collision_groups import CollisionGroups

        return CollisionGroups(int(self._world.bodies.body_collision_group[self._check()]))

    @property
    def com(self) -> mn.Vector3:
        """Center of mass in the asset frame (the offset of the visual node is ``-com``)."""
        self._check()
        return mn.Vector3(self._description.com)

    # -- velocities ------------------------------------------------------------------------------
    def _set_velocity(self, name: str, value: Any, label: str) -> None:
        velocity = np.asarray(mn.to_vector3(value, label))
        index = self._check()
        b = self._world.bodies
        if b.body_motion_type[index] == STATIC:
            return
        getattr(b, name)[index] = velocity
        self._wake(index)

    @property
    def linear_velocity(self) -> mn.Vector3:
        """World frame, m/s (KINEMATIC: the stored value)."""
        return mn.Vector3(self._world.bodies.body_linear_velocity[self._check()])

    @linear_velocity.setter
    def linear_velocity(self, value: Any) -> None:
        self._set_velocity("body_linear_velocity", value, "linear_velocity")

    @property
    def angular_velocity(self) -> mn.Vector3:
        """World frame, rad/s."""
        return mn.Vector3(self._world.bodies.body_angular_velocity[self._check()])

    @angular_velocity.setter
    def angular_velocity(self, value: Any) -> None:
        self._set_velocity("body_angular_velocity", value, "angular_velocity")

    # -- forces and impulses -------------------------------------------------------------------
    def _dynamic_index(self):
        index = self._check()
        b = self._world.bodies
        return index if b.body_motion_type[index] == DYNAMIC else None

    @quiet_overflow
    def apply_force(self, force: Any, relative_position: Any) -> None:
        """Force (N, world frame) at a world-frame offset from the COM, for the next
        ``step_physics`` call: ``F += f``, ``tau += r x f``."""
        f = np.asarray(mn.to_vector3(force, "force"))
        r = np.asarray(mn.to_vector3(relative_position, "relative_position"))
        index = self._dynamic_index()
        if index is None:
            return
        b = self._world.bodies
        total_force = finite_result(b.body_force[index] + f, "force", "total force")
        torque = finite_result(np.cross(r, f), "relative_position", "torque")
        total_torque = finite_result(b.body_torque[index] + torque, "force", "total torque")
        self._check_force_step(index, total_force, total_torque, "force")
        b.body_force[index] = total_force
        b.body_torque[index] = total_torque
        self._wake(index)

    @quiet_overflow
    def apply_torque(self, torque: Any) -> None:
        """Torque (N m, world frame) for the next ``step_physics`` call."""
        tau = np.asarray(mn.to_vector3(torque, "torque"))
        index = self._dynamic_index()
        if index is not None:
            b = self._world.bodies
            total = finite_result(b.body_torque[index] + tau, "torque", "total torque")
            self._check_force_step(index, b.body_force[index], total, "torque")
            b.body_torque[index] = total
            self._wake(index)

    def _check_force_step(
        self, index: int, force: np.ndarray, torque: np.ndarray, name: str
    ) -> None:
        """Refuse a force/torque whose velocity change over one fixed step,
        ``h F / m`` and ``h I_w^-1 tau``, or the velocity it leads to, is not finite."""
        b, h = self._world.bodies, self._world.get_physics_time_step()
        dv = finite_result(h * (force / b.body_mass[index]), name, "velocity change")
        finite_result(b.body_linear_velocity[index] + dv, name, "linear velocity")
        inv = world_inverse_inertia(b.body_rotation[index][None], b.body_inertia[index][None])[0]
        dw = finite_result(h * (inv @ torque), name, "angular velocity change")
        finite_result(b.body_angular_velocity[index] + dw, name, "angular velocity")

    @quiet_overflow
    def apply_impulse(self, impulse: Any, relative_position: Any) -> None:
        """Instant impulse (N s, world) at a world offset: ``v += J/m``, ``w += I^-1 (r x J)``."""
        j = np.asarray(mn.to_vector3(impulse, "impulse"))
        r = np.asarray(mn.to_vector3(relative_position, "relative_position"))
        index = self._dynamic_index()
        if index is None:
            return
        b = self._world.bodies
        linear = finite_result(
            b.body_linear_velocity[index] + j / b.body_mass[index], "impulse", "linear velocity"
        )
        angular = self._angular_after(index, np.cross(r, j), "impulse")
        b.body_linear_velocity[index] = linear
        b.body_angular_velocity[index] = angular
        self._wake(index)

    @quiet_overflow
    def apply_impulse_torque(self, impulse: Any) -> None:
        """Instant angular impulse (N m s, world): ``w += I_w^-1 L``."""
        angular = np.asarray(mn.to_vector3(impulse, "impulse"))
        index = self._dynamic_index()
        if index is not None:
            new = self._angular_after(index, angular, "impulse")
            self._world.bodies.body_angular_velocity[index] = new
            self._wake(index)

    def _angular_after(self, index: int, angular: np.ndarray, name: str) -> np.ndarray:
        """Candidate angular velocity after an angular impulse: ``w + I_w^-1 L``, finite."""
        b = self._world.bodies
        finite_result(angular, name, "angular impulse")
        inv = world_inverse_inertia(b.body_rotation[index][None], b.body_inertia[index][None])[0]
        return finite_result(
            b.body_angular_velocity[index] + inv @ angular, name, "angular velocity"
        )

    # -- material and mass ---------------------------------------------------------------------
    def _scalar(self, name: str) -> float:
        return float(getattr(self._world.bodies, name)[self._check()])

    def _set_scalar(self, name: str, value: float) -> None:
        index = self._check()
        getattr(self._world.bodies, name)[index] = value
        self._wake(index)

    @property
    def mass(self) -> float:
        """kg. Setting it keeps the inertia (as Bullet's ``setMassProps`` call in Habitat)."""
        return self._scalar("body_mass")

    @mass.setter
    @quiet_overflow
    def mass(self, value: Any) -> None:
        mass = number_argument(value, "mass", 0.0, low_open=True)
        index = self._check()
        b = self._world.bodies
        # a pending force must still give a finite velocity change h F / m
        finite_result(
            self._world.get_physics_time_step() * b.body_force[index] / mass,
            "mass",
            "velocity change under the pending force",
        )
        self._set_scalar("body_mass", mass)
        warn_beyond_stable_ratio(self._world.bodies, index, self._world.mass_ratio_warned)

    @property
    def intertia_diagonal(self) -> mn.Vector3:  # Habitat's spelling
        """Diagonal inertia about the COM, object axes, kg m^2."""
        return mn.Vector3(self._world.bodies.body_inertia[self._check()])

    @intertia_diagonal.setter
    def intertia_diagonal(self, value: Any) -> None:
        inertia = check_inertia(
            np.asarray(mn.to_vector3(value, "intertia_diagonal")), "intertia_diagonal"
        )
        index = self._check()
        self._world.bodies.body_inertia[index] = inertia
        self._wake(index)

    inertia_diagonal = intertia_diagonal

    @property
    def rolling_friction_coefficient(self) -> float:
        """Rolling resistance (Bullet's): the contact torque opposing rolling is at most
        ``mu_roll N`` (N m for a normal force N), with the pair value
        ``r_a f_b + r_b f_a`` (see :mod:`engine.physics.solver.rolling_friction`)."""
        return self._scalar("body_rolling_friction")

    @rolling_friction_coefficient.setter
    def rolling_friction_coefficient(self, value: Any) -> None:
        self._set_scalar(
            "body_rolling_friction", number_argument(value, "rolling_friction_coefficient", 0.0)
        )

    @property
    def spinning_friction_coefficient(self) -> float:
        """Spinning (torsional) resistance: the contact torque about the normal is at most
        ``mu_spin N``, pair value ``s_a f_b + s_b f_a``."""
        return self._scalar("body_spinning_friction")

    @spinning_friction_coefficient.setter
    def spinning_friction_coefficient(self, value: Any) -> None:
        self._set_scalar(
            "body_spinning_friction", number_argument(value, "spinning_friction_coefficient", 0.0)
        )

    @property
    def friction_coefficient(self) -> float:
        return self._scalar("body_friction")

    @friction_coefficient.setter
    def friction_coefficient(self, value: Any) -> None:
        self._set_scalar("body_friction", number_argument(value, "friction_coefficient", 0.0))

    @property
    def restitution_coefficient(self) -> float:
        return self._scalar("body_restitution")

    @restitution_coefficient.setter
    def restitution_coefficient(self, value: Any) -> None:
        self._set_scalar(
            "body_restitution", number_argument(value, "restitution_coefficient", 0.0, 1.0)
        )

    @property
    def linear_damping(self) -> float:
        return self._scalar("body_linear_damping")

    @linear_damping.setter
    def linear_damping(self, value: Any) -> None:
        self._set_scalar("body_linear_damping", number_argument(value, "linear_damping", 0.0, 1.0))

    @property
    def angular_damping(self) -> float:
        return self._scalar("body_angular_damping")

    @angular_damping.setter
    def angular_damping(self, value: Any) -> None:
        self._set_scalar(
            "body_angular_damping", number_argument(value, "angular_damping", 0.0, 1.0)
        )

    # -- collisions and semantics ---------------------------------------------------------
    @property
    def collidable(self) -> bool:
        return bool(self._world.bodies.body_collidable[self._check()])

    @collidable.setter
    def collidable(self, value: Any) -> None:
        if not isinstance(value, bool | np.bool_):
            raise TypeError(f"collidable must be a bool, got {value!r}")
        index = self._check()
        self._wake_island(index)
        self._world.bodies.body_collidable[index] = bool(value)
        for key in [k for k in self._world.manifolds if index in k]:
            del self._world.manifolds[key]
        self._wake(index)

    @property
    def semantic_id(self) -> int:
        self._check()
        drawables = self.visual_drawables()
        return int(drawables[0].semantic_id) if drawables else int(self._template.semantic_id)

    @semantic_id.setter
    def semantic_id(self, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
            raise ValueError(f"semantic_id must be a non-negative int, got {value!r}")
        self._check()
        for drawable in self.visual_drawables():
            drawable.semantic_id = int(value)
        for node in self.visual_scene_nodes:
            node._semantic_id = int(value)
