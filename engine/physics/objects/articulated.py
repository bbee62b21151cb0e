"""The articulated-object names of ``habitat_sim.physics``: placeholders and two enums.

Habitat-sim simulates articulated objects (URDF multibodies: links joined by revolute,
prismatic, spherical, planar or fixed joints, driven by joint motors) through Bullet's
Featherstone solver; habitat-lab's rearrange tasks and robots build on them. rigidsim
simulates rigid objects only (:class:`engine.physics.ManagedRigidObject`, joined if need be by
:class:`engine.physics.RigidConstraintSettings`), so the classes here are
:class:`~engine.core.placeholder.Placeholder`\\ s: habitat-lab imports and annotates
with them; constructing one, or calling a method on the class, raises
``NotImplementedError``. :meth:`engine.Simulator.get_articulated_object_manager` raises the
same way.

``JointType`` and ``JointMotorType`` are real enums (they are plain values; Habitat numbers
``JointType`` as Bullet's ``btMultibodyLink`` joint types: Revolute 0, Prismatic 1,
Spherical 2, Planar 3, Fixed 4, Invalid 5). Nothing in rigidsim produces them.
"""

from __future__ import annotations

from engine.core.named_enum import NamedIntEnum
from engine.core.placeholder import Placeholder

__all__ = [
    "ArticulatedObjectManager",
    "JointMotorSettings",
    "JointMotorType",
    "JointType",
    "ManagedArticulatedObject",
    "ManagedBulletArticulatedObject",
]

_MISSING = "articulated objects (URDF multibodies with joints and motors) are not simulated"
_INSTEAD = (
    "rigid objects through sim.get_rigid_object_manager() and ManagedRigidObject, "
    "joined with sim.create_rigid_constraint(RigidConstraintSettings)"
)


class JointType(NamedIntEnum):
    """Habitat's joint types of an articulated object's links (Bullet's numbering)."""

    Revolute = 0
    Prismatic = 1
    Spherical = 2
    Planar = 3
    Fixed = 4
    Invalid = 5


class JointMotorType(NamedIntEnum):
    """Habitat's joint motor kinds: one degree of freedom, or a spherical joint's three."""

    SingleDof = 0
    Spherical = 1


class ManagedArticulatedObject(Placeholder):
    """Placeholder of Habitat's handle to an articulated object (module docstring)."""

    habitat_name = "habitat_sim.physics.ManagedArticulatedObject"
    missing = _MISSING
    instead = _INSTEAD


class ManagedBulletArticulatedObject(ManagedArticulatedObject):
    """Placeholder of Habitat's Bullet-backed articulated-object handle."""

    habitat_name = "habitat_sim.physics.ManagedBulletArticulatedObject"


class ArticulatedObjectManager(Placeholder):
    """Placeholder of Habitat's articulated-object manager (``get_articulated_object_manager``)."""

    habitat_name = "habitat_sim.physics.ArticulatedObjectManager"
    missing = _MISSING
    instead = _INSTEAD


class JointMotorSettings(Placeholder):
    """Placeholder of Habitat's joint motor settings (position/velocity targets and gains)."""

    habitat_name = "habitat_sim.physics.JointMotorSettings"
    missing = "joint motors of articulated objects are not simulated"
    instead = (
        "drive a rigid object with its VelocityControl, or with forces and torques "
        "(apply_force, apply_torque)"
    )
