"""Geometry helpers of Habitat's ``habitat_sim.geo``: the :class:`Ray` used by ``cast_ray``
and :func:`get_transformed_bb` (the world box around a transformed local box).

Also Habitat's axis constants (Y up, -Z forward, right handed): ``UP``, ``GRAVITY``,
``FRONT``, ``BACK``, ``LEFT``, ``RIGHT``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine import mn

UP = np.array([0.0, 1.0, 0.0])
GRAVITY = -UP
FRONT = np.array([0.0, 0.0, -1.0])
BACK = -FRONT
LEFT = np.array([-1.0, 0.0, 0.0])
RIGHT = -LEFT


class Ray:
    """A ray ``origin + t direction`` (world frame, meters); ``direction`` need not be unit.

    Hit distances reported by ``cast_ray`` are in units of ``|direction|`` (Habitat's rule):
    with a unit direction they are meters.

    Examples
    --------
    >>> ray = Ray([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
    >>> [float(x) for x in ray.direction]
    [1.0, 0.0, 0.0]
    """

    def __init__(self, origin: Any = (0.0, 0.0, 0.0), direction: Any = (0.0, 0.0, 0.0)) -> None:
        self.origin = origin
        self.direction = direction

    @property
    def origin(self) -> mn.Vector3:
        return mn.Vector3(self._origin)

    @origin.setter
    def origin(self, value: Any) -> None:
        self._origin = np.asarray(mn.to_vector3(value, "origin"))

    @property
    def direction(self) -> mn.Vector3:
        return mn.Vector3(self._direction)

    @direction.setter
    def direction(self, value: Any) -> None:
        self._direction = np.asarray(mn.to_vector3(value, "direction"))

    def __repr__(self) -> str:
        return f"Ray(origin={self._origin.tolist()}, direction={self._direction.tolist()})"


def get_transformed_bb(range: mn.Range3D, xform: Any) -> mn.Range3D:  # noqa: A002 - Habitat's name
    """The axis-aligned box around ``range`` after the 4x4 transformation ``xform``.

    Each world axis of the result is the extent of the 8 transformed corners; computed as
    Arvo's method: ``center' = M center``, ``half' = |R S| half`` (absolute values of the
    rotation-scaling block times the half size), which bounds the corners exactly.
    """
    matrix = np.asarray(xform, dtype=np.float64)
    if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
        raise ValueError(f"xform must be a finite 4x4 matrix, got {xform!r}")
    low, high = np.asarray(range.min), np.asarray(range.max)
    center = matrix[:3, :3] @ (0.5 * (low + high)) + matrix[:3, 3]
    half = np.abs(matrix[:3, :3]) @ (0.5 * (high - low))
    return mn.Range3D(center - half, center + half)
