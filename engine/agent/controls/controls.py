"""The base of every agent control and its parameters (Habitat's ``agent.controls.controls``,
which re-exports them; they live here, outside :mod:`engine.agent`, so that
:mod:`engine.registry` can check a control's class without importing the agent package).

A control is a callable object ``control(scene_node, actuation_spec)`` that moves a scene node;
``body_action`` says whether it moves the agent's body or its sensors. See
:mod:`engine.agent.controls.default_controls` for the registered ones.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import Any

from engine.core.fixed_fields import FixedFields

__all__ = ["ActuationSpec", "SceneNodeControl"]


@dataclass
class ActuationSpec(FixedFields):
    """How far a control moves: meters for moves, degrees for turns and looks.

    ``constraint`` (degrees) bounds the look angle of ``look_up/down/left/right``; None means
    unbounded.
    """

    amount: float
    constraint: float | None = None


class SceneNodeControl(abc.ABC):
    """Base class of controls: subclass it, implement ``__call__``, register it."""

    def __init__(self, body_action: bool = False) -> None:
        self.body_action = bool(body_action)

    @abc.abstractmethod
    def __call__(self, scene_node: Any, actuation_spec: ActuationSpec) -> None:
        """Move ``scene_node`` as ``actuation_spec`` says."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}(body_action={self.body_action})"
