"""rigidsim's physics: the public names of ``habitat_sim.physics``.

``MotionType``, ``VelocityControl``, ``RigidObjectManager``, ``ManagedRigidObject``,
``RaycastResults``, ``RayHitInfo``, ``ContactPointData``, ``RigidState`` and the world,
``PhysicsWorld``. See :mod:`engine.physics.world` for the step pipeline and
:mod:`engine.physics.settings` for the conventions (Y up, meters, quaternions
``[x, y, z, w]``, contact normals from body A to body B).
"""

from __future__ import annotations

from .objects import DeadObjectError, ManagedRigidObject, MotionType, RigidObjectManager
from .queries import ContactPointData, RaycastResults, RayHitInfo
from .settings import SolverSettings
from .velocity_control import RigidState, VelocityControl
from .world import STAGE_ID, PhysicsWorld

__all__ = [
    "STAGE_ID",
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
