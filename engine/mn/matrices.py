"""Matrices of :mod:`engine.mn`: Magnum's ``Matrix3x3``, ``Matrix3``, ``Matrix4`` (the boxes,
``Range1D`` to ``Range3D``, are in :mod:`engine.mn.ranges`).

A ``Matrix4`` is a 4x4 homogeneous transformation whose columns are the basis vectors and the
translation; a ``Matrix3`` is the same for 2D (3x3 homogeneous, Magnum's 2D transformation
matrix; a plain 3x3 matrix is ``Matrix3x3``). Magnum's quirk is kept: ``Matrix4.translation(v)``
and ``Matrix4.rotation(angle, axis)`` construct on the class, while ``m.translation`` and
``m.rotation()`` read an instance. ``==`` is Magnum's fuzzy compare of every element
(:func:`engine.mn.vectors.fuzzy_equal`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine.mn.vectors import Vector2, Vector3, finite_array, fuzzy_equal, radians, stable_norm

__all__ = ["Matrix3", "Matrix3x3", "Matrix4"]


# --------------------------------------------------------------------------------------------
# Matrices
# --------------------------------------------------------------------------------------------
class _MatrixN:
    """Shared behaviour of the square matrix wrappers (a float64 array, rows x columns)."""

    _size = 4
    __slots__ = ("_data",)
    __array_priority__ = 20.0

    def __init__(self, data: Any = None, *more_columns: Any) -> None:
        """``Matrix(array)`` takes a (rows, columns) array; ``Matrix(c0, c1, ...)`` takes the
        columns one by one, as Magnum's constructor does."""
        if data is None:
            data = np.eye(self._size)
        if more_columns:
            data = np.column_stack([np.asarray(c, dtype=np.float64) for c in (data, *more_columns)])
        array = np.array(data, dtype=np.float64)
        if array.shape != (self._size, self._size):
            raise ValueError(
                f"{type(self).__name__} needs shape ({self._size}, {self._size}), got {array.shape}"
            )
        self._data = array

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self._data.astype(dtype) if dtype is not None else self._data.copy()

    def __getitem__(self, index: Any) -> Any:
        return self._data[index]

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._data.tolist()})"

    def __eq__(self, other: object) -> bool:
        """Magnum's fuzzy compare, element by element."""
        try:
            return fuzzy_equal(self._data, np.asarray(other, dtype=np.float64))
        except (TypeError, ValueError):
            return False

    # No __hash__: a mutable-looking value type, like ndarray (a class that defines __eq__
    # and no __hash__ gets ``__hash__ = None`` from Python).

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
    """``Matrix4.translation(v)`` builds a translation; ``m.translation`` reads one (Magnum).
    The same for ``Matrix3`` in 2D."""

    def __get__(self, instance: Any, owner: type[Matrix3] | type[Matrix4]) -> Any:
        if instance is None:
            return owner._translation_matrix
        if isinstance(instance, Matrix3):
            return Vector2(instance._data[:2, 2])
        return Vector3(instance._data[:3, 3])

    def __set__(self, instance: Any, value: Any) -> None:
        """``m.translation = v`` replaces the translation column (Magnum's setter)."""
        if isinstance(instance, Matrix3):
            instance._data[:2, 2] = finite_array(value, 2, "translation")
        else:
            instance._data[:3, 3] = finite_array(value, 3, "translation")


class _DualRotation2D:
    """``Matrix3.rotation(angle)`` on the class, ``m.rotation()`` (2x2 block) on an instance."""

    def __get__(self, instance: Matrix3 | None, owner: type[Matrix3]) -> Any:
        if instance is None:
            return owner._rotation_matrix
        return lambda: instance._data[:2, :2] / np.linalg.norm(instance._data[:2, :2], axis=0)


class Matrix3(Matrix3x3):
    """A 2D homogeneous transformation (Magnum's ``Matrix3``): columns are the 2D basis
    vectors and the translation. ``Matrix3.rotation(angle)`` turns counterclockwise."""

    __slots__ = ()
    translation = _TranslationAccessor()
    rotation = _DualRotation2D()

    @classmethod
    def from_(cls, rotation_scaling: Any, translation: Any) -> Matrix3:
        """Build from a 2x2 rotation (and scaling) part and a 2D translation."""
        matrix = np.eye(3)
        matrix[:2, :2] = np.asarray(rotation_scaling, dtype=np.float64)
        matrix[:2, 2] = finite_array(translation, 2, "translation")
        return cls(matrix)

    @classmethod
    def _translation_matrix(cls, vector: Any) -> Matrix3:
        return cls.from_(np.eye(2), vector)

    @classmethod
    def scaling(cls, vector: Any) -> Matrix3:
        return cls.from_(np.diag(finite_array(vector, 2, "scaling")), (0.0, 0.0))

    @classmethod
    def _rotation_matrix(cls, angle: Any) -> Matrix3:
        c, s = math.cos(radians(angle)), math.sin(radians(angle))
        return cls.from_([[c, -s], [s, c]], (0.0, 0.0))

    def rotation_scaling(self) -> np.ndarray:
        """The 2x2 upper-left block (rotation and scaling)."""
        return self._data[:2, :2].copy()

    def transform_point(self, point: Any) -> Vector2:
        """``M (p, 1)`` in 2D."""
        return Vector2(self._data[:2, :2] @ finite_array(point, 2, "point") + self._data[:2, 2])

    def transform_vector(self, vector: Any) -> Vector2:
        """``M (v, 0)`` in 2D: no translation."""
        return Vector2(self._data[:2, :2] @ finite_array(vector, 2, "vector"))

    def inverted_rigid(self) -> Matrix3:
        """Inverse of a rotation + translation: ``[R^T, -R^T t]``."""
        rotation = self._data[:2, :2]
        return Matrix3.from_(rotation.T, -rotation.T @ self._data[:2, 2])


class _DualRotation:
    """``Matrix4.rotation(angle, axis)`` on the class, ``m.rotation()`` on an instance."""

    def __get__(self, instance: Matrix4 | None, owner: type[Matrix4]) -> Any:
        if instance is None:
            return lambda angle, axis: owner.from_(axis_angle_matrix(angle, axis), (0.0, 0.0, 0.0))
        return instance.rotation_normalized


class Matrix4(_MatrixN):
    """A 4x4 homogeneous transformation (Magnum's ``Matrix4``); columns are basis vectors."""

    _size = 4
    __slots__ = ()
    translation = _TranslationAccessor()
    rotation = _DualRotation()

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

    @classmethod
    def rotation_x(cls, angle: Any) -> Matrix4:
        """Rotation by ``angle`` about +X (Magnum's ``Matrix4.rotation_x``)."""
        return cls.from_(axis_angle_matrix(angle, (1.0, 0.0, 0.0)), (0.0, 0.0, 0.0))

    @classmethod
    def rotation_y(cls, angle: Any) -> Matrix4:
        """Rotation by ``angle`` about +Y."""
        return cls.from_(axis_angle_matrix(angle, (0.0, 1.0, 0.0)), (0.0, 0.0, 0.0))

    @classmethod
    def rotation_z(cls, angle: Any) -> Matrix4:
        """Rotation by ``angle`` about +Z."""
        return cls.from_(axis_angle_matrix(angle, (0.0, 0.0, 1.0)), (0.0, 0.0, 0.0))

    @classmethod
    def look_at(cls, eye: Any, target: Any, up: Any) -> Matrix4:
        """A camera (or object) pose at ``eye`` whose -Z axis points at ``target``.

        Columns (Magnum's ``lookAt``): ``backward = |eye - target|``,
        ``right = |up x backward|``, ``real_up = backward x right``, translation ``eye``.
        ValueError when ``eye == target`` or ``up`` is parallel to the view direction.
        """
        eye_v = finite_array(eye, 3, "eye")
        backward = eye_v - finite_array(target, 3, "target")
        right = np.cross(finite_array(up, 3, "up"), backward)
        if np.linalg.norm(backward) < 1e-12 or np.linalg.norm(right) < 1e-12:
            raise ValueError(
                f"look_at needs eye != target and up not parallel to the view direction, got "
                f"eye={eye!r}, target={target!r}, up={up!r}"
            )
        backward = backward / np.linalg.norm(backward)
        right = right / np.linalg.norm(right)
        return cls.from_(np.column_stack([right, np.cross(backward, right), backward]), eye_v)

    @property
    def right(self) -> Vector3:
        """The first column (local +X in the parent frame)."""
        return Vector3(self._data[:3, 0])

    @property
    def up(self) -> Vector3:
        """The second column (local +Y)."""
        return Vector3(self._data[:3, 1])

    @property
    def backward(self) -> Vector3:
        """The third column (local +Z; a camera looks down -backward)."""
        return Vector3(self._data[:3, 2])

    def rotation_scaling(self) -> Matrix3x3:
        return Matrix3x3(self._data[:3, :3])

    def rotation_normalized(self) -> Matrix3x3:
        """The rotation part with scaling divided out (columns normalized)."""
        block = self._data[:3, :3]
        return Matrix3x3(block / np.linalg.norm(block, axis=0))

    def transform_point(self, point: Any) -> Vector3:
        """``M (p, 1)``: rotation, scaling and translation, divided by the resulting ``w``
        (Magnum's rule: a projection matrix gives normalized device coordinates)."""
        moved = self._data[:3, :3] @ np.asarray(point, dtype=np.float64) + self._data[:3, 3]
        w = float(self._data[3, :3] @ np.asarray(point, dtype=np.float64) + self._data[3, 3])
        return Vector3(moved if w == 1.0 else moved / w)

    def transform_vector(self, vector: Any) -> Vector3:
        """``M (v, 0)``: rotation and scaling, no translation."""
        return Vector3(self._data[:3, :3] @ np.asarray(vector, dtype=np.float64))

    def inverted_rigid(self) -> Matrix4:
        """Inverse of a rotation + translation matrix: ``[R^T, -R^T t]``."""
        rotation = self._data[:3, :3]
        return Matrix4.from_(rotation.T, -rotation.T @ self._data[:3, 3])


def quaternion_to_matrix(xyzw: np.ndarray) -> np.ndarray:
    """3x3 rotation matrix of a unit ``[x, y, z, w]`` quaternion (see the module docstring)."""
    # as Python floats: the same double arithmetic as NumPy scalars, without a NumPy
    # operation per term (scene nodes build their matrices through here on every step)
    x, y, z, w = np.asarray(xyzw, dtype=np.float64).tolist()
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
    return quaternion_to_matrix(
        np.append(axis_array / axis_length * math.sin(half), math.cos(half))
    )


def rotation_and_scaling(
    value: Any, min_scaling: float, orthogonality_tolerance: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Split a 4x4 transformation into ``(rotation 3x3, scaling (3,), translation (3,))``.

    ``M[:3, :3] = R diag(s)``: ``s`` are the column lengths, ``R = M[:3, :3] / s``. Refuses
    with a ValueError what is not a scaled rotation plus translation: a non-finite or
    non-4x4 value, a column shorter than ``min_scaling``, a reflection (``det R < 0``) or a
    shear (``|R^T R - I|`` above ``orthogonality_tolerance`` in some entry).
    """
    try:
        matrix = np.asarray(value, dtype=np.float64) if not isinstance(value, str) else None
    except (TypeError, ValueError):
        matrix = None
    if matrix is None or matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
        raise ValueError(f"transformation must be a finite 4x4 matrix, got {value!r}")
    scaling = stable_norm(matrix[:3, :3], axis=0)
    if np.any(scaling < min_scaling) or not np.all(np.isfinite(scaling)):
        raise ValueError(
            f"transformation has a degenerate rotation part (a column shorter than "
            f"{min_scaling}): {value!r}"
        )
    rotation = matrix[:3, :3] / scaling
    if np.linalg.det(rotation) < 0.0:
        raise ValueError(f"transformation is a reflection (negative determinant): {value!r}")
    if not np.allclose(rotation.T @ rotation, np.eye(3), atol=orthogonality_tolerance):
        raise ValueError(f"transformation has a shear (its axes are not orthogonal): {value!r}")
    return rotation, scaling, matrix[:3, 3].copy()
