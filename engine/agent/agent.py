"""Agents: a scene node that carries sensors and moves by discrete actions.

Mirrors ``habitat_sim.agent.agent``. An :class:`Agent` controls a :class:`SceneNode` (its
body frame: Y up, looking down -Z) and the camera sensors posed on it. ``AgentState`` is its
pose (``position``, ``rotation``) plus each sensor's world pose (``sensor_states``, keyed by
uuid, :class:`SixDOFPose`).

``agent.act(name)`` looks ``name`` up in ``agent_config.action_space``; the ``ActionSpec``
names a control of :mod:`engine.registry`. Body controls (``move_forward`` 0.25 m along -Z,
``turn_left`` / ``turn_right`` 10 degrees about +Y, ...) move the agent node and go through
``agent.controls.move_filter_fn`` (the simulator's ``step_filter``: the navmesh); sensor
controls (``look_up``, ``move_up``, ...) move every sensor node. ``act`` returns ``collided``,
Habitat's test::

    collided = |after - before|^2 + 1e-5 < |end - before|^2

i.e. the filter shortened the requested step.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import quaternion

from engine import mn
from engine.agent.controls import ActuationSpec, ObjectControls, UnknownActionError
from engine.core.fixed_fields import FixedFields
from engine.mn.vectors import real_components
from engine.scene.graph import SceneNode
from engine.sensors.cameras import Sensor, SensorSpec
from engine.sensors.factory import SensorFactory

__all__ = ["ActionSpec", "Agent", "AgentConfiguration", "AgentState", "SixDOFPose"]


@dataclass
class ActionSpec(FixedFields):
    """A named action: ``name`` of a registered control and its ``actuation``."""

    name: str
    actuation: ActuationSpec | None = None


def _default_action_space() -> dict[str, ActionSpec]:
    return {
        "move_forward": ActionSpec("move_forward", ActuationSpec(0.25)),
        "turn_left": ActionSpec("turn_left", ActuationSpec(10.0)),
        "turn_right": ActionSpec("turn_right", ActuationSpec(10.0)),
    }


@dataclass
class AgentConfiguration(FixedFields):
    """An agent's body and sensors (Habitat's defaults: 1.5 m tall, radius 0.1 m)."""

    height: float = 1.5
    radius: float = 0.1
    sensor_specifications: list[SensorSpec] = field(default_factory=list)
    action_space: dict[Any, ActionSpec] = field(default_factory=_default_action_space)
    body_type: str = "cylinder"


def _as_position(value: Any, name: str) -> np.ndarray:
    """``(3,) float64`` copy of a 3-vector; NaN is stored (checked when the state is used)."""
    if isinstance(value, str | bytes) or not real_components(value):
        raise TypeError(
            f"{name} must be a 3-vector of real numbers (no strings, bools or complex "
            f"numbers), got {value!r}"
        )
    try:
        position = np.array(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError) as err:
        raise TypeError(f"{name} must be a 3-vector of numbers, got {value!r}") from err
    if position.shape != (3,):
        raise ValueError(f"{name} must have 3 components, got {value!r}")
    return position


def _check_finite(position: np.ndarray, name: str) -> None:
    if not np.all(np.isfinite(position)):
        raise ValueError(f"{name} must be finite, got {position.tolist()}")


class _Pose(FixedFields):
    """The ``position`` and ``rotation`` properties shared by :class:`AgentState` and
    :class:`SixDOFPose` (conversions in AgentState's docstring)."""

    _position: np.ndarray  # (3,) float64, meters
    _rotation: np.ndarray  # (4,) float64 unit quaternion [x, y, z, w], used by set_state
    _rotation_value: Any  # the value assigned, returned as is (Habitat's attrs field)

    @property
    def position(self) -> np.ndarray:
        return self._position.copy()

    @position.setter
    def position(self, value: Any) -> None:
        self._position = _as_position(value, "AgentState.position")

    @property
    def rotation(self) -> Any:
        """The rotation as assigned (``np.quaternion``, ``mn.Quaternion`` or coefficients)."""
        return self._rotation_value

    @rotation.setter
    def rotation(self, value: Any) -> None:
        self._rotation = mn.to_quaternion(value, "AgentState.rotation").xyzw
        self._rotation_value = value


def numpy_quaternion(rotation: mn.Quaternion) -> quaternion.quaternion:
    """``np.quaternion(w, x, y, z)`` of a Magnum quaternion (the type Habitat's states hold)."""
    x, y, z, w = rotation.xyzw
    return quaternion.quaternion(w, x, y, z)


class AgentState(_Pose):
    """An agent's pose: ``position`` (3,) in meters and ``rotation`` (a unit quaternion).

    As in Habitat, ``rotation`` is a numpy-quaternion ``np.quaternion(w, x, y, z)`` (the
    identity by default, and in every state ``get_state`` returns), so
    ``quat_to_angle_axis(state.rotation)`` works unchanged. It accepts an ``np.quaternion``, an
    :class:`mn.Quaternion` or a list / ndarray read as coefficients ``[x, y, z, w]`` (Habitat's
    ``quat_from_coeffs`` order), and reads back **what was assigned** (Habitat's attrs field
    keeps it: after ``state.rotation = mn_quat``, ``state.rotation * q`` is Magnum's product);
    ``set_state`` uses its normalized value. ``sensor_states`` maps sensor uuids to
    :class:`SixDOFPose`.

    As in Habitat (attrs validators), the constructor refuses a non-finite position
    (``ValueError``); assigning one later is stored and refused by ``Agent.set_state``.
    """

    _extra_fields = ("sensor_states",)

    def __init__(
        self,
        position: Any = (0.0, 0.0, 0.0),
        rotation: Any = None,
        sensor_states: dict[str, SixDOFPose] | None = None,
    ) -> None:
        self.position = position
        _check_finite(self._position, "AgentState.position")
        self.rotation = quaternion.quaternion(1, 0, 0, 0) if rotation is None else rotation
        self.sensor_states = {} if sensor_states is None else dict(sensor_states)

    def __repr__(self) -> str:
        return f"AgentState(position={self._position.tolist()}, rotation={self.rotation!r})"


class SixDOFPose(_Pose):
    """A sensor's world pose in ``AgentState.sensor_states``: ``position``, ``rotation``.

    Same types and conversions as :class:`AgentState` (the properties are shared).
    """

    def __init__(self, position: Any = (0.0, 0.0, 0.0), rotation: Any = None) -> None:
        self.position = position
        _check_finite(self._position, "SixDOFPose.position")
        self.rotation = quaternion.quaternion(1, 0, 0, 0) if rotation is None else rotation

    def __repr__(self) -> str:
        return f"SixDOFPose(position={self._position.tolist()}, rotation={self.rotation!r})"


class _Body:
    """Habitat's ``agent.body``: the feature that attaches the agent to its node."""

    def __init__(self, scene_node: SceneNode) -> None:
        self.object = scene_node


class Agent:
    """An agent: its scene node, its sensors (dict by uuid), its controls and action space.

    ``Agent(scene_node, agent_config=None)`` as in Habitat; the simulator sets
    ``agent.controls.move_filter_fn`` to its ``step_filter``. ``initial_state`` is None until
    ``Simulator.initialize_agent`` (or ``set_state(..., is_initial=True)``) sets it.
    """

    def __init__(
        self,
        scene_node: SceneNode,
        agent_config: AgentConfiguration | None = None,
        _sensors: dict[str, Sensor] | None = None,
        controls: ObjectControls | None = None,
    ) -> None:
        if not isinstance(scene_node, SceneNode):
            raise TypeError(f"Agent needs a SceneNode, got {type(scene_node).__name__}")
        self.body = _Body(scene_node)
        self.agent_config = agent_config if agent_config is not None else AgentConfiguration()
        self.controls = controls if controls is not None else ObjectControls()
        self.reconfigure(self.agent_config)
        self.initial_state: AgentState | None = None

    @property
    def scene_node(self) -> SceneNode:
        return self.body.object

    @property
    def sensors(self) -> dict[str, Sensor]:
        """Live view of the sensors on the agent's node and below it, by uuid (Habitat's
        ``scene_node.subtree_sensors``: a sensor created on an object carried by the agent
        is one of them)."""
        return self.scene_node.subtree_sensors

    @property
    def _sensors(self) -> dict[str, Sensor]:
        # Habitat's deprecated name
        return self.sensors

    def get_sensors(self) -> dict[str, Sensor]:
        return self.sensors

    def reconfigure(
        self, agent_config: AgentConfiguration, reconfigure_sensors: bool = True
    ) -> None:
        """Adopt ``agent_config``; re-create the sensors from its specifications."""
        uuids = [spec.uuid for spec in agent_config.sensor_specifications]
        if len(set(uuids)) != len(uuids):
            raise ValueError(f"sensor uuids must be unique, got {uuids}")
        for spec in agent_config.sensor_specifications:
            spec.validate()  # all or nothing: no sensor is made from a bad list
        self.agent_config = agent_config
        if reconfigure_sensors:
            for uuid in list(self.scene_node.subtree_sensors):
                SensorFactory.delete_subtree_sensor(self.scene_node, uuid)
            SensorFactory.create_sensors(self.scene_node, agent_config.sensor_specifications)

    def _add_sensor(self, spec: SensorSpec, modify_agent_config: bool = True) -> Sensor:
        """Attach a new sensor to the agent's node and return it."""
        if spec.uuid in self.sensors:
            raise ValueError(f"a sensor {spec.uuid!r} already exists on this agent")
        sensor = SensorFactory.create_sensors(self.scene_node, [spec])[spec.uuid]
        if modify_agent_config and not any(
            s is spec for s in self.agent_config.sensor_specifications
        ):
            self.agent_config.sensor_specifications.append(spec)
        return sensor

    @property
    def state(self) -> AgentState:
        """``get_state()``; assigning calls ``set_state(state)`` with the defaults."""
        return self.get_state()

    @state.setter
    def state(self, new_state: AgentState) -> None:
        self.set_state(new_state, reset_sensors=True, infer_sensor_states=True, is_initial=False)

    def get_state(self) -> AgentState:
        """The agent's world pose and its sensors' world poses (a fresh ``AgentState``)."""
        world = self.scene_node.world_matrix()
        state = AgentState(world[:3, 3], numpy_quaternion(mn.Quaternion.from_matrix(world[:3, :3])))
        for uuid, sensor in self._sensors.items():
            sensor_world = sensor.world_from_camera()
            sensor_rotation = mn.Quaternion.from_matrix(sensor_world[:3, :3])
            state.sensor_states[uuid] = SixDOFPose(
                sensor_world[:3, 3], numpy_quaternion(sensor_rotation)
            )
        return state

    def set_state(
        self,
        state: AgentState,
        reset_sensors: bool = True,
        infer_sensor_states: bool = True,
        is_initial: bool = False,
    ) -> None:
        """Put the agent (and its sensors) in ``state`` (Habitat's arguments).

        ``reset_sensors``: sensors go back to their spec pose relative to the body first.
        ``infer_sensor_states=False``: each sensor in ``state.sensor_states`` is placed at its
        given world pose instead of following the body. ``is_initial``: keep ``state`` as
        the pose ``Simulator.reset`` returns to. A non-finite position raises ValueError and
        changes nothing.
        """
        if not isinstance(state, AgentState):
            raise TypeError(f"set_state needs an AgentState, got {type(state).__name__}")
        _check_finite(state.position, "AgentState.position")
        if not infer_sensor_states:
            unknown = sorted(set(state.sensor_states) - set(self._sensors))
            if unknown:
                raise KeyError(
                    f"sensor_states names unknown sensors {unknown}; "
                    f"the agent has {sorted(self._sensors)}"
                )
            for uuid, pose in state.sensor_states.items():
                _check_finite(pose.position, f"sensor_states[{uuid!r}].position")
        world = _pose_matrix(state.position, state.rotation)
        parent = self.scene_node.parent
        local = world if parent is None else np.linalg.inv(parent.world_matrix()) @ world
        self.scene_node.transformation = local
        if reset_sensors:
            for sensor in self._sensors.values():
                sensor.set_transformation_from_spec()
        if not infer_sensor_states:
            body_from_world = np.linalg.inv(world)
            for uuid, pose in state.sensor_states.items():
                sensor_world = _pose_matrix(pose.position, pose.rotation)
                self._sensors[uuid].node.transformation = body_from_world @ sensor_world
        if is_initial:
            self.initial_state = state

    def act(self, action_id: Any) -> bool:
        """Perform the action ``action_id`` of the action space; True when a move collided.

        An id missing from the action space, or naming no registered control, raises
        :class:`UnknownActionError` (an ``AssertionError`` as in Habitat, and a ``KeyError``).
        """
        if action_id not in self.agent_config.action_space:
            raise UnknownActionError(
                f"No action {action_id!r} in action space "
                f"{sorted(map(str, self.agent_config.action_space))}"
            )
        action = self.agent_config.action_space[action_id]
        if self.controls.is_body_action(action.name):
            return self.controls.action(
                self.scene_node, action.name, action.actuation, apply_filter=True
            )
        for sensor in self._sensors.values():
            self.controls.action(sensor.node, action.name, action.actuation, apply_filter=False)
        return False

    def close(self) -> None:
        """Release the agent's sensors (their nodes leave the scene graph)."""
        for uuid in list(self.scene_node.subtree_sensors):
            SensorFactory.delete_subtree_sensor(self.scene_node, uuid)


def _pose_matrix(position: Any, rotation: Any) -> np.ndarray:
    """``(4, 4)`` world matrix of a position and a quaternion-like rotation."""
    matrix = np.eye(4)
    matrix[:3, :3] = mn.quaternion_to_matrix(mn.to_quaternion(rotation, "rotation").xyzw)
    matrix[:3, 3] = np.asarray(position, dtype=np.float64)
    return matrix
