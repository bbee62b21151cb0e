"""``ObjectControls``: run a registered control on a node, then the move filter (collisions).

``action(node, name, spec, apply_filter)`` remembers the node's world position ``p0``, runs
the control (the node reaches ``p1``), and when ``apply_filter`` asks
``move_filter_fn(p0, p1)`` (the simulator's ``step_filter``: the navmesh) where the step may
end, ``p2``, and moves the node there. It reports a collision when the filter shortened the
step (Habitat's test, squared lengths in m^2)::

    collided = |p2 - p0|^2 + 1e-5 < |p1 - p0|^2
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from engine.agent.controls.controls import ActuationSpec
from engine.agent.controls.registry import registry
from engine.scene.graph import SceneNode

__all__ = ["ObjectControls", "UnknownActionError"]

#: Habitat's collision tolerance on squared distances (m^2).
EPS = 1e-5


class UnknownActionError(KeyError, AssertionError):
    """An action or control name that does not exist. Habitat asserts here, so this is an
    ``AssertionError`` as Habitat's tests expect, and a ``KeyError`` as rigidsim's lookups
    raise."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def _noop_filter(start: Any, end: Any) -> Any:
    return end


class ObjectControls:
    """Applies controls to scene nodes; ``move_filter_fn(start, end) -> end`` filters moves."""

    def __init__(self, move_filter_fn: Callable[[Any, Any], Any] = _noop_filter) -> None:
        self.move_filter_fn = move_filter_fn

    @staticmethod
    def is_body_action(action_name: str) -> bool:
        """Whether the registered control ``action_name`` moves the body (else the sensors)."""
        return _lookup(action_name).body_action

    def action(
        self,
        obj: SceneNode,
        action_name: str,
        actuation_spec: ActuationSpec | None,
        apply_filter: bool = True,
    ) -> bool:
        """Run control ``action_name`` on ``obj``; return whether the filter blocked it.

        ``actuation_spec`` is None when the action spec has none (as Habitat's
        ``ActionSpec.actuation``); a custom control may ignore it."""
        control = _lookup(action_name)
        start = np.asarray(obj.absolute_translation, dtype=np.float64)
        control(obj, actuation_spec)
        end = np.asarray(obj.absolute_translation, dtype=np.float64)
        if not apply_filter:
            return False
        filtered = np.asarray(self.move_filter_fn(start, end), dtype=np.float64)
        obj.translate(filtered - end)  # the node's parent frame is the world for agents
        moved_sq = float(np.sum((filtered - start) ** 2))
        wanted_sq = float(np.sum((end - start) ** 2))
        return moved_sq + EPS < wanted_sq

    def __call__(
        self,
        obj: SceneNode,
        action_name: str,
        actuation_spec: ActuationSpec | None,
        apply_filter: bool = True,
    ) -> bool:
        return self.action(obj, action_name, actuation_spec, apply_filter)


def _lookup(action_name: str):
    control = registry.get_move_fn(action_name)
    if control is None:
        raise UnknownActionError(
            f"No move_fn for action {action_name!r}; registered: {registry.move_fn_names()}"
        )
    return control
