"""Agent controls, structured as Habitat's ``habitat_sim.agent.controls``.

What is here, in reading order:

1. :mod:`.controls`: ``ActuationSpec`` and ``SceneNodeControl``, the base of every control;
2. :mod:`.default_controls`: Habitat's moves and turns of the body and of its sensors;
3. :mod:`.registry`: the named controls (Habitat's ``habitat_sim.registry``, whose path is
   the face ``engine.registry``), holding the default controls at start;
4. :mod:`.object_controls`: ``ObjectControls``, a registered control run on a node, then the
   move filter;
5. :mod:`.pyrobot_noisy_controls`: the noisy PyRobot controls.

May import: ``engine.scene`` (the nodes they move), ``engine.core``, ``engine.mn``.
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
