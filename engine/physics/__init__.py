"""rigidsim's physics: the public names of ``habitat_sim.physics``.

``MotionType``, ``VelocityControl``, ``RigidObjectManager``, ``ManagedRigidObject``,
``RaycastResults``, ``RayHitInfo``, ``ContactPointData``, ``RigidState`` and the world,
``PhysicsWorld``. See :mod:`engine.physics.world` for the step pipeline and
:mod:`engine.physics.core.settings` for the conventions (Y up, meters, quaternions
``[x, y, z, w]``, contact normals from body A to body B).
"""

from __future__ import annotations

from engine.core.named_enum import NamedIntEnum

from .collision.collision_groups import CollisionGroupHelper, CollisionGroups
from .core.settings import SolverSettings
from .objects.constraints import RigidConstraintSettings, RigidConstraintType
from .objects.queries import ContactPointData, RaycastResults, RayHitInfo
from .objects.rigid_object_manager import (
    DeadObjectError,
    ManagedRigidObject,
    MotionType,
    RigidObjectManager,
)
from .objects.velocity_control import RigidState, VelocityControl
from .world import STAGE_ID, PhysicsWorld


class PhysicsSimulationLibrary(NamedIntEnum):
    """Habitat's physics backends. rigidsim's solver stands in for ``Bullet`` (the value a
    physics-enabled Habitat simulator reports, so Habitat's checks keep working)."""

    NoPhysics = 0
    Bullet = 1


__all__ = [
    "STAGE_ID",
    "CollisionGroupHelper",
    "CollisionGroups",
    "PhysicsSimulationLibrary",
    "RigidConstraintSettings",
    "RigidConstraintType",
    "ContactPointData",
    "DeadObjectError",
    "ManagedRigidObject",
    "MotionType",
    "PhysicsWorld",
    "RayHitInfo",
    "RaycastResults",
    "RigidObjectManager",
    "RigidState",
    "SolverSettings",
    "VelocityControl",
]
