"""rigidsim's physics: the public names of ``habitat_sim.physics``.

``MotionType``, ``VelocityControl``, ``RigidObjectManager``, ``ManagedRigidObject``,
``RaycastResults``, ``RayHitInfo``, ``ContactPointData``, ``RigidState`` and the world,
``PhysicsWorld``, are importable from here as from Habitat. ``world.py`` holds
``PhysicsWorld`` and its step (read it first); ``core/settings.py`` the conventions (Y up,
meters, quaternions ``[x, y, z, w]``, contact normals from body A to body B).

The code is in folders by stage of the step, like Bullet's and Jolt's sources; each
folder's ``__init__`` maps it. The layering, lowest first (a folder imports only folders
below it; no import circle, type-hint imports included, between modules or folders):

1. ``core/``: settings, body state arrays, shapes, quaternions, timers;
2. ``collision/`` and ``solver/``, independent of each other: the batched pieces of the
   collision stage (broad phase, contact rules, manifolds) and of the solve, integrate
   and sleep stages (rows, colors, sweeps, stage priority);
3. ``reference/``: their plain twins, one pair or one contact point at a time;
4. ``pipeline/``: the collision and solve stages, which pick the batched path or the twin,
   and the contact pair table;
5. ``objects/``: Habitat's object API (manager, object handles, velocity control,
   constraints, queries);
6. ``world.py`` and this ``__init__``: ``PhysicsWorld``, its step and the public names.

The articulated-object names (``ManagedArticulatedObject``, ``ArticulatedObjectManager``,
``JointMotorSettings``, ...) are placeholders that raise ``NotImplementedError`` when used
(:mod:`engine.physics.objects.articulated`): rigidsim has no articulated objects.
"""

from __future__ import annotations

from engine.core.named_enum import NamedIntEnum

from .collision.collision_groups import CollisionGroupHelper, CollisionGroups
from .core.settings import SolverSettings
from .objects.articulated import (  # placeholders: no articulated objects
    ArticulatedObjectManager,
    JointMotorSettings,
    JointMotorType,
    JointType,
    ManagedArticulatedObject,
    ManagedBulletArticulatedObject,
)
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
    "ArticulatedObjectManager",
    "JointMotorSettings",
    "JointMotorType",
    "JointType",
    "ManagedArticulatedObject",
    "ManagedBulletArticulatedObject",
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
