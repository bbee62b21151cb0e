"""Scratch poses for the greedy follower: the agent's controls on a node, or their arithmetic.

The greedy geodesic follower (``engine.nav``) tries many short primitives ``[turn] * n +
[forward]`` from the agent's pose without moving the agent. Habitat runs each primitive through
the agent's own controls on a scratch scene node; rigidsim keeps that as the reference path and
adds a fast twin for the default controls (``GreedyGeodesicFollower.use_reference_poses``
selects the reference):

* :class:`NodePose` (reference): a scratch ``SceneNode`` moved by ``agent.controls`` -- any
  registered control, any actuation, the agent's move filter.
* :class:`ArrayPose` (fast): the same arithmetic as the default ``move_forward`` /
  ``turn_left`` / ``turn_right`` controls and ``ObjectControls.action``, on a position array and
  an ``[x, y, z, w]`` quaternion, skipping the scene-node and Magnum wrappers::

      turn by theta about local +Y:  r = (0, sin(theta/2), 0, cos(theta/2))
                                     q <- normalize(normalize(q * r))
      forward by a:                  e = p + R(q) (0, 0, -a);   f = move_filter(p, e)
                                     p <- e + (f - e)
                                     collided = |f - p|^2 + eps < |e - p|^2

  It applies only when the agent's three actions are the default controls without a look
  constraint (:func:`default_controls_used`); the follower falls back to :class:`NodePose`
  otherwise. ``tests/engine/test_greedy_follower.py`` proves both give the same actions.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

import numpy as np

from engine import mn
from engine.agent.controls import ActuationSpec
from engine.agent.controls.default_controls import LookLeft, LookRight, MoveForward
from engine.agent.controls.object_controls import EPS
from engine.agent.controls.registry import registry
from engine.scene.graph import SceneNode

#: the follower's action names and the default control classes the fast path reproduces
DEFAULT_CONTROLS = {"move_forward": MoveForward, "turn_left": LookLeft, "turn_right": LookRight}


PoseT = TypeVar("PoseT", bound="ScratchPose")


class ScratchPose(Protocol):
    """A pose the follower can try actions on (``name`` is a control name)."""

    def act(self, name: str) -> bool:
        """Apply the action; return whether the move filter blocked part of it."""

    def copy(self: PoseT) -> PoseT:
        """An independent copy of this pose."""

    @property
    def position(self) -> np.ndarray:
        """World position, meters."""


class NodePose:
    """Reference: a scratch scene node moved by the agent's own controls."""

    def __init__(
        self, controls: Any, specs: dict[str, ActuationSpec], position: Any, rotation: Any
    ) -> None:
        self.controls, self.specs = controls, specs
        self.node = SceneNode(name="greedy follower scratch")
        self.node.translation = position
        self.node.rotation = rotation

    def act(self, name: str) -> bool:
        return bool(self.controls(self.node, name, self.specs[name], True))

    def copy(self) -> NodePose:
        return NodePose(self.controls, self.specs, self.node.translation, self.node.rotation)

    @property
    def position(self) -> np.ndarray:
        return np.asarray(self.node.translation, dtype=np.float64)


class ArrayPose:
    """Fast twin: the default controls' arithmetic on ``(3,)`` position and ``[x, y, z, w]``."""

    def __init__(
        self,
        move_filter: Callable[[Any, Any], Any],
        specs: dict[str, ActuationSpec],
        position: np.ndarray,
        xyzw: np.ndarray,
    ):
        self.move_filter, self.specs = move_filter, specs
        self.xyzw = np.asarray(xyzw, dtype=np.float64)
        self._position = np.asarray(position, dtype=np.float64)

    def act(self, name: str) -> bool:
        amount = float(self.specs[name].amount)
        if name == "move_forward":
            return self._forward(amount)
        self._turn(amount if name == "turn_left" else -amount)
        return False

    def _turn(self, degrees: float) -> None:
        turned = mn.quaternion_multiply(self.xyzw, _turn_quaternion(degrees))
        turned = turned / np.linalg.norm(turned)  # SceneNode.rotate_local
        self.xyzw = turned / np.linalg.norm(turned)  # the control's normalized()

    def _forward(self, amount: float) -> bool:
        start, end = self._position, self.forward_target(amount)
        filtered = np.asarray(self.move_filter(start, end), dtype=np.float64)
        self._position, collided = filtered_move(start, end, filtered)
        return collided

    def forward_target(self, amount: float) -> np.ndarray:
        """Where ``move_forward`` by ``amount`` aims, before the move filter:
        ``p + R(q) (0, 0, -amount)``, i.e. ``-amount`` times the third column of ``R(q)``
        (``mn.quaternion_to_matrix``; the product's other terms are exact zeros)."""
        x, y, z, w = self.xyzw.tolist()
        along = -amount
        offset = [2 * (x * z + w * y) * along, 2 * (y * z - w * x) * along]
        offset.append((1 - 2 * (x * x + y * y)) * along)
        return self._position + np.array(offset)

    def copy(self) -> ArrayPose:
        return ArrayPose(self.move_filter, self.specs, self._position, self.xyzw)

    @property
    def position(self) -> np.ndarray:
        return self._position


@functools.lru_cache(maxsize=16)
def _turn_quaternion(degrees: float) -> np.ndarray:
    """``[x, y, z, w]`` of a turn by ``degrees`` about local +Y (computed once per angle)."""
    half = 0.5 * math.radians(degrees)
    turn = np.array([0.0, math.sin(half), 0.0, math.cos(half)])
    turn.flags.writeable = False
    return turn


def filtered_move(
    start: np.ndarray, end: np.ndarray, filtered: np.ndarray
) -> tuple[np.ndarray, bool]:
    """(new position, collided) of a move ``start -> end`` that the filter sent to
    ``filtered``: ``ObjectControls.action``'s arithmetic."""
    # plain floats: the same sums as np.sum over 3 components, without its call overhead
    moved_sq = sum((f - s) ** 2 for f, s in zip(filtered.tolist(), start.tolist(), strict=True))
    wanted_sq = sum((e - s) ** 2 for e, s in zip(end.tolist(), start.tolist(), strict=True))
    return end + (filtered - end), moved_sq + EPS < wanted_sq


def default_controls_used(specs: dict[str, ActuationSpec]) -> bool:
    """Whether the fast :class:`ArrayPose` reproduces these actions (default controls, no
    look constraint)."""
    for name, control_class in DEFAULT_CONTROLS.items():
        if type(registry.get_move_fn(name)) is not control_class:
            return False
        if name != "move_forward" and specs[name].constraint is not None:
            return False
    return True
