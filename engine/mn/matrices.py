"""Matrices and boxes of :mod:`engine.mn`: Magnum's ``Matrix3x3``, ``Matrix4``, ``Range3D``.

A ``Matrix4`` is a 4x4 homogeneous transformation whose columns are the basis vectors and the
translation. Magnum's quirk is kept: ``Matrix4.translation(v)`` and ``Matrix4.rotation(angle,
axis)`` construct on the class, while ``m.translation`` and ``m.rotation()`` read an instance.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine.mn.vectors import Vector3, finite_array, radians

__all__ = ["Matrix3x3", "Matrix4", "Range3D"]


# --------------------------------------------------------------------------------------------
# Matrices
# --------------------------------------------------------------------------------------------
class _MatrixN:
    """Shared behaviour of the square matrix wrappers (a float64 array, rows x columns)."""

    _size = 4
    __slots__ = ("_data",)
    __array_priority__ = 20.0

    def __init__(self, data: Any = None) -> None:
        if data is None:
            data = np.eye(self._size)
        array = np.array(data, dtype=np.float64)
        if array.shape != (self._size, self._size):
            raise ValueError(
                f"{type(self).__name__} needs shape ({self._size}, {self._size}), "
                f"got {array.shape}"
            )
        self._data = array

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self._data.astype(dtype) if dtype is not None else self._data.copy()

    def __getitem__(self, index: Any) -> Any:
        return self._data[index]

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._data.tolist()})"

    def __eq__(self, other: object) -> bool:
        try:
            return bool(np.array_equal(self._data, np.asarray(other, dtype=np.float64)))
        except (TypeError, ValueError):
            return False

    __hash__ = None  # mutable-looking value type, like ndarray

    def __matmul__(self, other: Any) -> Any:
        result = self._data @ np.asarray(other, dtype=np.float64)
        if result.shape == self._data.shape:
            return type(self)(result)
        return Vector3(result) if result.shape == (3,) else result

    __mul__ = __matmul__

    def transposed(self) -> Any:
        return type(self)(self._data.T)

    def inverted(self) -> Any:
        return type(self)(np.linalg.inv(self._data))

    @classmethod
    def identity_init(cls) -> Any:
        return cls()


class Matrix3x3(_MatrixN):
    """A 3x3 matrix (Magnum's ``Matrix3x3``), e.g. a rotation from :meth:`Quaternion.to_matrix`."""

    _size = 3
    __slots__ = ()


class _TranslationAccessor:
    """``Matrix4.translation(v)`` builds a translation; ``m.translation`` reads one (Magnum)."""

    def __get__(self, instance: Matrix4 | None, owner: type) -> Any:
        if instance is None:
            return owner._translation_matrix
        return Vector3(instance._data[:3, 3])


class Matrix4(_MatrixN):
    """A 4x4 homogeneous transformation (Magnum's ``Matrix4``); columns are basis vectors."""

    _size = 4
    __slots__ = ()
    translation = _TranslationAccessor()

    @classmethod
    def from_(cls, rotation_scaling: Any, translation: Any) -> Matrix4:
        """Build from a 3x3 rotation (and scaling) part and a translation."""
        matrix = np.eye(4)
        matrix[:3, :3] = np.asarray(rotation_scaling, dtype=np.float64)
        matrix[:3, 3] = finite_array(translation, 3, "translation")
        return cls(matrix)

    @classmethod
    def _translation_matrix(cls, vector: Any) -> Matrix4:
        return cls.from_(np.eye(3), vector)

    @classmethod
    def scaling(cls, vector: Any) -> Matrix4:
        return cls.from_(np.diag(finite_array(vector, 3, "scaling")), (0.0, 0.0, 0.0))

    def rotation_scaling(self) -> Matrix3x3:
        return Matrix3x3(self._data[:3, :3])

    def rotation_normalized(self) -> Matrix3x3:
        """The rotation part with scaling divided out (columns normalized)."""
        block = self._data[:3, :3]
        return Matrix3x3(block / np.linalg.norm(block, axis=0))

    def transform_point(self, point: Any) -> Vector3:
        """``M (p, 1)``: rotation, scaling and translation."""
        return Vector3(self._data[:3, :3] @ np.asarray(point, dtype=np.float64) + self._data[:3, 3])

    def transform_vector(self, vector: Any) -> Vector3:
        """``M (v, 0)``: rotation and scaling, no translation."""
        return Vector3(self._data[:3, :3] @ np.asarray(vector, dtype=np.float64))

    def inverted_rigid(self) -> Matrix4:
        """Inverse of a rotation + translation matrix: ``[R^T, -R^T t]``."""
        rotation = self._data[:3, :3]
        return Matrix4.from_(rotation.T, -rotation.T @ self._data[:3, 3])


def quaternion_to_matrix(xyzw: np.ndarray) -> np.ndarray:
    """3x3 rotation matrix of a unit ``[x, y, z, w]`` quaternion (see the module docstring)."""
    x, y, z, w = xyzw
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def axis_angle_matrix(angle: Any, axis: Any) -> np.ndarray:
    """3x3 rotation by ``angle`` (:class:`Deg` or :class:`Rad`) about ``axis`` (normalized
    here), through the unit quaternion ``(u sin(theta/2), cos(theta/2))``."""
    axis_array = finite_array(axis, 3, "axis")
    axis_length = np.linalg.norm(axis_array)
    if axis_length < 1e-12:
        raise ValueError(f"rotation axis must be non-zero, got {axis_array.tolist()}")
    half = 0.5 * radians(angle)
    return quaternion_to_matrix(np.append(axis_array / axis_length * math.sin(half),
                                          math.cos(half)))


class _DualRotation:
    """``Matrix4.rotation(angle, axis)`` on the class, ``m.rotation()`` on an instance."""

    def __get__(self, instance: Matrix4 | None, owner: type) -> Any:
        if instance is None:
            return lambda angle, axis: owner.from_(axis_angle_matrix(angle, axis),
                                                   (0.0, 0.0, 0.0))
        return instance.rotation_normalized


Matrix4.rotation = _DualRotation()


# --------------------------------------------------------------------------------------------
# Axis-aligned boxes
# --------------------------------------------------------------------------------------------
class Range3D:
    """An axis-aligned box ``[min, max]`` (Magnum's ``Range3D``), e.g. an object's AABB."""

    __slots__ = ("_min", "_max")

    def __init__(self, min: Any = (0.0, 0.0, 0.0), max: Any = (0.0, 0.0, 0.0)) -> None:  # noqa: A002
        self._min = finite_array(min, 3, "min")
        self._max = finite_array(max, 3, "max")

    @classmethod
    def from_points(cls, points: Any) -> Range3D:
        array = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return cls(array.min(axis=0), array.max(axis=0))

    @property
    def min(self) -> Vector3:
        return Vector3(self._min)

    @property
    def max(self) -> Vector3:
        return Vector3(self._max)

    @property
    def front_bottom_left(self) -> Vector3:
        return Vector3(self._min[0], self._min[1], self._max[2])

    def size(self) -> Vector3:
        return Vector3(self._max - self._min)

    def center(self) -> Vector3:
        return Vector3(0.5 * (self._min + self._max))

    def size_x(self) -> float:
        return float(self._max[0] - self._min[0])

    def size_y(self) -> float:
        return float(self._max[1] - self._min[1])

    def size_z(self) -> float:
        return float(self._max[2] - self._min[2])

    def contains(self, point: Any) -> bool:
        p = np.asarray(point, dtype=np.float64)
        return bool(np.all(p >= self._min) and np.all(p <= self._max))

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Range3D)
            and bool(np.array_equal(self._min, other._min))
            and bool(np.array_equal(self._max, other._max))
        )

    __hash__ = None

    def __repr__(self) -> str:
        return f"Range3D(min={self.min!r}, max={self.max!r})"
