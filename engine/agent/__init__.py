"""Habitat's ``habitat_sim.agent`` package: agents (:mod:`.agent`) and their controls.

``engine.agent.AgentConfiguration``, ``AgentState``, ``Agent``, ``ActionSpec``,
``SixDOFPose`` and, from :mod:`engine.agent.controls`, ``ActuationSpec``,
``SceneNodeControl``, ``ObjectControls``, ``PyRobotNoisyActuationSpec``.
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
