"""Habitat's ``habitat_sim.errors``: the exceptions Habitat code catches by name."""

from __future__ import annotations

from typing import Any

__all__ = ["GreedyFollowerError", "InvalidAttachedObject", "assert_obj_valid"]


class GreedyFollowerError(Exception):
    """The greedy follower found no way to the goal (no path, or too many actions)."""


class InvalidAttachedObject(RuntimeError):
    """An object (sensor, agent body) is no longer attached to a scene node."""


def assert_obj_valid(obj: Any) -> None:
    """Raise :class:`InvalidAttachedObject` when ``obj`` (or its ``object``) is None."""
    if obj is None or getattr(obj, "object", True) is None:
        raise InvalidAttachedObject("attached object is invalid: it has no scene node")
