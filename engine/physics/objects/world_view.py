"""What an object handle and the constraint store read of the physics world.

:class:`WorldView` is a structural type (:class:`typing.Protocol`): the attributes and
methods of :class:`engine.physics.world.PhysicsWorld` that :mod:`physics_object`,
:mod:`object_properties` and :mod:`constraints` use. They annotate their ``world`` with it
instead of importing ``PhysicsWorld``, which imports them, so the world sits above the
objects and no import, type hints included, goes back up. mypy checks that the
``PhysicsWorld`` passed in has every member listed here.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from ..collision.collision_objects import CollisionObjects
from ..collision.contacts import ManifoldStore
from ..core.bodies import Bodies

__all__ = ["WorldView"]


class WorldView(Protocol):
    """The physics world as its objects and constraints see it."""

    #: every body's state arrays (index = object id, 0 = the stage)
    bodies: Bodies
    #: the persistent contact manifolds (islands for waking)
    manifolds: ManifoldStore
    #: the fcl objects of every body (the contact test)
    collision_objects: CollisionObjects
    #: the velocity control of every object, by object id
    velocity_controls: dict[int, Any]
    #: bodies already warned of a mass ratio beyond what the solver holds (mass_ratio.py)
    mass_ratio_warned: set[int]

    def get_physics_time_step(self) -> float:
        """The fixed step, seconds."""
        ...

    def set_body_pose(
        self, index: int, position: np.ndarray, rotation: np.ndarray, wake: bool = True
    ) -> None:
        """Teleport body ``index`` (position (3,), rotation [x, y, z, w])."""
        ...
