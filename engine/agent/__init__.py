"""Agents and their controls: Habitat's ``habitat_sim.agent`` package.

``AgentConfiguration``, ``AgentState``, ``Agent``, ``ActionSpec``, ``SixDOFPose`` and, from
:mod:`engine.agent.controls`, ``ActuationSpec``, ``SceneNodeControl``, ``ObjectControls``,
``PyRobotNoisyActuationSpec`` are importable from here. What is here, in reading order:

1. :mod:`engine.agent.controls`: what an action does to a scene node (its own map);
2. :mod:`~engine.agent.agent`: ``Agent`` (a body node with sensors below it), its
   configuration and state, ``agent.act(name)``.

May import: ``engine.sensors`` (an agent's sensors are made by ``SensorFactory``),
``engine.scene``, ``engine.core``, ``engine.mn``. Navigation and the simulator build on it.
"""

from engine.agent.agent import ActionSpec, Agent, AgentConfiguration, AgentState, SixDOFPose
from engine.agent.controls import (
    ActuationSpec,
    ObjectControls,
    PyRobotNoisyActuationSpec,
    SceneNodeControl,
    UnknownActionError,
)

__all__ = [
    "ActionSpec",
    "ActuationSpec",
    "Agent",
    "AgentConfiguration",
    "AgentState",
    "ObjectControls",
    "PyRobotNoisyActuationSpec",
    "SceneNodeControl",
    "SixDOFPose",
    "UnknownActionError",
]
