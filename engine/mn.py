"""A small Magnum-like math module: the types Habitat tutorials use via ``import magnum as mn``.

rigidsim code writes ``from engine import mn`` and then uses the same names as Magnum's Python
bindings: :class:`Vector3`, :class:`Quaternion`, :class:`Deg`, :class:`Rad`, :class:`Matrix4`,
:class:`Range3D`. The types are thin wrappers around NumPy arrays so that they mix freely with
lists and ``np.ndarray`` (``Vector3 + [1, 2, 3]``, ``np.asarray(v)``).

Conventions (declared once, used everywhere in rigidsim)
-------------------------------------------------------
* Right handed, Y up, -Z forward; meters, radians inside.
* A quaternion is stored as a ``(4,)`` float64 array in the order ``[x, y, z, w]`` (scalar last,
  like Magnum's ``Quaternion((x, y, z), w)`` and SciPy). Conversion from other orders
  (numpy-quaternion's ``(w, x, y, z)``, JSON's ``[w, x, y, z]``) happens only at the API boundary,
  in :func:`to_quaternion` and the template loaders.
* Rotating a vector: ``v' = q v q*``; the matrix of ``q`` is the usual
  ``R = (w^2 - |u|^2) I + 2 u u^T + 2 w [u]x`` with ``u = (x, y, z)``.

Magnum quirks kept on purpose: ``Vector3.dot()`` with no argument is the **squared** length, and
``Matrix4.translation`` is both a static constructor (``Matrix4.translation(v)``) and, on an
instance, the translation part (``m.translation``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

__all__ = [
    "Deg",
    "Matrix3x3",
    "Matrix4",
    "Quaternion",
    "Rad",
    "Range3D",
    "Vector2",
    "Vector3",
    "to_quaternion",
    "to_vector3",
]


# --------------------------------------------------------------------------------------------
# Angles
# --------------------------------------------------------------------------------------------
class Rad(float):
    """An angle in radians. ``Rad(Deg(180))`` converts; ``float(Rad(x)) == x``."""

    def __new__(cls, value: Any = 0.0) -> Rad:
        if isinstance(value, Deg):
            return super().__new__(cls, math.radians(float(value)))
        return super().__new__(cls, float(value))

    def __repr__(self) -> str:
        return f"Rad({float(self)!r})"


class Deg(float):
    """An angle in degrees. ``Deg(Rad(math.pi)) == 180``."""

    def __new__(cls, value: Any = 0.0) -> Deg:
        if isinstance(value, Rad):
            return super().__new__(cls, math.degrees(float(value)))
        return super().__new__(cls, float(value))

    def __repr__(self) -> str:
        return f"Deg({float(self)!r})"


def _radians(angle: Any) -> float:
    """An angle given as :class:`Deg`, :class:`Rad` or a plain number (read as radians)."""
    if isinstance(angle, Deg):
        return math.radians(float(angle))
    value = float(angle)
    if not math.isfinite(value):
        raise ValueError(f"angle must be finite, got {angle!r}")
    return value


# --------------------------------------------------------------------------------------------
# Validation helpers used at every API boundary
# --------------------------------------------------------------------------------------------
def _finite_array(value: Any, length: int, name: str) -> np.ndarray:
    """``value`` as a finite float64 array of shape ``(length,)``, else a ValueError naming it."""
    if value is None:
        raise ValueError(f"{name} must be a {length}-vector, got None")
    if isinstance(value, str | bytes):
        raise ValueError(f"{name} must be a {length}-vector of numbers, got {value!r}")
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a {length}-vector of numbers, got {value!r}") from error
    if array.shape != (length,):
        raise ValueError(f"{name} must have shape ({length},), got shape {array.shape}: {value!r}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite, got {array.tolist()}")
    return array


def to_vector3(value: Any, name: str = "value") -> Vector3:
    """Convert a list, tuple, ndarray or :class:`Vector3` to a finite :class:`Vector3`.

    Raises ``ValueError`` naming ``name`` for None, NaN, inf, strings or a wrong shape.
    """
    return Vector3(_finite_array(value, 3, name))


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
        xyzw = _finite_array(value, 4, name)
    xyzw = _finite_array(xyzw, 4, name)
    norm = float(np.linalg.norm(xyzw))
    if norm < 1e-12:
        raise ValueError(f"{name} must be a non-zero quaternion, got {xyzw.tolist()}")
    return Quaternion.from_xyzw(xyzw / norm)


# --------------------------------------------------------------------------------------------
# Vectors
# --------------------------------------------------------------------------------------------
class _VectorN:
    """Shared arithmetic of :class:`Vector2` and :class:`Vector3` (a wrapped float64 array)."""

    _size = 3
    __slots__ = ("_data",)
    __array_priority__ = 20.0  # so ndarray + Vector3 defers to Vector3.__radd__

    def __init__(self, *values: Any) -> None:
        if len(values) == 0:
            data = np.zeros(self._size)
        elif len(values) == 1:
            if np.isscalar(values[0]):
                data = np.full(self._size, float(values[0]))
            else:
                data = np.array(values[0], dtype=np.float64).reshape(-1)
        else:
            data = np.array(values, dtype=np.float64)
        if data.shape != (self._size,):
            raise ValueError(f"{type(self).__name__} needs {self._size} components, got {values!r}")
        self._data = data

    # -- array protocol and sequence behaviour -------------------------------------------------
    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self._data.astype(dtype) if dtype is not None else self._data.copy()

    def __len__(self) -> int:
        return self._size

    def __iter__(self):
        return iter(self._data.tolist())

    def __getitem__(self, index: int) -> float:
        return float(self._data[index])

    def __setitem__(self, index: int, value: float) -> None:
        self._data[index] = float(value)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(f'{c:g}' for c in self._data)})"

    def __eq__(self, other: object) -> bool:
        try:
            return bool(np.array_equal(self._data, np.asarray(other, dtype=np.float64)))
        except (TypeError, ValueError):
            return False

    def __hash__(self) -> int:
        return hash(tuple(self._data.tolist()))

    def _wrap(self, data: np.ndarray) -> Any:
        return type(self)(data)

    # -- arithmetic with scalars, lists and arrays --------------------------------------------
    def __add__(self, other: Any) -> Any:
        return self._wrap(self._data + np.asarray(other, dtype=np.float64))

    __radd__ = __add__

    def __sub__(self, other: Any) -> Any:
        return self._wrap(self._data - np.asarray(other, dtype=np.float64))

    def __rsub__(self, other: Any) -> Any:
        return self._wrap(np.asarray(other, dtype=np.float64) - self._data)

    def __mul__(self, other: Any) -> Any:
        return self._wrap(self._data * np.asarray(other, dtype=np.float64))

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> Any:
        return self._wrap(self._data / np.asarray(other, dtype=np.float64))

    def __neg__(self) -> Any:
        return self._wrap(-self._data)

    # -- Magnum's vector API ---------------------------------------------------------------------
    def dot(self, other: Any = None) -> float:
        """Dot product; with no argument the **squared length** (Magnum's quirk)."""
        if other is None:
            return float(self._data @ self._data)
        return float(self._data @ np.asarray(other, dtype=np.float64))

    def length(self) -> float:
        return float(np.linalg.norm(self._data))

    def normalized(self) -> Any:
        length = self.length()
        if length == 0.0:
            raise ValueError("cannot normalize a zero-length vector")
        return self._wrap(self._data / length)

    def is_normalized(self) -> bool:
        return abs(self.dot() - 1.0) < 1e-6

    @property
    def x(self) -> float:
        return float(self._data[0])

    @x.setter
    def x(self, value: float) -> None:
        self._data[0] = float(value)

    @property
    def y(self) -> float:
        return float(self._data[1])

    @y.setter
    def y(self, value: float) -> None:
        self._data[1] = float(value)


class Vector2(_VectorN):
    """A 2-component float vector (Magnum's ``Vector2``)."""

    _size = 2
    __slots__ = ()


class Vector3(_VectorN):
    """A 3-component float vector (Magnum's ``Vector3``), mixing freely with lists and ndarrays."""

    _size = 3
    __slots__ = ()

    @property
    def z(self) -> float:
        return float(self._data[2])

    @z.setter
    def z(self, value: float) -> None:
        self._data[2] = float(value)

    def cross(self, other: Any) -> Vector3:
        return Vector3(np.cross(self._data, np.asarray(other, dtype=np.float64)))

    @staticmethod
    def zero_init() -> Vector3:
        return Vector3(0.0, 0.0, 0.0)

    @staticmethod
    def x_axis(length: float = 1.0) -> Vector3:
        return Vector3(length, 0.0, 0.0)

    @staticmethod
    def y_axis(length: float = 1.0) -> Vector3:
        return Vector3(0.0, length, 0.0)

    @staticmethod
    def z_axis(length: float = 1.0) -> Vector3:
        return Vector3(0.0, 0.0, length)


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
    q = np.array(q)
    return q / np.linalg.norm(q)


class Quaternion:
    """A rotation quaternion, Magnum style: ``Quaternion((x, y, z), w)``; identity by default."""

    __slots__ = ("_xyzw",)

    def __init__(self, vector: Iterable[float] = (0.0, 0.0, 0.0), scalar: float = 1.0) -> None:
        xyz = np.array(vector, dtype=np.float64).reshape(-1)
        if xyz.shape != (3,):
            raise ValueError(f"Quaternion vector part needs 3 components, got {vector!r}")
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
    def rotation(cls, angle: Any, axis: Any) -> Quaternion:
        """Rotation by ``angle`` (:class:`Deg` or :class:`Rad`) about ``axis`` (normalized here)."""
        axis_array = _finite_array(axis, 3, "axis")
        axis_length = np.linalg.norm(axis_array)
        if axis_length < 1e-12:
            raise ValueError(f"rotation axis must be non-zero, got {axis_array.tolist()}")
        half = 0.5 * _radians(angle)
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

    @property
    def scalar(self) -> float:
        return float(self._xyzw[3])

    @property
    def xyzw(self) -> np.ndarray:
        """A copy as ``[x, y, z, w]`` (rigidsim's internal order)."""
        return self._xyzw.copy()

    def __repr__(self) -> str:
        x, y, z, w = self._xyzw
        return f"Quaternion(({x:g}, {y:g}, {z:g}), {w:g})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Quaternion) and bool(np.array_equal(self._xyzw, other._xyzw))

    def __hash__(self) -> int:
        return hash(tuple(self._xyzw.tolist()))

    # -- algebra --------------------------------------------------------------------------------
    def __mul__(self, other: Any) -> Quaternion:
        if isinstance(other, Quaternion):
            return Quaternion.from_xyzw(quaternion_multiply(self._xyzw, other._xyzw))
        return Quaternion.from_xyzw(self._xyzw * float(other))

    __rmul__ = __mul__

    def __add__(self, other: Quaternion) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw + other._xyzw)

    def __neg__(self) -> Quaternion:
        return Quaternion.from_xyzw(-self._xyzw)

    def dot(self, other: Quaternion | None = None) -> float:
        """Dot product; with no argument the squared length (as :meth:`Vector3.dot`)."""
        other_xyzw = self._xyzw if other is None else other._xyzw
        return float(self._xyzw @ other_xyzw)

    def length(self) -> float:
        return float(np.linalg.norm(self._xyzw))

    def is_normalized(self) -> bool:
        return abs(self.dot() - 1.0) < 1e-6

    def normalized(self) -> Quaternion:
        return Quaternion.from_xyzw(self._xyzw / self.length())

    def conjugated(self) -> Quaternion:
        x, y, z, w = self._xyzw
        return Quaternion.from_xyzw([-x, -y, -z, w])

    def inverted(self) -> Quaternion:
        """``q^-1 = q* / |q|^2``."""
        return Quaternion.from_xyzw(self.conjugated()._xyzw / self.dot())

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
        matrix[:3, 3] = _finite_array(translation, 3, "translation")
        return cls(matrix)

    @classmethod
    def _translation_matrix(cls, vector: Any) -> Matrix4:
        return cls.from_(np.eye(3), vector)

    @classmethod
    def scaling(cls, vector: Any) -> Matrix4:
        return cls.from_(np.diag(_finite_array(vector, 3, "scaling")), (0.0, 0.0, 0.0))

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


class _DualRotation:
    """``Matrix4.rotation(angle, axis)`` on the class, ``m.rotation()`` on an instance."""

    def __get__(self, instance: Matrix4 | None, owner: type) -> Any:
        if instance is None:
            return lambda angle, axis: owner.from_(
                Quaternion.rotation(angle, axis).to_matrix(), (0.0, 0.0, 0.0)
            )
        return instance.rotation_normalized


Matrix4.rotation = _DualRotation()


# --------------------------------------------------------------------------------------------
# Axis-aligned boxes
# --------------------------------------------------------------------------------------------
class Range3D:
    """An axis-aligned box ``[min, max]`` (Magnum's ``Range3D``), e.g. an object's AABB."""

    __slots__ = ("_min", "_max")

    def __init__(self, min: Any = (0.0, 0.0, 0.0), max: Any = (0.0, 0.0, 0.0)) -> None:  # noqa: A002
        self._min = _finite_array(min, 3, "min")
        self._max = _finite_array(max, 3, "max")

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
