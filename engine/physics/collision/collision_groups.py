"""Collision groups and masks (Habitat's ``CollisionGroups`` and ``CollisionGroupHelper``).

Every body belongs to one group (a single bit) and carries the mask of its group (the bits of
the groups it may touch). Two bodies A and B interact, in contacts, contact tests and ray
casts, only when each is in the other's mask (Bullet's two-way filter)::

    collide(A, B) = (group_A & mask_B) != 0  and  (group_B & mask_A) != 0

A body's group follows its motion type (STATIC -> ``Static``, KINEMATIC -> ``Kinematic``,
DYNAMIC -> ``Dynamic``) unless ``obj.override_collision_group(group)`` fixed it; changing
the motion type (to a different one) resets the group to the new type's, as Habitat does.
As in Bullet, a body copies its group's mask when it gets the group (creation, override,
motion type change): editing a mask later affects bodies only once their group is set again
(Habitat's note: "changing group settings requires overriding object group again"). The default
masks are Habitat's: every group touches everything except ``Noncollidable``, except that
``Static`` and ``Kinematic`` ignore each other (and themselves), and ``Noncollidable``
touches nothing. Rays are in the ``Default`` group. The stage is a ``Static`` body.

The masks are global, as in Habitat (static methods of ``CollisionGroupHelper``); tests that
change them should restore them (``CollisionGroupHelper.reset()``).
"""

from __future__ import annotations

import enum
from typing import ClassVar

import numpy as np

__all__ = [
    "CollisionGroupHelper",
    "CollisionGroups",
    "assign_group",
    "filter_pairs",
    "group_for_motion_type",
    "interacts_with_group",
]


class CollisionGroups(enum.IntFlag):
    """Habitat's collision groups (one bit each)."""

    Default = 1
    Static = 2
    Kinematic = 4
    Dynamic = 8
    Robot = 16
    Noncollidable = 32
    UserGroup0 = 64
    UserGroup1 = 128
    UserGroup2 = 256
    UserGroup3 = 512
    UserGroup4 = 1024
    UserGroup5 = 2048
    UserGroup6 = 4096
    UserGroup7 = 8192
    UserGroup8 = 16384
    UserGroup9 = 32768


#: every group bit (Habitat's ``AllFilter`` as a mask)
ALL_GROUPS = int(sum(g.value for g in CollisionGroups))


def _default_masks() -> dict[int, int]:
    everything = ALL_GROUPS & ~CollisionGroups.Noncollidable
    masks = {int(g): int(everything) for g in CollisionGroups}
    not_fixed = int(everything & ~CollisionGroups.Static & ~CollisionGroups.Kinematic)
    masks[int(CollisionGroups.Static)] = not_fixed
    masks[int(CollisionGroups.Kinematic)] = not_fixed
    masks[int(CollisionGroups.Noncollidable)] = 0
    return masks


def _default_names() -> dict[str, int]:
    return {name: int(group) for name, group in CollisionGroups.__members__.items()}


class CollisionGroupHelper:
    """Static helpers over the global group -> mask table (Habitat's names)."""

    _masks: ClassVar[dict[int, int]] = _default_masks()
    _names: ClassVar[dict[str, int]] = _default_names()

    @staticmethod
    def _check(group: int | str) -> int:
        if isinstance(group, str):
            return int(CollisionGroupHelper.get_group(group))
        value = int(group)
        if value not in CollisionGroupHelper._masks:
            raise ValueError(f"not a single collision group: {group!r}")
        return value

    @staticmethod
    def get_mask_for_group(group: int) -> CollisionGroups:
        return CollisionGroups(CollisionGroupHelper._masks[CollisionGroupHelper._check(group)])

    @staticmethod
    def set_mask_for_group(group: int, mask: int) -> None:
        """Set which groups ``group`` interacts with (both sides must agree to collide)."""
        CollisionGroupHelper._masks[CollisionGroupHelper._check(group)] = int(mask) & ALL_GROUPS

    @staticmethod
    def set_group_interacts_with(group_a: int, group_b: int, interacts: bool) -> None:
        """Set or clear the bits of ``a`` in ``b``'s mask and of ``b`` in ``a``'s mask."""
        a, b = CollisionGroupHelper._check(group_a), CollisionGroupHelper._check(group_b)
        for one, other in ((a, b), (b, a)):
            mask = CollisionGroupHelper._masks[one]
            CollisionGroupHelper._masks[one] = (mask | other) if interacts else (mask & ~other)

    @staticmethod
    def get_group(name: str) -> CollisionGroups:
        if name not in CollisionGroupHelper._names:
            raise ValueError(f"no collision group named {name!r}")
        return CollisionGroups(CollisionGroupHelper._names[name])

    @staticmethod
    def get_group_name(group: int) -> str:
        value = CollisionGroupHelper._check(group)
        return next(n for n, g in CollisionGroupHelper._names.items() if g == value)

    @staticmethod
    def set_group_name(group: int, new_name: str) -> bool:
        """Rename a group; False (as Habitat) if the name is taken."""
        if new_name in CollisionGroupHelper._names:
            return False
        old = CollisionGroupHelper.get_group_name(group)
        CollisionGroupHelper._names[new_name] = CollisionGroupHelper._names.pop(old)
        return True

    @staticmethod
    def get_all_group_names() -> list[str]:
        return list(CollisionGroupHelper._names)

    @staticmethod
    def reset() -> None:
        """Restore Habitat's default masks and names (rigidsim's helper for tests)."""
        CollisionGroupHelper._masks = _default_masks()
        CollisionGroupHelper._names = _default_names()


def group_for_motion_type(motion_type: np.ndarray) -> np.ndarray:
    """Default group of each body from its motion type (0 static, 1 kinematic, 2 dynamic)."""
    table = np.array(
        [CollisionGroups.Static, CollisionGroups.Kinematic, CollisionGroups.Dynamic], dtype=np.int64
    )
    return table[np.clip(motion_type, 0, 2)]


def filter_pairs(bodies, pairs: np.ndarray) -> np.ndarray:
    """The rows of ``pairs (p, 2)`` whose bodies' groups and (copied) masks let them collide:
    ``(g_a & m_b) != 0 and (g_b & m_a) != 0``."""
    if len(pairs) == 0:
        return pairs
    group, mask = bodies.body_collision_group, bodies.body_collision_mask
    a, b = pairs[:, 0], pairs[:, 1]
    return pairs[((group[a] & mask[b]) != 0) & ((group[b] & mask[a]) != 0)]


def interacts_with_group(bodies, indices: np.ndarray, group: int) -> np.ndarray:
    """``(k,)`` bool: bodies ``indices`` interact with a probe of ``group`` (e.g. a ray, whose
    mask is the group's current one)."""
    indices = np.asarray(indices, dtype=np.int64)
    probe_mask = CollisionGroupHelper._masks[int(group)]
    return ((bodies.body_collision_group[indices] & probe_mask) != 0) & (
        (int(group) & bodies.body_collision_mask[indices]) != 0
    )


def assign_group(bodies, index: int, group: int | None = None) -> None:
    """Give body ``index`` a group (None: its motion type's) and copy that group's mask."""
    if group is None:
        group = int(group_for_motion_type(bodies.body_motion_type[index : index + 1])[0])
    value = CollisionGroupHelper._check(group)
    bodies.body_collision_group[index] = value
    bodies.body_collision_mask[index] = CollisionGroupHelper._masks[value]
