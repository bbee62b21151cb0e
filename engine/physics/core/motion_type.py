"""``MotionType``: how a rigid object moves (Habitat's ``habitat_sim.physics.MotionType``).

The values are the ints stored in ``Bodies.body_motion_type``; an ``IntEnum`` compares equal
to them, so ``bodies.body_motion_type == MotionType.DYNAMIC`` is a plain array comparison.
"""

from __future__ import annotations

from engine.core.named_enum import NamedIntEnum


class MotionType(NamedIntEnum):
    """How an object moves. Set with ``obj.motion_type = MotionType.KINEMATIC``."""

    def __new__(cls, value: int, doc: str):
        member = int.__new__(cls, value)
        member._value_ = value
        member.__doc__ = doc
        return member

    UNDEFINED = (-1, "Not a valid motion type; setting it raises ValueError.")
    STATIC = (
        0,
        "Never moves: pose setters are silently ignored; other bodies collide with "
        "it. Use for furniture you do not want to move (and to bake into a navmesh).",
    )
    KINEMATIC = (
        1,
        "Moved only by its pose setters or velocity control; pushes dynamic "
        "bodies and is never pushed. Use for robots and scripted motion.",
    )
    DYNAMIC = (2, "Moved by gravity, forces, impulses and contacts. The default.")
