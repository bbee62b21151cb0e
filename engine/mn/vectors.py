"""Angles, vectors and input validation of :mod:`engine.mn` (Magnum's ``Deg``, ``Rad``,
``Vector2``, ``Vector3``).

``Vector3`` wraps a ``(3,)`` float64 array and mixes freely with lists and ndarrays
(``Vector3 + [1, 2, 3]``, ``np.asarray(v)``); ``dot()`` with no argument is the **squared**
length, as in Magnum. ``to_vector3`` is the one validator every public setter uses: NaN, inf,
None, strings (numeric ones too), bools, complex numbers and wrong shapes raise a
``ValueError`` naming the parameter.

Equality is Magnum's fuzzy compare (``TypeTraits<Float>::equals``), component by component,
with the float epsilon ``e = 1e-5``::

    a == b  <=>  a, b bitwise equal
                 or |a - b| < e                    when a or b is 0 or |a - b| < e
                 or |a - b| / (|a| + |b|) < e      otherwise (relative error)

so ``Vector3(1, 2, 3) == Vector3(1, 2, 3 + 1e-6)`` is True, as in Magnum. Integer vectors
(``Vector2i``, ``Vector3i``) compare exactly. Like Magnum's Python types, vectors are not
hashable (a fuzzy ``==`` cannot have a consistent hash).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "DOUBLE_EPSILON",
    "FLOAT_EPSILON",
    "Deg",
    "Rad",
    "Vector2",
    "Vector2i",
    "Vector3",
    "Vector3d",
    "Vector3i",
    "Vector4",
    "finite_array",
    "fuzzy_equal",
    "is_scalar",
    "radians",
    "real_components",
    "to_vector3",
]

#: Magnum's ``TypeTraits<Float>::epsilon()``: the fuzzy-compare tolerance of float types.
FLOAT_EPSILON = 1.0e-5
#: Magnum's ``TypeTraits<Double>::epsilon()``: the tolerance of double types (``Vector3d``).
DOUBLE_EPSILON = 1.0e-14


def fuzzy_equal(a: Any, b: Any, epsilon: float = FLOAT_EPSILON) -> bool:
    """Magnum's fuzzy compare of two arrays of equal shape, element by element (see the
    module docstring): absolute near zero, relative to ``|a| + |b|`` elsewhere."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        return False
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        difference = np.abs(a - b)
        near_zero = (a == 0.0) | (b == 0.0) | (difference < epsilon)
        relative = difference / (np.abs(a) + np.abs(b))
        equal = (a == b) | np.where(near_zero, difference < epsilon, relative < epsilon)
    return bool(np.all(equal))


def is_scalar(value: object) -> bool:
    """``np.isscalar`` as a plain bool: True for a number (or str/bytes), False for arrays
    and sequences. (numpy's stub declares ``isscalar`` a TypeGuard that would narrow the
    caller's value to numpy's scalar union, which ``float()`` does not accept.)"""
    return bool(np.isscalar(value))


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


def radians(angle: Any) -> float:
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
def finite_array(value: Any, length: int, name: str) -> np.ndarray:
    """``value`` as a finite float64 array of shape ``(length,)``, else a ValueError naming it."""
    if value is None:
        raise ValueError(f"{name} must be a {length}-vector, got None")
    if isinstance(value, str | bytes) or not real_components(value):
        raise ValueError(
            f"{name} must be a {length}-vector of real numbers (no strings, bools or "
            f"complex numbers), got {value!r}"
        )
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a {length}-vector of numbers, got {value!r}") from error
    if array.shape != (length,):
        raise ValueError(f"{name} must have shape ({length},), got shape {array.shape}: {value!r}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be finite, got {array.tolist()}")
    return array


def real_components(value: Any) -> bool:
    """False when ``value`` holds a string, a bool or a complex number anywhere (numpy
    would read ``"1"`` as 1.0 and ``True`` as 1.0, and drop an imaginary part with only a
    warning); nested lists and tuples are looked into, arrays by their dtype."""
    if isinstance(value, list | tuple):
        return all(real_components(item) for item in value)
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "O":
            return all(real_components(item) for item in value.ravel().tolist())
        return value.dtype.kind in "iuf"
    return not isinstance(value, str | bytes | bool | np.bool_ | complex | np.complexfloating)


def stable_norm(array: Any, axis: int = -1) -> np.ndarray:
    """Euclidean norm along ``axis`` that does not overflow: ``m |x / m|`` with
    ``m = max |x_i|``, so ``[1e200, 0, 0]`` has norm 1e200 (``sqrt(x . x)`` would give inf).
    Zero vectors have norm 0; non-finite input gives a non-finite norm."""
    values = np.asarray(array, dtype=np.float64)
    biggest = np.max(np.abs(values), axis=axis, keepdims=True)
    safe = np.where((biggest > 0.0) & np.isfinite(biggest), biggest, 1.0)
    norm = np.linalg.norm(values / safe, axis=axis, keepdims=True) * safe  # m |x / m|
    norm = np.where(np.isfinite(biggest), norm, biggest)
    return np.squeeze(norm, axis=axis)


def to_vector3(value: Any, name: str = "value") -> Vector3:
    """Convert a list, tuple, ndarray or :class:`Vector3` to a finite :class:`Vector3`.

    Raises ``ValueError`` naming ``name`` for None, NaN, inf, strings or a wrong shape.
    """
    return Vector3(finite_array(value, 3, name))


# --------------------------------------------------------------------------------------------
# Vectors
# --------------------------------------------------------------------------------------------
class _VectorN:
    """Shared arithmetic of :class:`Vector2` and :class:`Vector3` (a wrapped float64 array)."""

    _size = 3
    _epsilon = FLOAT_EPSILON  # the fuzzy-compare tolerance of ==
    __slots__ = ("_data",)
    __array_priority__ = 20.0  # so ndarray + Vector3 defers to Vector3.__radd__

    def __init__(self, *values: Any) -> None:
        if not real_components(values):
            raise TypeError(
                f"{type(self).__name__} takes real numbers (no strings, bools or complex "
                f"numbers), got {values!r}"
            )
        if len(values) == 0:
            data = np.zeros(self._size)
        elif len(values) == 1 and is_scalar(values[0]):
            data = np.full(self._size, float(values[0]))
        else:
            # components, one sequence, or a shorter vector plus components:
            # Vector3(Vector2(1, 2), 3), Vector4(Vector3(...), w), Color4(Color3(...), a)
            data = np.concatenate([np.asarray(v, dtype=np.float64).reshape(-1) for v in values])
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
        """Magnum's fuzzy ``==`` (module docstring); lists and ndarrays compare too."""
        if isinstance(other, str | bytes) or other is None:
            return False
        try:
            other_array = np.asarray(other, dtype=np.float64)
        except (TypeError, ValueError):
            return False
        if other_array.shape != self._data.shape:
            return False
        return fuzzy_equal(self._data, other_array, self._epsilon)

    # No __hash__: fuzzy equality has no consistent hash (Magnum's types are unhashable);
    # a class that defines __eq__ and no __hash__ gets ``__hash__ = None`` from Python.

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
        """Magnum: ``|dot() - 1| < 2 epsilon`` (the squared length within [1 - e, 1 + e]^2)."""
        return abs(self.dot() - 1.0) < 2.0 * FLOAT_EPSILON

    def is_zero(self) -> bool:
        return fuzzy_equal(self._data, np.zeros(self._size))

    def sum(self) -> float:
        return float(self._data.sum())

    def product(self) -> float:
        return float(self._data.prod())

    def min(self) -> float:
        return float(self._data.min())

    def max(self) -> float:
        return float(self._data.max())

    def flipped(self) -> Any:
        """Components in reverse order."""
        return self._wrap(self._data[::-1].copy())

    def projected(self, line: Any) -> Any:
        """Projection on ``line``: ``line (v . line) / |line|^2``."""
        direction = np.asarray(line, dtype=np.float64)
        return self._wrap(direction * (self._data @ direction) / (direction @ direction))

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

    def perpendicular(self) -> Vector2:
        """The vector turned by 90 degrees counterclockwise: ``(-y, x)``."""
        return Vector2(-self._data[1], self._data[0])

    @staticmethod
    def zero_init() -> Vector2:
        return Vector2(0.0, 0.0)

    @staticmethod
    def x_axis(length: float = 1.0) -> Vector2:
        return Vector2(length, 0.0)

    @staticmethod
    def y_axis(length: float = 1.0) -> Vector2:
        return Vector2(0.0, length)


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


class Vector3d(Vector3):
    """Magnum's double-precision ``Vector3d``. rigidsim's ``Vector3`` already holds float64, so
    the two differ only in ``==``: Magnum's double epsilon ``1e-14`` instead of ``1e-5``."""

    _epsilon = DOUBLE_EPSILON
    __slots__ = ()


class Vector4(Vector3):
    """A 4-component float vector (Magnum's ``Vector4``): ``Vector4(Vector3(...), w)``."""

    _size = 4
    __slots__ = ()

    def cross(self, other: Any) -> Vector3:  # pragma: no cover - Magnum has no 4D cross
        raise AttributeError("Vector4 has no cross product")

    @property
    def w(self) -> float:
        return float(self._data[3])

    @w.setter
    def w(self, value: float) -> None:
        self._data[3] = float(value)

    @property
    def xyz(self) -> Vector3:
        return Vector3(self._data[:3])

    @staticmethod
    def zero_init() -> Vector4:
        return Vector4(0.0, 0.0, 0.0, 0.0)


class _IntVectorN(_VectorN):
    """Integer vectors: exact ``==``; arithmetic truncates towards zero, as Magnum's
    integer vectors do (``Vector2i(3, 5) / 2 == Vector2i(1, 2)``)."""

    __slots__ = ()

    def __init__(self, *values: Any) -> None:
        super().__init__(*values)
        if (
            len(values) == 1 and isinstance(values[0], _VectorN) and np.all(np.isfinite(self._data))
        ):  # Magnum's explicit conversion of a float vector truncates towards zero
            self._data = np.trunc(self._data)
        if not np.all(np.isfinite(self._data)) or np.any(self._data != np.trunc(self._data)):
            raise ValueError(f"{type(self).__name__} needs integer components, got {values!r}")
        self._data = self._data.astype(np.int64)

    def __getitem__(self, index: int) -> int:
        return int(self._data[index])

    def __setitem__(self, index: int, value: float) -> None:
        self._data[index] = int(value)  # a float truncates towards zero

    def __iter__(self):
        return iter(self._data.tolist())

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(str(c) for c in self._data.tolist())})"

    def __eq__(self, other: object) -> bool:
        if isinstance(other, str | bytes) or other is None:
            return False
        try:
            return bool(np.array_equal(self._data, np.asarray(other, dtype=np.float64)))
        except (TypeError, ValueError):
            return False

    # No __hash__ (unhashable, as the float vectors): __eq__ alone sets it to None.

    def _wrap(self, data: np.ndarray) -> Any:
        return type(self)(np.trunc(data))

    def __truediv__(self, other: Any) -> Any:
        return self._wrap(self._data / np.asarray(other, dtype=np.float64))

    @property
    def x(self) -> int:
        return int(self._data[0])

    @x.setter
    def x(self, value: float) -> None:
        self._data[0] = float(value)  # stored in the int64 array: truncates towards zero

    @property
    def y(self) -> int:
        return int(self._data[1])

    @y.setter
    def y(self, value: float) -> None:
        self._data[1] = float(value)


class Vector2i(_IntVectorN):
    """A 2-component integer vector (Magnum's ``Vector2i``), e.g. an image size."""

    _size = 2
    __slots__ = ()


class Vector3i(_IntVectorN):
    """A 3-component integer vector (Magnum's ``Vector3i``)."""

    _size = 3
    __slots__ = ()

    z = property(lambda self: int(self._data[2]), lambda self, value: self.__setitem__(2, value))
