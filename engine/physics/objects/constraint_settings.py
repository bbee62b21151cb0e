"""What a rigid constraint holds together: Habitat's ``RigidConstraintSettings`` and
``RigidConstraintType`` (the solve is in :mod:`.constraints`).

Every field is checked when it is set, so a bad value raises naming the field before a
constraint exists: ids are ints, ``max_impulse > 0``; a pivot is a finite point within the
coordinate range positions obey (``|component| <= MAX_COORDINATE``, the largest 32-bit float:
beyond it Habitat's float pivots are inf, and the anchor algebra ``r x lambda`` overflows);
a frame is a rotation, ``|F^T F - I| <= ORTHOGONALITY_TOLERANCE`` entrywise and
``det F > 0`` (a zero, sheared or mirroring frame has no orientation to hold).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine import mn
from engine.core.fixed_fields import unknown_attribute_error
from engine.core.named_enum import NamedIntEnum

from ..core.settings import MAX_COORDINATE, ORTHOGONALITY_TOLERANCE

__all__ = ["WORLD", "RigidConstraintSettings", "RigidConstraintType"]

#: object id that means "the world" (Habitat's -1).
WORLD = -1


class RigidConstraintType(NamedIntEnum):
    """Habitat's constraint kinds."""

    PointToPoint = 0
    Fixed = 1


_SETTINGS_FIELDS = (
    "constraint_type",
    "max_impulse",
    "object_id_a",
    "object_id_b",
    "link_id_a",
    "link_id_b",
    "pivot_a",
    "pivot_b",
    "frame_a",
    "frame_b",
)


class RigidConstraintSettings:
    """What a constraint holds together (Habitat's fields and defaults).

    ``object_id_b = -1`` attaches A to the world: ``pivot_b`` and ``frame_b`` are then
    world-frame; otherwise each pivot and frame is in its own object's local frame.
    """

    __slots__ = tuple(f"_{name}" for name in _SETTINGS_FIELDS)

    def __init__(self) -> None:
        self.constraint_type = RigidConstraintType.PointToPoint
        self.max_impulse = 1000.0
        self.object_id_a = -1
        self.object_id_b = -1
        self.link_id_a = 0
        self.link_id_b = 0
        self.pivot_a = mn.Vector3()
        self.pivot_b = mn.Vector3()
        self.frame_a = mn.Matrix3x3()
        self.frame_b = mn.Matrix3x3()

    def __setattr__(self, name: str, value: Any) -> None:
        if name not in _SETTINGS_FIELDS:
            raise unknown_attribute_error("RigidConstraintSettings", name, _SETTINGS_FIELDS)
        if name == "constraint_type":
            value = RigidConstraintType(int(value))
        elif name == "max_impulse":
            value = float(value)
            if not value > 0.0:
                raise ValueError(f"max_impulse must be > 0, got {value!r}")
        elif name.startswith(("object_id", "link_id")):
            if isinstance(value, bool) or not isinstance(value, int | np.integer):
                raise TypeError(f"{name} must be an int, got {value!r}")
            value = int(value)
        elif name.startswith("pivot"):
            value = checked_pivot(value, name)
        else:
            value = mn.Matrix3x3(checked_frame(value, name))
        object.__setattr__(self, f"_{name}", value)

    def __getattr__(self, name: str) -> Any:
        if name in _SETTINGS_FIELDS:
            value = object.__getattribute__(self, f"_{name}")
            return (
                type(value)(np.asarray(value))
                if isinstance(value, mn.Vector3 | mn.Matrix3x3)
                else value
            )
        raise unknown_attribute_error("RigidConstraintSettings", name, _SETTINGS_FIELDS)

    def copy(self) -> RigidConstraintSettings:
        clone = RigidConstraintSettings()
        for name in _SETTINGS_FIELDS:
            setattr(clone, name, getattr(self, name))
        return clone

    def __repr__(self) -> str:
        return (
            f"RigidConstraintSettings({self.constraint_type.name}, a={self.object_id_a}, "
            f"b={self.object_id_b}, max_impulse={self.max_impulse})"
        )


def checked_pivot(value: Any, name: str) -> mn.Vector3:
    """A pivot as a finite ``Vector3`` within ``MAX_COORDINATE``, else ValueError naming it."""
    pivot = mn.to_vector3(value, name)
    if np.any(np.abs(np.asarray(pivot)) > MAX_COORDINATE):
        raise ValueError(
            f"{name} must lie within +-{MAX_COORDINATE:.4g} m on every axis (the range of "
            f"positions), got {np.asarray(pivot).tolist()}"
        )
    return pivot


def checked_frame(value: Any, name: str) -> np.ndarray:
    """A constraint frame as a ``(3, 3)`` rotation matrix, else ValueError naming it."""
    try:
        matrix = np.array(np.asarray(value), dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a 3x3 rotation matrix, got {value!r}") from error
    if matrix.shape != (3, 3) or not np.all(np.isfinite(matrix)):
        raise ValueError(f"{name} must be a finite 3x3 rotation, got {value!r}")
    off = np.abs(matrix.T @ matrix - np.eye(3)).max()
    if off > ORTHOGONALITY_TOLERANCE or np.linalg.det(matrix) <= 0.0:
        raise ValueError(
            f"{name} must be a rotation (orthonormal columns, determinant +1), got "
            f"{matrix.tolist()} (|F^T F - I| = {off:.3g}, det = {np.linalg.det(matrix):.3g})"
        )
    return matrix
