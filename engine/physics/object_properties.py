"""``ManagedRigidObject``: one rigid object's properties and actions (Habitat's names,
including ``intertia``), a thin handle on one body of the :class:`PhysicsWorld`.

Every getter returns a copy; every setter validates first (ValueError/TypeError naming the
value) and only then writes the world's ``body_*`` arrays, so bad input changes nothing.
Validation includes overflow: a setter computes its candidate result (the new pose, the
velocity after an impulse, the velocity change a force makes over one fixed step), checks it
is finite, and only then commits it, so ``translate([1e308, 0, 0])`` twice is refused the
second time with the body unchanged.
STATIC objects ignore pose setters; KINEMATIC objects store velocities without moving;
forces and impulses act only on DYNAMIC objects. Pose and velocity writes wake the body.
"""

from __future__ import annotations

import copy
import functools
import math
from typing import Any

import numpy as np

from engine import mn
from engine.attributes import check_inertia
from engine.fixed_fields import public_names, unknown_attribute_error
from engine.mn.vectors import stable_norm

from .bodies import DYNAMIC, KINEMATIC, STATIC
from .collision_groups import assign_group
from .integrate import world_inverse_inertia
from .motion_type import MotionType
from .node_sync import canonical_sign
from .quaternions import matrix_to_quat, quat_multiply, quat_to_matrix
from .queries import contact_test
from .settings import (
    MIN_AXIS_SCALE,
    MIN_QUATERNION_NORM,
    ORTHOGONALITY_TOLERANCE,
    TIME_TO_SLEEP,
)
from .sleeping import wake_body, wake_island
from .velocity_control import RigidState


def _number(
    value: Any, name: str, low: float = -math.inf, high: float = math.inf, low_open: bool = False
) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise TypeError(f"{name} must be a number, got {value!r}")
    number = float(value)
    if not math.isfinite(number) or number < low or number > high or (low_open and number <= low):
        bound = ">" if low_open else ">="
        raise ValueError(f"{name} must be finite, {bound} {low} and <= {high}, got {value!r}")
    return number


def _quiet_overflow(method):
    """Run ``method`` with NumPy's overflow warnings off: it checks its results itself."""

    @functools.wraps(method)
    def wrapped(*args, **kwargs):
        with np.errstate(over="ignore", invalid="ignore"):
            return method(*args, **kwargs)

    return wrapped


def _finite_result(value: np.ndarray, name: str, what: str) -> np.ndarray:
    """``value`` if every component is finite, else a ValueError naming the argument."""
    if not np.all(np.isfinite(value)):
        raise ValueError(
            f"{name} is too large: it would make a non-finite {what} "
            f"({np.asarray(value).tolist()}); the object is unchanged"
        )
    return value


def _angle(value: Any) -> float:
    return float(
        mn.Rad(_number(float(mn.Rad(value)) if isinstance(value, mn.Deg) else value, "angle"))
    )


class DeadObjectError(RuntimeError):
    """Raised when a removed object (``is_alive == False``) is used."""


class ManagedRigidObject:
    """A rigid object in the world (Habitat's ``ManagedRigidObject``).

    Frames: ``translation`` is the center of mass in the world frame (m); ``rotation`` the
    world_from_object quaternion; velocities world frame (m/s, rad/s); forces world frame (N)
    at a world-frame offset from the COM.
    """

    def __init__(self, world, index, handle, template, description, root, visual) -> None:
        self._world, self._index, self._handle = world, index, handle
        self._template = copy.copy(template.copy())
        self._user_attributes = template.get_user_config().copy()
        self._description = description
        self._root_node, self._visual_node = root, visual
        self._alive = True

    @property
    def is_alive(self) -> bool:
        """False once the object was removed from the world."""
        return self._alive

    def _check(self) -> int:
        if not self._alive:
            raise DeadObjectError(f"rigid object {self._handle!r} was removed (is_alive False)")
        return self._index

    def _wake(self, index: int) -> None:
        wake_body(self._world.bodies, index)

    def _wake_island(self, index: int) -> None:
        """Wake the bodies resting on (touching) body ``index`` before it changes."""
        wake_island(self._world.bodies, self._world.manifolds, index)

    def __repr__(self) -> str:
        state = "alive" if self._alive else "removed"
        return f"<ManagedRigidObject {self._handle!r} id={self._index} {state}>"

    # -- fixed fields (Habitat's wrapper is a C++ binding: no new attributes) ---------------
    def __setattr__(self, name: str, value) -> None:
        if name.startswith("_") or isinstance(getattr(type(self), name, None), property):
            object.__setattr__(self, name, value)  # read-only properties raise themselves
            return
        raise unknown_attribute_error(type(self).__name__, name, public_names(type(self)))

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        raise unknown_attribute_error(type(self).__name__, name, public_names(type(self)))

    # -- identity ------------------------------------------------------------------------------
    @property
    def handle(self) -> str:
        self._check()
        return self._handle

    @property
    def object_id(self) -> int:
        return self._check()

    @property
    def creation_attributes(self):
        """A copy of the template the object was created from."""
        self._check()
        return self._template.copy()

    @property
    def user_attributes(self):
        """The object's own user configuration (a copy of the template's at creation)."""
        self._check()
        return self._user_attributes

    @property
    def root_scene_node(self):
        self._check()
        return self._root_node

    @property
    def visual_scene_nodes(self) -> list:
        self._check()
        return [self._visual_node]

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
        from .collision_groups import CollisionGroupHelper

        value = CollisionGroupHelper._check(group)  # ValueError for non-groups
        index = self._check()
        self._wake_island(index)
        assign_group(self._world.bodies, index, value)
        self._wake(index)

    @property
    def collision_group(self):
        """The object's current collision group (override, or from its motion type)."""
        from .collision_groups import CollisionGroups

        return CollisionGroups(int(self._world.bodies.body_collision_group[self._check()]))

    @property
    def com(self) -> mn.Vector3:
        """Center of mass in the asset frame (the offset of the visual node is ``-com``)."""
        self._check()
        return mn.Vector3(self._description.com)

    # -- motion type ---------------------------------------------------------------------------
    @property
    def motion_type(self):
        return MotionType(int(self._world.bodies.body_motion_type[self._check()]))

    @motion_type.setter
    def motion_type(self, value: Any) -> None:
        index = self._check()
        valid = (STATIC, KINEMATIC, DYNAMIC)
        if isinstance(value, bool) or not isinstance(value, int) or value not in valid:
            raise ValueError(f"motion_type must be STATIC, KINEMATIC or DYNAMIC, got {value!r}")
        b = self._world.bodies
        if b.body_motion_type[index] == int(value):
            return
        b.body_motion_type[index] = int(value)
        assign_group(b, index)  # a new motion type resets the collision group (Habitat)
        if value != DYNAMIC:
            b.body_awake[index] = True
        self._wake(index)
        self._wake_island(index)

    # -- pose ----------------------------------------------------------------------------------
    def _set_pose(self, position: np.ndarray, rotation: np.ndarray, name: str = "pose") -> None:
        """Validate the candidate pose (finite position, non-zero finite quaternion), then
        teleport the body; ``name`` is the argument blamed when it is not."""
        index = self._check()
        _finite_result(position, name, "position")
        norm = float(stable_norm(rotation))
        if not (np.isfinite(norm) and norm > MIN_QUATERNION_NORM):
            raise ValueError(f"{name} would make a degenerate rotation {rotation.tolist()}")
        _finite_result(rotation / norm, name, "rotation")
        if self._world.bodies.body_motion_type[index] == STATIC:
            return  # Habitat: STATIC objects silently ignore pose setters
        self._world.set_body_pose(index, position, rotation / norm)

    @property
    def translation(self) -> mn.Vector3:
        """Center of mass, world frame, m."""
        return mn.Vector3(self._world.bodies.body_position[self._check()])

    @translation.setter
    def translation(self, value: Any) -> None:
        position = np.asarray(mn.to_vector3(value, "translation"))
        self._set_pose(
            position, self._world.bodies.body_rotation[self._check()].copy(), "translation"
        )

    @property
    def rotation(self) -> mn.Quaternion:
        """world_from_object. DYNAMIC objects report the sign Habitat's do (its nodes take
        the pose from Bullet through a matrix: ``w > 0`` near the identity); KINEMATIC and
        STATIC ones keep the sign they were given, step after step."""
        index = self._check()
        b = self._world.bodies
        rotation = b.body_rotation[index]
        if b.body_motion_type[index] == DYNAMIC:
            rotation = canonical_sign(rotation[None])[0]
        return mn.Quaternion.from_xyzw(rotation)

    @rotation.setter
    def rotation(self, value: Any) -> None:
        rotation = mn.to_quaternion(value, "rotation").xyzw
        self._set_pose(self._world.bodies.body_position[self._check()].copy(), rotation, "rotation")

    @property
    def transformation(self) -> mn.Matrix4:
        index = self._check()
        b = self._world.bodies
        return mn.Matrix4.from_(quat_to_matrix(b.body_rotation[index]), b.body_position[index])

    @transformation.setter
    def transformation(self, value: Any) -> None:
        self._check()
        matrix = np.asarray(value, dtype=np.float64) if not isinstance(value, str) else None
        if matrix is None or matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
            raise ValueError(f"transformation must be a finite 4x4 matrix, got {value!r}")
        scale = stable_norm(matrix[:3, :3], axis=0)
        if np.any(scale < MIN_AXIS_SCALE) or not np.all(np.isfinite(scale)):
            raise ValueError(f"transformation has a degenerate rotation part: {value!r}")
        rotation_matrix = matrix[:3, :3] / scale
        if np.linalg.det(rotation_matrix) < 0.0:
            raise ValueError(f"transformation is a reflection (negative determinant): {value!r}")
        if not np.allclose(
            rotation_matrix.T @ rotation_matrix, np.eye(3), atol=ORTHOGONALITY_TOLERANCE
        ):
            raise ValueError(f"transformation has a shear (its axes are not orthogonal): {value!r}")
        rotation = matrix_to_quat(rotation_matrix)
        current = self._world.bodies.body_rotation[self._check()]
        if float(rotation @ current) < 0.0:  # q and -q are one rotation: keep the sign
            rotation = -rotation
        self._set_pose(matrix[:3, 3].copy(), rotation, "transformation")

    @property
    def rigid_state(self) -> RigidState:
        return RigidState(self.rotation, self.translation)

    @rigid_state.setter
    def rigid_state(self, value: Any) -> None:
        self._check()
        if not isinstance(value, RigidState):
            raise TypeError(f"rigid_state must be a RigidState, got {value!r}")
        self._set_pose(value._translation.copy(), value._rotation.copy(), "rigid_state")

    @_quiet_overflow
    def translate(self, vector: Any) -> None:
        """Move by ``vector`` (world frame, m)."""
        offset = np.asarray(mn.to_vector3(vector, "vector"))
        index = self._check()
        self._set_pose(
            self._world.bodies.body_position[index] + offset,
            self._world.bodies.body_rotation[index].copy(),
            "vector",
        )

    @_quiet_overflow
    def translate_local(self, vector: Any) -> None:
        """Move by ``vector`` given in the object's frame."""
        offset = np.asarray(mn.to_vector3(vector, "vector"))
        index = self._check()
        b = self._world.bodies
        self._set_pose(
            b.body_position[index] + quat_to_matrix(b.body_rotation[index]) @ offset,
            b.body_rotation[index].copy(),
            "vector",
        )

    def rotate(self, angle: Any, axis: Any, local: bool = False) -> None:
        """Rotate by ``angle`` (Rad/Deg) about ``axis``: world axes (``q' = r q``) or local
        (``q' = q r``)."""
        turn = mn.Quaternion.rotation(mn.Rad(_angle(angle)), axis).xyzw
        index = self._check()
        b = self._world.bodies
        q = b.body_rotation[index]
        new = quat_multiply(q, turn) if local else quat_multiply(turn, q)
        self._set_pose(b.body_position[index].copy(), new, "angle")

    def rotate_local(self, angle: Any, axis: Any) -> None:
        self.rotate(angle, axis, local=True)

    def rotate_x(self, angle: Any) -> None:
        self.rotate(angle, (1.0, 0.0, 0.0))

    def rotate_y(self, angle: Any) -> None:
        self.rotate(angle, (0.0, 1.0, 0.0))

    def rotate_z(self, angle: Any) -> None:
        self.rotate(angle, (0.0, 0.0, 1.0))

    def rotate_x_local(self, angle: Any) -> None:
        self.rotate(angle, (1.0, 0.0, 0.0), local=True)

    def rotate_y_local(self, angle: Any) -> None:
        self.rotate(angle, (0.0, 1.0, 0.0), local=True)

    def rotate_z_local(self, angle: Any) -> None:
        self.rotate(angle, (0.0, 0.0, 1.0), local=True)

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

    @_quiet_overflow
    def apply_force(self, force: Any, relative_position: Any) -> None:
        """Force (N, world frame) at a world-frame offset from the COM, for the next
        ``step_physics`` call: ``F += f``, ``tau += r x f``."""
        f = np.asarray(mn.to_vector3(force, "force"))
        r = np.asarray(mn.to_vector3(relative_position, "relative_position"))
        index = self._dynamic_index()
        if index is None:
            return
        b = self._world.bodies
        total_force = _finite_result(b.body_force[index] + f, "force", "total force")
        torque = _finite_result(np.cross(r, f), "relative_position", "torque")
        total_torque = _finite_result(b.body_torque[index] + torque, "force", "total torque")
        self._check_force_step(index, total_force, total_torque, "force")
        b.body_force[index] = total_force
        b.body_torque[index] = total_torque
        self._wake(index)

    @_quiet_overflow
    def apply_torque(self, torque: Any) -> None:
        """Torque (N m, world frame) for the next ``step_physics`` call."""
        tau = np.asarray(mn.to_vector3(torque, "torque"))
        index = self._dynamic_index()
        if index is not None:
            b = self._world.bodies
            total = _finite_result(b.body_torque[index] + tau, "torque", "total torque")
            self._check_force_step(index, b.body_force[index], total, "torque")
            b.body_torque[index] = total
            self._wake(index)

    def _check_force_step(
        self, index: int, force: np.ndarray, torque: np.ndarray, name: str
    ) -> None:
        """Refuse a force/torque whose velocity change over one fixed step,
        ``h F / m`` and ``h I_w^-1 tau``, or the velocity it leads to, is not finite."""
        b, h = self._world.bodies, self._world.get_physics_time_step()
        dv = _finite_result(h * (force / b.body_mass[index]), name, "velocity change")
        _finite_result(b.body_linear_velocity[index] + dv, name, "linear velocity")
        inv = world_inverse_inertia(b.body_rotation[index][None], b.body_inertia[index][None])[0]
        dw = _finite_result(h * (inv @ torque), name, "angular velocity change")
        _finite_result(b.body_angular_velocity[index] + dw, name, "angular velocity")

    @_quiet_overflow
    def apply_impulse(self, impulse: Any, relative_position: Any) -> None:
        """Instant impulse (N s, world) at a world offset: ``v += J/m``, ``w += I^-1 (r x J)``."""
        j = np.asarray(mn.to_vector3(impulse, "impulse"))
        r = np.asarray(mn.to_vector3(relative_position, "relative_position"))
        index = self._dynamic_index()
        if index is None:
            return
        b = self._world.bodies
        linear = _finite_result(
            b.body_linear_velocity[index] + j / b.body_mass[index], "impulse", "linear velocity"
        )
        angular = self._angular_after(index, np.cross(r, j), "impulse")
        b.body_linear_velocity[index] = linear
        b.body_angular_velocity[index] = angular
        self._wake(index)

    @_quiet_overflow
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
        _finite_result(angular, name, "angular impulse")
        inv = world_inverse_inertia(b.body_rotation[index][None], b.body_inertia[index][None])[0]
        return _finite_result(
            b.body_angular_velocity[index] + inv @ angular, name, "angular velocity"
        )

    def contact_test(self) -> bool:
        """True if the object currently overlaps another collidable object or the stage."""
        return contact_test(self._world.bodies, self._world.collision_objects, self._check())

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
    @_quiet_overflow
    def mass(self, value: Any) -> None:
        mass = _number(value, "mass", 0.0, low_open=True)
        index = self._check()
        b = self._world.bodies
        # a pending force must still give a finite velocity change h F / m
        _finite_result(
            self._world.get_physics_time_step() * b.body_force[index] / mass,
            "mass",
            "velocity change under the pending force",
        )
        self._set_scalar("body_mass", mass)

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
        ``r_a f_b + r_b f_a`` (see :mod:`engine.physics.rolling_friction`)."""
        return self._scalar("body_rolling_friction")

    @rolling_friction_coefficient.setter
    def rolling_friction_coefficient(self, value: Any) -> None:
        self._set_scalar(
            "body_rolling_friction", _number(value, "rolling_friction_coefficient", 0.0)
        )

    @property
    def spinning_friction_coefficient(self) -> float:
        """Spinning (torsional) resistance: the contact torque about the normal is at most
        ``mu_spin N``, pair value ``s_a f_b + s_b f_a``."""
        return self._scalar("body_spinning_friction")

    @spinning_friction_coefficient.setter
    def spinning_friction_coefficient(self, value: Any) -> None:
        self._set_scalar(
            "body_spinning_friction", _number(value, "spinning_friction_coefficient", 0.0)
        )

    @property
    def friction_coefficient(self) -> float:
        return self._scalar("body_friction")

    @friction_coefficient.setter
    def friction_coefficient(self, value: Any) -> None:
        self._set_scalar("body_friction", _number(value, "friction_coefficient", 0.0))

    @property
    def restitution_coefficient(self) -> float:
        return self._scalar("body_restitution")

    @restitution_coefficient.setter
    def restitution_coefficient(self, value: Any) -> None:
        self._set_scalar("body_restitution", _number(value, "restitution_coefficient", 0.0, 1.0))

    @property
    def linear_damping(self) -> float:
        return self._scalar("body_linear_damping")

    @linear_damping.setter
    def linear_damping(self, value: Any) -> None:
        self._set_scalar("body_linear_damping", _number(value, "linear_damping", 0.0, 1.0))

    @property
    def angular_damping(self) -> float:
        return self._scalar("body_angular_damping")

    @angular_damping.setter
    def angular_damping(self, value: Any) -> None:
        self._set_scalar("body_angular_damping", _number(value, "angular_damping", 0.0, 1.0))

    # -- flags ----------------------------------------------------------------------------------
    @property
    def awake(self) -> bool:
        index = self._check()
        b = self._world.bodies
        return bool(b.body_awake[index]) if b.body_motion_type[index] == DYNAMIC else False

    @awake.setter
    def awake(self, value: Any) -> None:
        if not isinstance(value, bool | np.bool_):
            raise TypeError(f"awake must be a bool, got {value!r}")
        index = self._check()
        b = self._world.bodies
        if value:
            self._wake(index)
        elif b.body_motion_type[index] == DYNAMIC:
            b.body_awake[index] = False
            b.body_sleep_time[index] = TIME_TO_SLEEP  # rested long enough: stays asleep
            b.body_linear_velocity[index] = 0.0
            b.body_angular_velocity[index] = 0.0

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
        drawables = self._visual_node.drawables
        return int(drawables[0].semantic_id) if drawables else int(self._template.semantic_id)

    @semantic_id.setter
    def semantic_id(self, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
            raise ValueError(f"semantic_id must be a non-negative int, got {value!r}")
        self._check()
        for drawable in self._visual_node.drawables:
            drawable.semantic_id = int(value)


__all__ = ["KINEMATIC", "DeadObjectError", "ManagedRigidObject"]
