"""Angles, vectors and input validation of :mod:`engine.mn` (Magnum's ``Deg``, ``Rad``,
``Vector2``, ``Vector3``).

``Vector3`` wraps a ``(3,)`` float64 array and mixes freely with lists and ndarrays
(``Vector3 + [1, 2, 3]``, ``np.asarray(v)``); ``dot()`` with no argument is the **squared**
length, as in Magnum. ``to_vector3`` is the one validator every public setter uses: NaN, inf,
None, strings and wrong shapes raise a ``ValueError`` naming the parameter.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["Deg", "Rad", "Vector2", "Vector3", "finite_array", "radians", "to_vector3"]


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
    return Vector3(finite_array(value, 3, name))



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

