"""Agents: a scene node that carries sensors and moves by discrete actions.

Mirrors ``habitat_sim.agent``. An :class:`Agent` owns a :class:`SceneNode` (its body frame:
Y up, looking down -Z) and the camera sensors posed on it. ``AgentState`` is its pose
(``position``, ``rotation``) plus the sensors' states.

Actions (Habitat's default action space): ``move_forward`` by 0.25 m along the agent's -Z,
``turn_left`` / ``turn_right`` by 10 degrees about +Y. A move goes through the simulator's
``step_filter`` (the navmesh, when loaded). ``act`` returns ``collided``, Habitat's test::

    collided = |after - before|^2 + 1e-5 < |end - before|^2

i.e. the filter shortened the requested step.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import quaternion

from engine import mn
from engine.scene_node import SceneNode
from engine.sensors import CameraSensor, CameraSensorSpec

__all__ = ["ActionSpec", "ActuationSpec", "Agent", "AgentConfiguration", "AgentState"]

#: Habitat's collision test tolerance on squared distances (m^2).
COLLISION_EPS = 1e-5


@dataclass
class ActuationSpec:
    """How much an action moves: meters for moves, degrees for turns."""

    amount: float = 0.25


@dataclass
class ActionSpec:
    """A named action and its actuation (Habitat's ``ActionSpec``)."""

    name: str
    actuation: ActuationSpec = field(default_factory=ActuationSpec)


def _default_action_space() -> dict[str, ActionSpec]:
    return {
        "move_forward": ActionSpec("move_forward", ActuationSpec(0.25)),
        "turn_left": ActionSpec("turn_left", ActuationSpec(10.0)),
        "turn_right": ActionSpec("turn_right", ActuationSpec(10.0)),
    }


@dataclass
class AgentConfiguration:
    """An agent's body and sensors (Habitat's defaults: 1.5 m tall, radius 0.1 m)."""

    height: float = 1.5
    radius: float = 0.1
    sensor_specifications: list[CameraSensorSpec] = field(default_factory=list)
    action_space: dict[str, ActionSpec] = field(default_factory=_default_action_space)
    body_type: str = "cylinder"


class AgentState:
    """An agent's pose: ``position`` (3,) in meters and ``rotation`` (a unit quaternion).

    As in Habitat, ``rotation`` reads back as a numpy-quaternion ``np.quaternion(w, x, y, z)``
    (the identity by default), so Habitat's ``AgentState(rotation=np.quaternion(...))`` and
    ``quat_to_angle_axis(state.rotation)`` work unchanged. It accepts an ``np.quaternion``, an
    :class:`mn.Quaternion` or a list / ndarray read as coefficients ``[x, y, z, w]`` (Habitat's
    ``quat_from_coeffs`` order); the value is normalized. A non-finite position or a zero or
    non-finite rotation raises ``ValueError``.
    """

    def __init__(self, position: Any = (0.0, 0.0, 0.0), rotation: Any = None) -> None:
        self.position = position
        self.rotation = mn.Quaternion() if rotation is None else rotation
        self.sensor_states: dict[str, Any] = {}

    @property
    def position(self) -> np.ndarray:
        return self._position.copy()

    @position.setter
    def position(self, value: Any) -> None:
        self._position = np.asarray(mn.to_vector3(value, "AgentState.position"))

    @property
    def rotation(self) -> quaternion.quaternion:
        x, y, z, w = self._rotation
        return quaternion.quaternion(w, x, y, z)

    @rotation.setter
    def rotation(self, value: Any) -> None:
        self._rotation = mn.to_quaternion(value, "AgentState.rotation").xyzw

    def __repr__(self) -> str:
        return f"AgentState(position={self._position.tolist()}, rotation={self.rotation!r})"


StepFilter = Callable[[np.ndarray, np.ndarray], Any]


class Agent:
    """An agent: its scene node, its sensors and its action space."""

    def __init__(self, scene_node: SceneNode, agent_config: AgentConfiguration,
                 step_filter: StepFilter | None = None) -> None:
        uuids = [spec.uuid for spec in agent_config.sensor_specifications]
        if len(set(uuids)) != len(uuids):
            raise ValueError(f"sensor uuids must be unique, got {uuids}")
        self.scene_node = scene_node
        self.agent_config = agent_config
        self._step_filter = step_filter
        self._sensors = [CameraSensor(s, scene_node) for s in agent_config.sensor_specifications]
        self.initial_state = self.get_state()

    @property
    def sensors(self) -> list[CameraSensor]:
        return list(self._sensors)

    def get_state(self) -> AgentState:
        """The agent's world pose (a fresh ``AgentState``)."""
        world = self.scene_node.world_matrix()
        state = AgentState(world[:3, 3], mn.Quaternion.from_matrix(world[:3, :3]))
        for sensor in self._sensors:
            sensor_world = sensor.world_from_camera()
            state.sensor_states[sensor.uuid] = (
                sensor_world[:3, 3].copy(), mn.Quaternion.from_matrix(sensor_world[:3, :3]))
        return state

    def set_state(self, state: AgentState, reset_sensors: bool = True) -> None:
        """Move the agent node to ``state`` (its position and rotation in the world)."""
        if not isinstance(state, AgentState):
            raise TypeError(f"set_state needs an AgentState, got {type(state).__name__}")
        parent = self.scene_node.parent
        world = np.eye(4)
        world[:3, :3] = mn.quaternion_to_matrix(mn.to_quaternion(state.rotation).xyzw)
        world[:3, 3] = state.position
        local = world if parent is None else np.linalg.inv(parent.world_matrix()) @ world
        self.scene_node.transformation = local
        if reset_sensors:
            for sensor in self._sensors:
                sensor.reset_pose()

    def act(self, action_name: str) -> bool:
        """Perform a named action; returns True when a move was blocked (collided)."""
        if action_name not in self.agent_config.action_space:
            raise KeyError(f"unknown action {action_name!r}; known: "
                           f"{sorted(self.agent_config.action_space)}")
        spec = self.agent_config.action_space[action_name]
        amount = float(spec.actuation.amount)
        if spec.name in ("turn_left", "turn_right"):
            sign = 1.0 if spec.name == "turn_left" else -1.0
            self.scene_node.rotate_y_local(mn.Rad(sign * math.radians(amount)))
            return False
        if spec.name in ("move_forward", "move_backward"):
            sign = 1.0 if spec.name == "move_forward" else -1.0
            return self._move(sign * amount)
        raise ValueError(f"action {spec.name!r} has no actuation in rigidsim")

    def _move(self, distance: float) -> bool:
        """Step along the body's -Z through the step filter; report a collision."""
        start = self.scene_node.absolute_translation
        forward = self.scene_node.world_matrix()[:3, :3] @ np.array([0.0, 0.0, -1.0])
        end = np.asarray(start) + distance * forward
        filtered = np.asarray(self._step_filter(start, end) if self._step_filter else end,
                              dtype=np.float64)
        self.scene_node.translate(filtered - np.asarray(start))
        moved_sq = float(np.sum((filtered - np.asarray(start)) ** 2))
        wanted_sq = float(np.sum((end - np.asarray(start)) ** 2))
        return moved_sq + COLLISION_EPS < wanted_sq
