"""Rotations of :mod:`engine.mn`: Magnum's ``Quaternion`` and the quaternion formulas.

Stored as a ``(4,)`` float64 array ``[x, y, z, w]`` (scalar last). Rotating a vector:
``v' = q v q*``; the matrix of a unit ``q`` is ``R = (w^2 - |u|^2) I + 2 u u^T + 2 w [u]x``
with ``u = (x, y, z)``. ``to_quaternion`` converts every accepted input (a ``Quaternion``,
numpy-quaternion-like objects with ``w, x, y, z`` attributes, ``[x, y, z, w]`` lists).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from engine.mn.matrices import Matrix3x3, quaternion_to_matrix
from engine.mn.vectors import (
    FLOAT_EPSILON,
    Rad,
    Vector3,
    finite_array,
    fuzzy_equal,
    is_scalar,
    radians,
    real_components,
    stable_norm,
)

__all__ = [
    "Quaternion",
    "matrix_to_quaternion",
    "quaternion_multiply",
    "quaternion_to_matrix",
    "to_quaternion",
]


def to_quaternion(value: Any, name: str = "rotation") -> Quaternion:
    """Convert any quaternion-like value to a unit :class:`Quaternion`.

    Accepted: a :class:`Quaternion`; a numpy-quaternion-like object with attributes
    ``w, x, y, z`` (``np.quaternion(w, x, y, z)``); a 4-sequence read as ``[x, y, z, w]``
    (Habitat's "coeffs" order). A zero, non-finite or wrongly shaped value raises ValueError.
    """
    if isinstance(value, Quaternion):
        xyzw = value.xyzw
    elif all(hasattr(value, attr) for attr in ("w", "x", "y", "z")):
        xyzw = np.array([value.x, value.y, value.z, value.w], dtype=np.float64)
    else:
        xyzw = finite_array(value, 4, name)
    xyzw = finite_array(xyzw, 4, name)
    norm = float(stable_norm(xyzw))  # no overflow for huge components ([1e300, 1e300, 0, 0])
    if norm < 1e-12:
        raise ValueError(f"{name} must be a non-zero quaternion, got {xyzw.tolist()}")
    return Quaternion.from_xyzw(xyzw / norm)


# --------------------------------------------------------------------------------------------
# Quaternions
# --------------------------------------------------------------------------------------------
def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product ``a * b`` of two ``[x, y, z, w]`` arrays (``a`` applied after ``b``)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    )


def matrix_to_quaternion(matrix: np.ndarray) -> np.ndarray:
    """``[x, y, z, w]`` of a 3x3 rotation matrix (Shepperd's method, stable for every angle)."""
    m = np.asarray(matrix, dtype=np.float64)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4]
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = [s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s]
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = [(m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = [(m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4, (m[1, 0] - m[0, 1]) / s]
    xyzw = np.array(q)
    return xyzw / np.linalg.norm(xyzw)


def _is_vector_scalar_pair(value: Any) -> bool:
    """True for a ``((x, y, z), w)`` pair (a 2-sequence whose first item has 3 numbers)."""
    if isinstance(value, str | bytes | np.ndarray) or not hasattr(value, "__len__"):
        return False
    return len(value) == 2 and hasattr(value[0], "__len__") and len(value[0]) == 3


class Quaternion:
    """A quaternion, Magnum style. Constructors, as in Magnum's Python bindings:

    * ``Quaternion()``: the identity ``((0, 0, 0), 1)``;
    * ``Quaternion(vector, scalar)``: e.g. ``Quaternion(mn.Vector3(0, 1, 0), 0)``;
    * ``Quaternion(((x, y, z), w))``: one ``(vector, scalar)`` tuple;
    * ``Quaternion(vector)``: a pure quaternion ``(vector, 0)`` (scalar zero, as Magnum).

    ``==`` is Magnum's fuzzy compare of the four components (see :mod:`engine.mn.vectors`);
    ``q`` and ``-q`` are the same rotation but not equal quaternions, as in Magnum.
    """

    __slots__ = ("_xyzw",)

    def __init__(self, *args: Any) -> None:
        if len(args) == 0:
            vector, scalar = (0.0, 0.0, 0.0), 1.0
        elif len(args) == 2:
            vector, scalar = args
        elif len(args) == 1 and _is_vector_scalar_pair(args[0]):
            vector, scalar = args[0]
        elif len(args) == 1:
            vector, scalar = args[0], 0.0
        else:
            raise TypeError(
                f"Quaternion takes (), (vector, scalar), ((x, y, z), w) or "
                f"(vector), got {len(args)} arguments"
            )
        if not real_components((vector, scalar)):
            raise TypeError(
                f"Quaternion takes real numbers (no strings, bools or complex numbers), "
                f"got ({vector!r}, {scalar!r})"
            )
        xyz = np.array(vector, dtype=np.float64).reshape(-1)
        if xyz.shape != (3,):
            raise ValueError(f"Quaternion vector part needs 3 components, got {vector!r}")
        if isinstance(scalar, bool) or not is_scalar(scalar):
            raise TypeError(f"Quaternion scalar part must be a number, got {scalar!r}")
        self._xyzw = np.append(xyz, float(scalar))

    # -- constructors ---------------------------------------------------------------------------
    @classmethod
    def from_xyzw(cls, xyzw: Iterable[float]) -> Quaternion:
        """From an ``[x, y, z, w]`` array (rigidsim's internal order)."""
        q = cls.__new__(cls)
        q._xyzw = np.array(xyzw, dtype=np.float64).reshape(4)
        return q

    @classmethod
    def identity_init(cls) -> Quaternion:
        return cls()

    @classmethod
    def zero_init(cls) -> Quaternion:
        return cls.from_xyzw(np.zeros(4))

    @classmethod
    def rotation(cls, angle: Any, axis: Any) -> Quaternion:
        """Rotation by ``angle`` (:class:`Deg` or :class:`Rad`) about ``axis`` (normalized here)."""
        axis_array = finite_array(axis, 3, "axis")
        axis_length = np.linalg.norm(axis_array)
        if axis_length < 1e-12:
            raise ValueError(f"rotation axis must be non-zero, got {axis_array.tolist()}")
        half = 0.5 * radians(angle)
        return cls(axis_array / axis_length * math.sin(half), math.cos(half))

    @classmethod
    def from_matrix(cls, matrix: Any) -> Quaternion:
        """From a 3x3 rotation matrix (the rotation part of a 4x4 is accepted too)."""
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape == (4, 4):
            m = m[:3, :3]
        if m.shape != (3, 3):
            raise ValueError(f"from_matrix needs a 3x3 matrix, got shape {m.shape}")
        return cls.from_xyzw(matrix_to_quaternion(m))

    # -- accessors ------------------------------------------------------------------------------
    @property
    def vector(self) -> Vector3:
        return Vector3(self._xyzw[:3])

    @vector.setter
    def vector(self, value: Any) -> None:
        self._xyzw[:3] = finite_array(value, 3, "vector")

    @property
    def scalar(self) -> float:
        return float(self._xyzw[3])

    @scalar.setter
    def scalar(self, value: Any) -> None:
        self._xyzw[3] = float(value)

    @property
    def xyzw(self) -> np.ndarray:
        """A copy as ``[x, y, z, w]`` (rigidsim's internal order)."""
        return self._xyzw.copy()

    def __repr__(self) -> str:
        x, y, z, w = self._xyzw
        return f"Quaternion(({x:g}, {y:g}, {z:g}), {w:g})"

    def __eq__(self, other: object) -> bool:
        """Magnum's fuzzy compare of vector and scalar parts (relative epsilon 1e-5)."""
        return isinstance(other, Quaternion) and fuzzy_equal(self._xyzw, other._xyzw)

    # No __hash__: fuzzy equality has no consistent hash (as Magnum's Python type); a class
    # that defines __eq__ and no __hash__ gets ``__hash__ = None`` from Python.

    # -- algebra --------------------------------------------------------------------------------
    def __mul__(self, other: Any) -> Quaternion:
        if isinstance(other, Quaternion):
            return Quaternion.from_xyzw(quaternion_multiply(self._xyzw, other._xyzw))
        return Quaternion.from_xyzw(self._xyzw * float(other))

    __rmul__ = __mul__

    def __add__(self, other: Quaternion) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw + other._xyzw)

    def __sub__(self, other: Quaternion) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw - other._xyzw)

    def __truediv__(self, other: float) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw / float(other))

    def __neg__(self) -> Quaternion:
        return Quaternion.from_xyzw(-self._xyzw)

    def dot(self, other: Quaternion | None = None) -> float:
        """Dot product; with no argument the squared length (as :meth:`Vector3.dot`)."""
        other_xyzw = self._xyzw if other is None else other._xyzw
        return float(self._xyzw @ other_xyzw)

    def length(self) -> float:
        return float(np.linalg.norm(self._xyzw))

    def is_normalized(self) -> bool:
        """Magnum: ``|dot() - 1| < 2 epsilon``."""
        return abs(self.dot() - 1.0) < 2.0 * FLOAT_EPSILON

    def normalized(self) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw / self.length())

    def conjugated(self) -> Quaternion:
        x, y, z, w = self._xyzw
        return Quaternion.from_xyzw([-x, -y, -z, w])

    def inverted(self) -> Quaternion:
        """``q^-1 = q* / |q|^2``."""
        return Quaternion.from_xyzw(self.conjugated()._xyzw / self.dot())

    def inverted_normalized(self) -> Quaternion:
        """Inverse of a unit quaternion: its conjugate."""
        return self.conjugated()

    def angle(self) -> Rad:
        """Rotation angle in [0, 2 pi] of a unit quaternion: ``2 acos(w)``."""
        return Rad(2.0 * math.acos(max(-1.0, min(1.0, self.scalar))))

    def axis(self) -> Vector3:
        """Rotation axis of a unit quaternion (NaN for the identity, like Magnum)."""
        sin_half = math.sqrt(max(0.0, 1.0 - self.scalar**2))
        if sin_half < 1e-12:
            return Vector3(np.full(3, np.nan))
        return Vector3(self._xyzw[:3] / sin_half)

    def to_matrix(self) -> Matrix3x3:
        return Matrix3x3(quaternion_to_matrix(self._xyzw))

    def transform_vector(self, vector: Any) -> Vector3:
        """Rotate ``vector`` by this quaternion: ``q v q^-1``."""
        return Vector3(quaternion_to_matrix(self._xyzw) @ np.asarray(vector, dtype=np.float64))

    transform_vector_normalized = transform_vector
