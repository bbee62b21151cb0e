"""Agent controls, structured as Habitat's ``habitat_sim.agent.controls``.

``ActuationSpec`` and ``SceneNodeControl`` (:mod:`.controls`), the default controls
(:mod:`.default_controls`, registered by :mod:`engine.agent.controls.registry`),
the noisy PyRobot controls (:mod:`.pyrobot_noisy_controls`) and ``ObjectControls``
(:mod:`.object_controls`).
"""

from engine.agent.controls.controls import ActuationSpec, SceneNodeControl
from engine.agent.controls.object_controls import ObjectControls, UnknownActionError
from engine.agent.controls.pyrobot_noisy_controls import PyRobotNoisyActuationSpec

__all__ = [
    "ActuationSpec",
    "ObjectControls",
    "PyRobotNoisyActuationSpec",
    "SceneNodeControl",
    "UnknownActionError",
]
