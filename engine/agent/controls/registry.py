"""Habitat's ``habitat_sim.registry``: named controls ("move functions") the agents look up.

An agent's ``ActionSpec("move_forward", ActuationSpec(0.25))`` names a control registered
here. User code adds its own control exactly as in Habitat::

    @habitat_sim.registry.register_move_fn(body_action=True)
    class StrafeUp(habitat_sim.agent.SceneNodeControl):
        def __call__(self, scene_node, actuation_spec):
            scene_node.translate_local([0.0, actuation_spec.amount, 0.0])

The name defaults to the class name in snake case (``StrafeUp`` -> ``strafe_up``);
``body_action=True`` moves the agent's body (sensors follow, the step filter applies),
``False`` moves each sensor on its own. ``get_move_fn(name)`` returns the registered control
instance, or None.
"""

from __future__ import annotations

import re
from typing import Any

from engine.agent.controls.controls import SceneNodeControl
from engine.agent.controls.default_controls import DEFAULT_CONTROLS

__all__ = ["registry"]


def camel_to_snake(name: str) -> str:
    """``MoveForward`` -> ``move_forward``, ``RotateSensorAntiClockwise`` -> ..._anti_clockwise."""
    words = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", name)  # split before Capitalized words
    return re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", words).lower()  # and before lone capitals


class _Registry:
    """The global store of named controls (Habitat's ``registry``)."""

    def __init__(self) -> None:
        self._move_fns: dict[str, Any] = {}
        for control, name, body_action in DEFAULT_CONTROLS:  # Habitat's default controls
            self.register_move_fn(control, name=name, body_action=body_action)

    def register_move_fn(
        self,
        controller: type | None = None,
        *,
        name: str | None = None,
        body_action: bool | None = None,
    ):
        """Register a ``SceneNodeControl`` subclass (usable as a decorator, with or without
        arguments). ``body_action`` must be given, as in Habitat (an AssertionError otherwise)."""
        assert body_action is not None, "body_action must be explicitly set to True or False"

        def register(control_class: type) -> type:
            is_control = isinstance(control_class, type) and issubclass(
                control_class, SceneNodeControl
            )
            assert is_control, "controls must inherit from habitat_sim.agent.SceneNodeControl"
            key = camel_to_snake(control_class.__name__) if name is None else name
            self._move_fns[key] = control_class(body_action)
            return control_class

        return register if controller is None else register(controller)

    def get_move_fn(self, name: str) -> Any:
        """The control registered under ``name``, or None."""
        return self._move_fns.get(name)

    def move_fn_names(self) -> list[str]:
        """Every registered control name, sorted (rigidsim addition, for error messages)."""
        return sorted(self._move_fns)


registry = _Registry()


def __getattr__(name: str) -> Any:
    # ``habitat_sim.registry.register_move_fn(...)`` (module-level use, as Habitat's docs do)
    if name in ("register_move_fn", "get_move_fn"):
        return getattr(registry, name)
    raise AttributeError(f"module 'engine.registry' has no attribute {name!r}")
