"""Agent controls, structured as Habitat's ``habitat_sim.agent.controls``.

``ActuationSpec`` and ``SceneNodeControl`` (:mod:`.controls`), the default controls
(:mod:`.default_controls`, registered by :mod:`engine.registry`) and ``ObjectControls``
(:mod:`.object_controls`).
"""

from engine.agent.controls.controls import ActuationSpec, SceneNodeControl
from engine.agent.controls.object_controls import ObjectControls, UnknownActionError

__all__ = ["ActuationSpec", "ObjectControls", "SceneNodeControl", "UnknownActionError"]
