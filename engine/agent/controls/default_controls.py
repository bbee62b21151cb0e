"""Habitat's default controls and the names :mod:`engine.registry` registers them under.

Body actions (the agent node moves, its sensors follow, the step filter applies):
``move_forward`` / ``move_backward`` along the node's -Z / +Z, ``move_left`` / ``move_right``
along -X / +X (meters), ``turn_left`` / ``turn_right`` about the node's +Y (degrees).

Sensor actions (every sensor node moves on its own, no step filter): ``move_up`` /
``move_down`` (local Y), ``look_left`` / ``look_right`` (local Y), ``look_up`` / ``look_down``
(local X), ``rotate_sensor_clockwise`` / ``rotate_sensor_anti_clockwise`` (local Z).

Moves are along the node's own axes, given in the parent frame as Habitat gives them:
``translate_local(amount * R[:, axis])`` (a TRS node's ``translate_local`` does not rotate).
Turns post-multiply the rotation (``q <- q * r(theta, axis)``) and renormalize. With a
``constraint`` c (degrees) a look control clamps the resulting look angle to ``[-c, c]``,
where the look angle of the forward vector ``f = q (0, 0, -1)`` is ``atan2(f_y, -f_z)``
about X (pitch) and ``-atan2(f_x, -f_z)`` about Y (yaw).
"""

from __future__ import annotations

import math

import numpy as np

from engine import mn
from engine.agent.controls.controls import ActuationSpec, SceneNodeControl
from engine.scene.graph import SceneNode

__all__ = ["DEFAULT_CONTROLS"]

#: ``(control class, name or None for its snake-case class name, body_action)``, in the
#: order :mod:`engine.registry` registers them (it imports this module; this module never
#: imports the registry, so there is no import cycle)
DEFAULT_CONTROLS: list[tuple[type[SceneNodeControl], str | None, bool]] = []


def default_control(body_action: bool):
    """Class decorator: list a control in :data:`DEFAULT_CONTROLS` under its class name."""

    def listed(control_class: type[SceneNodeControl]) -> type[SceneNodeControl]:
        DEFAULT_CONTROLS.append((control_class, None, body_action))
        return control_class

    return listed


_AXES = np.eye(3)  # local X, Y, Z
_FRONT = np.array([0.0, 0.0, -1.0])


def move_along(scene_node: SceneNode, distance: float, axis: int) -> None:
    """Translate ``distance`` meters along the node's own ``axis`` (0 X, 1 Y, 2 Z), given in
    the parent frame as Habitat does (``translate_local`` does not rotate its vector)."""
    own_axis = mn.quaternion_to_matrix(scene_node.rotation.xyzw)[:, axis]
    scene_node.translate_local(own_axis * float(distance))


def look_angle_degrees(rotation: mn.Quaternion, axis: int) -> float:
    """Pitch (axis 0) or yaw (axis 1) of the node's forward vector, degrees."""
    look = np.asarray(rotation.transform_vector(_FRONT))
    if axis == 0:
        return math.degrees(math.atan2(look[1], -look[2]))
    return -math.degrees(math.atan2(look[0], -look[2]))


def rotate_local(
    scene_node: SceneNode, degrees: float, axis: int, constraint: float | None = None
) -> None:
    """Rotate ``degrees`` about the node's own ``axis``, clamping the look angle if asked."""
    degrees = float(degrees)
    if constraint is not None:
        rotation = scene_node.rotation
        tilted = (
            float(rotation.angle()) != 0.0
            and 1.0 - abs(float(np.asarray(rotation.axis())[axis])) > 1e-3
        )
        if tilted:
            raise RuntimeError("Constrained look only works for a singular look action type")
        current = look_angle_degrees(rotation, axis)
        target = min(max(current + degrees, -float(constraint)), float(constraint))
        degrees = target - current
    scene_node.rotate_local(mn.Deg(degrees), _AXES[axis])
    scene_node.rotation = scene_node.rotation.normalized()


@default_control(body_action=True)
class MoveBackward(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, actuation_spec.amount, 2)


@default_control(body_action=True)
class MoveForward(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, -actuation_spec.amount, 2)


@default_control(body_action=True)
class MoveRight(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, actuation_spec.amount, 0)


@default_control(body_action=True)
class MoveLeft(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, -actuation_spec.amount, 0)


@default_control(body_action=False)
class MoveUp(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, actuation_spec.amount, 1)


@default_control(body_action=False)
class MoveDown(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        move_along(scene_node, -actuation_spec.amount, 1)


@default_control(body_action=False)
class LookLeft(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, actuation_spec.amount, 1, actuation_spec.constraint)


@default_control(body_action=False)
class LookRight(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, -actuation_spec.amount, 1, actuation_spec.constraint)


# turning the body is looking left/right applied to the agent node
DEFAULT_CONTROLS += [(LookLeft, "turn_left", True), (LookRight, "turn_right", True)]


@default_control(body_action=False)
class LookUp(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, actuation_spec.amount, 0, actuation_spec.constraint)


@default_control(body_action=False)
class LookDown(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, -actuation_spec.amount, 0, actuation_spec.constraint)


@default_control(body_action=False)
class RotateSensorClockwise(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, actuation_spec.amount, 2, actuation_spec.constraint)


@default_control(body_action=False)
class RotateSensorAntiClockwise(SceneNodeControl):
    def __call__(self, scene_node: SceneNode, actuation_spec: ActuationSpec) -> None:
        rotate_local(scene_node, -actuation_spec.amount, 2, actuation_spec.constraint)
