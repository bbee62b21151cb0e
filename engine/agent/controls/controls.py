"""Habitat's ``habitat_sim.agent.controls.controls``: ``ActuationSpec`` and ``SceneNodeControl``
(defined in :mod:`engine.control_base`)."""

from engine.control_base import ActuationSpec, SceneNodeControl

__all__ = ["ActuationSpec", "SceneNodeControl"]
