"""Habitat's ``habitat_sim.registry``: the named controls (defined in
:mod:`engine.agent.controls.registry`); ``engine.registry.register_move_fn`` and
``get_move_fn`` resolve through the module's ``__getattr__`` as in Habitat."""

from engine.agent.controls.registry import __getattr__, registry  # noqa: F401 - __getattr__ serves register_move_fn, get_move_fn

__all__ = ["registry"]
