"""Habitat's ``habitat_sim.agent.controls.default_controls`` (defined in
:mod:`engine.default_controls`; :mod:`engine.registry` registers them)."""

from engine.default_controls import DEFAULT_CONTROLS

__all__ = ["DEFAULT_CONTROLS"]
