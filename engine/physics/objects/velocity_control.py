"""``RigidState`` and ``VelocityControl``: Habitat's velocity-driven motion of objects.

``VelocityControl.integrate_transform(dt, state)`` is explicit Euler from the old state
``(q0, t0)`` exactly as Habitat-sim's ``VelocityControl::integrateTransform``::

    t1 = t0 + v dt                   (global linear velocity)
    t1 = t0 + q0.rotate(v dt)        (lin_vel_is_local)
    w  = q0.rotate(omega) if ang_vel_is_local else omega
    q1 = normalize(dq * q0),  dq = rotation by |w| dt about w / |w|   (only if w != 0)

Each part applies only while its ``controlling_*`` flag is set. Targets and resulting
translations beyond ``MAX_COORDINATE`` (Habitat's 32-bit float range) are refused with a
ValueError naming the value, before anything changes. The world uses it once per
``step_physics`` call with the requested ``dt`` for KINEMATIC objects; for DYNAMIC objects it
overwrites the body velocity once per call (see :mod:`engine.physics.world`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine import mn
from engine.mn.vectors import stable_norm

from .object_checks import within_range


class RigidState:
    """A rigid pose ``RigidState(rotation, translation)`` (rotation first, as Habitat)."""

    def __init__(self, rotation: Any = None, translation: Any = None) -> None:
        self.rotation = mn.Quaternion() if rotation is None else rotation
        self.translation = mn.Vector3(0.0, 0.0, 0.0) if translation is None else translation

    @property
    def rotation(self) -> mn.Quaternion:
        return mn.Quaternion.from_xyzw(self._rotation)

    @rotation.setter
    def rotation(self, value: Any) -> None:
        self._rotation = mn.to_quaternion(value, "rotation").xyzw

    @property
    def translation(self) -> mn.Vector3:
        return mn.Vector3(self._translation)

    @translation.setter
    def translation(self, value: Any) -> None:
        self._translation = np.asarray(mn.to_vector3(value, "translation"))

    def __repr__(self) -> str:
        return f"RigidState(rotation={self.rotation!r}, translation={self.translation!r})"


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"{name} must be a bool, got {value!r}")
    return bool(value)


class VelocityControl:
    """Velocity targets of one object (Habitat's ``VelocityControl``), all off by default.

    Examples
    --------
    >>> vc = VelocityControl()
    >>> vc.controlling_lin_vel = True
    >>> vc.linear_velocity = [1.0, 0.0, 0.0]
    >>> state = vc.integrate_transform(0.5, RigidState())
    >>> [float(x) for x in state.translation]
    [0.5, 0.0, 0.0]
    """

    def __init__(self) -> None:
        self._linear = np.zeros(3)
        self._angular = np.zeros(3)
        self._flags = {
            "controlling_lin_vel": False,
            "controlling_ang_vel": False,
            "lin_vel_is_local": False,
            "ang_vel_is_local": False,
        }

    @property
    def linear_velocity(self) -> mn.Vector3:
        """Target linear velocity, m/s (world frame unless ``lin_vel_is_local``)."""
        return mn.Vector3(self._linear)

    @linear_velocity.setter
    def linear_velocity(self, value: Any) -> None:
        linear = np.asarray(mn.to_vector3(value, "linear_velocity"))
        self._linear = within_range(linear, "linear_velocity", "target velocity")

    @property
    def angular_velocity(self) -> mn.Vector3:
        """Target angular velocity, rad/s (world frame unless ``ang_vel_is_local``)."""
        return mn.Vector3(self._angular)

    @angular_velocity.setter
    def angular_velocity(self, value: Any) -> None:
        angular = np.asarray(mn.to_vector3(value, "angular_velocity"))
        self._angular = within_range(angular, "angular_velocity", "target angular velocity")

    def __getattr__(self, name: str) -> Any:
        flags = self.__dict__.get("_flags")
        if flags is not None and name in flags:
            return flags[name]
        raise AttributeError(f"VelocityControl has no attribute {name!r}")

    def __setattr__(self, name: str, value: Any) -> None:
        if name in (
            "controlling_lin_vel",
            "controlling_ang_vel",
            "lin_vel_is_local",
            "ang_vel_is_local",
        ):
            self._flags[name] = _flag(value, name)
        else:
            object.__setattr__(self, name, value)

    @property
    def is_active(self) -> bool:
        """True when it controls the linear or the angular velocity (one look-up per step
        and object instead of two attribute fall-backs)."""
        flags = self._flags
        return flags["controlling_lin_vel"] or flags["controlling_ang_vel"]

    def world_velocities(self, rotation_xyzw: np.ndarray) -> tuple[np.ndarray | None, ...]:
        """Controlled world-frame ``(linear, angular)`` velocities (None when not controlled)."""
        rotation = mn.quaternion_to_matrix(rotation_xyzw)
        linear = angular = None
        if self.controlling_lin_vel:
            linear = rotation @ self._linear if self.lin_vel_is_local else self._linear.copy()
        if self.controlling_ang_vel:
            angular = rotation @ self._angular if self.ang_vel_is_local else self._angular.copy()
        return linear, angular

    def integrate_transform(self, dt: float, rigid_state: RigidState) -> RigidState:
        """Pose after ``dt`` seconds at the controlled velocities (see module docstring)."""
        dt = float(dt)
        if not np.isfinite(dt):
            raise ValueError(f"dt must be finite, got {dt!r}")
        if not isinstance(rigid_state, RigidState):
            raise TypeError(f"rigid_state must be a RigidState, got {rigid_state!r}")
        q0, t0 = rigid_state._rotation, rigid_state._translation
        translation, rotation = t0.copy(), q0.copy()
        linear, angular = self.world_velocities(q0)
        if linear is not None:
            with np.errstate(over="ignore", invalid="ignore"):  # checked just below
                translation = t0 + linear * dt  # t1 = t0 + v dt (v already rotated if local)
        if angular is not None:
            speed = float(stable_norm(angular))
            if speed > 0.0:
                half = 0.5 * speed * dt
                dq = np.append(angular / speed * np.sin(half), np.cos(half))
                rotation = mn.quaternion_multiply(dq, q0)  # q1 = dq * q0
                rotation /= np.linalg.norm(rotation)
        within_range(
            translation, f"linear_velocity {self._linear.tolist()} over dt={dt!r}", "translation"
        )
        return RigidState(mn.Quaternion.from_xyzw(rotation), translation)

    def __repr__(self) -> str:
        return (
            f"VelocityControl(linear_velocity={self._linear.tolist()}, "
            f"angular_velocity={self._angular.tolist()}, {self._flags})"
        )
