"""``ManagedPhysicsObject``: what every Habitat physics object has (Habitat's
``AbstractManagedPhysicsObject``): identity, scene nodes, motion type, pose, sleep state and
the contact test. :class:`~engine.physics.objects.object_properties.ManagedRigidObject` adds the
rigid body's dynamics (velocities, forces, mass, material), as Habitat's
``ManagedRigidBase`` does.

An object is a thin handle on one body of the :class:`PhysicsWorld`: every property reads
or writes the world's ``body_*`` arrays (index ``object_id``), so it is never out of sync
with the simulation; getters return copies, setters validate first
(:mod:`object_checks`). STATIC objects ignore pose setters; pose writes wake the body and
what rests on it. After removal ``is_alive`` is False and any other access raises
:class:`DeadObjectError`.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from engine import mn
from engine.core.fixed_fields import public_names, unknown_attribute_error
from engine.mn.matrices import rotation_and_scaling
from engine.mn.vectors import stable_norm

from ..collision.collision_groups import assign_group
from ..core.bodies import DYNAMIC, KINEMATIC, STATIC
from ..core.motion_type import MotionType
from ..core.quaternions import matrix_to_quat, quat_multiply, quat_to_matrix
from ..core.settings import (
    MIN_AXIS_SCALE,
    MIN_QUATERNION_NORM,
    ORTHOGONALITY_TOLERANCE,
    TIME_TO_SLEEP,
)
from ..solver.sleeping import wake_body, wake_island
from .node_sync import canonical_sign
from .object_checks import (
    DeadObjectError,
    angle_argument,
    finite_result,
    quiet_overflow,
    within_range,
)
from .queries import contact_test
from .velocity_control import RigidState
from .world_view import WorldView

__all__ = ["ManagedPhysicsObject"]


class ManagedPhysicsObject:
    """A physics object of the world (Habitat's ``AbstractManagedPhysicsObject``).

    Frames: ``translation`` is the center of mass in the world frame (m); ``rotation`` the
    world_from_object quaternion.
    """

    def __init__(
        self, world: WorldView, index, handle, template, description, root, visual
    ) -> None:
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
        return f"<{type(self).__name__} {self._handle!r} id={self._index} {state}>"

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
        """The visual node, the scale node, the asset's root, then one node per node of the
        render asset (:mod:`engine.scene.visual_nodes`): set ``semantic_id`` on one to relabel a
        part."""
        self._check()
        return list(getattr(self, "_visual_nodes", [self._visual_node]))

    def visual_drawables(self) -> list:
        """Every drawable of the object (on its visual node and the nodes below it)."""
        return [d for node in self._visual_node.descendants() for d in node.drawables]

    def set_light_setup(self, light_setup_key: str) -> None:
        """Light every part of the object with the setup ``light_setup_key`` (Habitat's
        ``set_light_setup``; ``""`` is the default setup, ``"no_lights"`` draws it flat)."""
        if not isinstance(light_setup_key, str):
            raise TypeError(f"light_setup_key must be a str, got {light_setup_key!r}")
        self._check()
        for drawable in self.visual_drawables():
            drawable.light_setup_key = light_setup_key

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
        within_range(position, name, "position")
        norm = float(stable_norm(rotation))
        if not (np.isfinite(norm) and norm > MIN_QUATERNION_NORM):
            raise ValueError(f"{name} would make a degenerate rotation {rotation.tolist()}")
        finite_result(rotation / norm, name, "rotation")
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
        rotation_matrix, _, translation = rotation_and_scaling(
            value, MIN_AXIS_SCALE, ORTHOGONALITY_TOLERANCE
        )
        rotation = matrix_to_quat(rotation_matrix)
        current = self._world.bodies.body_rotation[self._check()]
        if float(rotation @ current) < 0.0:  # q and -q are one rotation: keep the sign
            rotation = -rotation
        self._set_pose(translation, rotation, "transformation")

    @property
    def rigid_state(self) -> RigidState:
        return RigidState(self.rotation, self.translation)

    @rigid_state.setter
    def rigid_state(self, value: Any) -> None:
        self._check()
        if not isinstance(value, RigidState):
            raise TypeError(f"rigid_state must be a RigidState, got {value!r}")
        self._set_pose(value._translation.copy(), value._rotation.copy(), "rigid_state")

    @quiet_overflow
    def translate(self, vector: Any) -> None:
        """Move by ``vector`` (world frame, m)."""
        offset = np.asarray(mn.to_vector3(vector, "vector"))
        index = self._check()
        self._set_pose(
            self._world.bodies.body_position[index] + offset,
            self._world.bodies.body_rotation[index].copy(),
            "vector",
        )

    @quiet_overflow
    def translate_local(self, vector: Any) -> None:
        """Move by ``vector`` as Habitat does: its object moves its TRS scene node with
        ``translateLocal``, which adds the vector in the parent frame without rotating it,
        the same as :meth:`translate` (``engine.scene.graph`` explains the Magnum rule)."""
        self.translate(vector)

    def rotate(self, angle: Any, axis: Any, local: bool = False) -> None:
        """Rotate by ``angle`` (Rad/Deg) about ``axis``: world axes (``q' = r q``) or local
        (``q' = q r``)."""
        turn = mn.Quaternion.rotation(mn.Rad(angle_argument(angle)), axis).xyzw
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

    # -- sleep and contact -----------------------------------------------------------------
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

    def contact_test(self) -> bool:
        """True if the object currently overlaps another collidable object or the stage."""
        return contact_test(self._world.bodies, self._world.collision_objects, self._check())
