"""Axis-aligned boxes of :mod:`engine.mn`: Magnum's ``Range1D``, ``Range2D``, ``Range3D``.

A range is ``[min, max]`` per axis (an object's AABB, a scene's bounds). The accessors are
Magnum's Python ones: ``size()``, ``center()``, ``size_x()``..., ``center_x()``...,
``translated``, ``padded``, ``scaled`` (min and max multiplied), ``scaled_from_center`` (the
size multiplied about the center), ``contains``; the per-axis ranges ``x()``, ``y()``,
``z()`` (a :class:`Range1D`) and planes ``xy()``, ``yz()``, ``xz()`` (a :class:`Range2D`);
the sides ``left``/``right`` (x), ``bottom``/``top`` (y), ``back``/``front`` (z, front is +Z)
and the corners (``back_bottom_left`` is ``min``, ``front_top_right`` is ``max``).
``==`` is Magnum's fuzzy compare (:func:`engine.mn.vectors.fuzzy_equal`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine.mn.vectors import Vector2, Vector3, finite_array, fuzzy_equal

__all__ = ["Range1D", "Range2D", "Range3D"]


class _RangeN:
    """An axis-aligned box ``[min, max]`` in ``_size`` dimensions (Magnum's ``RangeND``)."""

    _size = 3
    _vector: Any = Vector3
    __slots__ = ("_min", "_max")

    def __init__(self, min: Any = None, max: Any = None) -> None:  # noqa: A002
        if max is None and _is_min_max_pair(min, self._size):
            min, max = min  # noqa: A001 - Magnum's Range3D((min, max))
        zero = np.zeros(self._size)
        self._min = finite_array(zero if min is None else min, self._size, "min")
        self._max = finite_array(zero if max is None else max, self._size, "max")

    def _wrap(self, array: np.ndarray) -> Any:
        """A value of this range's vector type (a float for :class:`Range1D`)."""
        return self._vector(array)

    @classmethod
    def from_points(cls, points: Any) -> Any:
        array = np.asarray(points, dtype=np.float64).reshape(-1, cls._size)
        return cls(array.min(axis=0), array.max(axis=0))

    @classmethod
    def from_size(cls, min: Any, size: Any) -> Any:  # noqa: A002
        low = finite_array(min, cls._size, "min")
        return cls(low, low + finite_array(size, cls._size, "size"))

    @classmethod
    def from_center(cls, center: Any, half_size: Any) -> Any:
        middle = finite_array(center, cls._size, "center")
        half = finite_array(half_size, cls._size, "half_size")
        return cls(middle - half, middle + half)

    @classmethod
    def zero_init(cls) -> Any:
        return cls()

    @property
    def min(self) -> Any:
        return self._wrap(self._min)

    @min.setter
    def min(self, value: Any) -> None:
        self._min = finite_array(value, self._size, "min")

    @property
    def max(self) -> Any:
        return self._wrap(self._max)

    @max.setter
    def max(self, value: Any) -> None:
        self._max = finite_array(value, self._size, "max")

    def size(self) -> Any:
        return self._wrap(self._max - self._min)

    def center(self) -> Any:
        return self._wrap(0.5 * (self._min + self._max))

    def translated(self, vector: Any) -> Any:
        offset = finite_array(vector, self._size, "vector")
        return type(self)(self._min + offset, self._max + offset)

    def padded(self, padding: Any) -> Any:
        pad = _per_axis(padding, self._size, "padding")
        return type(self)(self._min - pad, self._max + pad)

    def scaled(self, scaling: Any) -> Any:
        """``[min * s, max * s]`` (Magnum: scaled about the origin)."""
        factor = _per_axis(scaling, self._size, "scaling")
        return type(self)(self._min * factor, self._max * factor)

    def scaled_from_center(self, scaling: Any) -> Any:
        """The same center, the size multiplied by ``scaling``."""
        factor = _per_axis(scaling, self._size, "scaling")
        center, half = 0.5 * (self._min + self._max), 0.5 * (self._max - self._min)
        return type(self)(center - half * factor, center + half * factor)

    def contains(self, point: Any) -> bool:
        """True when ``point`` (or a whole range) lies inside (Magnum: min inclusive)."""
        if isinstance(point, _RangeN):
            return bool(np.all(point._min >= self._min) and np.all(point._max <= self._max))
        p = np.asarray(point, dtype=np.float64)
        return bool(np.all(p >= self._min) and np.all(p <= self._max))

    def __eq__(self, other: object) -> bool:
        return (
            type(other) is type(self)
            and fuzzy_equal(self._min, other._min)  # type: ignore[attr-defined]
            and fuzzy_equal(self._max, other._max)  # type: ignore[attr-defined]
        )

    # No __hash__ (fuzzy equality): __eq__ alone sets it to None.

    def __repr__(self) -> str:
        return f"{type(self).__name__}(min={self.min!r}, max={self.max!r})"


def _is_min_max_pair(value: Any, size: int) -> bool:
    """True for ``(min, max)`` given as one argument, each a ``size``-vector."""
    return (
        size > 1
        and isinstance(value, tuple | list)
        and len(value) == 2
        and all(np.shape(part) == (size,) for part in value)
    )


def _scalar(value: Any, name: str) -> float:
    """``value`` as a finite float, else a ValueError naming it."""
    try:
        number = float(np.asarray(value, dtype=np.float64).reshape(-1)[0])
    except (TypeError, ValueError, IndexError) as error:
        raise ValueError(f"{name} must be a number, got {value!r}") from error
    if np.size(value) != 1 or not np.isfinite(number):
        raise ValueError(f"{name} must be one finite number, got {value!r}")
    return number


def _per_axis(value: Any, size: int, name: str) -> np.ndarray:
    """A scalar or a ``size``-vector as a finite ``(size,)`` array (ValueError naming it)."""
    array = np.asarray(value, dtype=np.float64)
    if array.ndim == 0:
        array = np.full(size, float(array))
    return finite_array(array, size, name)


class Range1D(_RangeN):
    """An interval ``[min, max]`` (Magnum's ``Range1D``): ``min``, ``max``, ``size()`` and
    ``center()`` are floats."""

    _size = 1
    __slots__ = ()

    def __init__(self, min: Any = 0.0, max: Any = 0.0) -> None:  # noqa: A002
        if max is None and isinstance(min, tuple | list) and len(min) == 2:
            min, max = min  # noqa: A001 - Magnum's Range1D((min, max))
        super().__init__(np.reshape(_scalar(min, "min"), 1), np.reshape(_scalar(max, "max"), 1))

    def _wrap(self, array: np.ndarray) -> float:
        return float(np.asarray(array).reshape(-1)[0])


class _PlanarAccessors:
    """The x and y accessors shared by :class:`Range2D` and :class:`Range3D`."""

    __slots__ = ()
    _min: np.ndarray
    _max: np.ndarray

    left = property(lambda self: float(self._min[0]))
    right = property(lambda self: float(self._max[0]))
    bottom = property(lambda self: float(self._min[1]))
    top = property(lambda self: float(self._max[1]))

    def size_x(self) -> float:
        return float(self._max[0] - self._min[0])

    def size_y(self) -> float:
        return float(self._max[1] - self._min[1])

    def center_x(self) -> float:
        return float(0.5 * (self._min[0] + self._max[0]))

    def center_y(self) -> float:
        return float(0.5 * (self._min[1] + self._max[1]))

    def x(self) -> Range1D:
        return Range1D(self._min[0], self._max[0])

    def y(self) -> Range1D:
        return Range1D(self._min[1], self._max[1])


class Range2D(_PlanarAccessors, _RangeN):
    """A 2D axis-aligned rectangle (Magnum's ``Range2D``): ``left, right, bottom, top``."""

    _size = 2
    _vector = Vector2
    __slots__ = ()

    bottom_left = property(lambda self: Vector2(self._min))
    top_right = property(lambda self: Vector2(self._max))
    bottom_right = property(lambda self: Vector2(self._max[0], self._min[1]))
    top_left = property(lambda self: Vector2(self._min[0], self._max[1]))


class Range3D(_PlanarAccessors, _RangeN):
    """An axis-aligned box ``[min, max]`` (Magnum's ``Range3D``), e.g. an object's AABB."""

    _size = 3
    _vector = Vector3
    __slots__ = ()

    def _corner(self, right: bool, top: bool, front: bool) -> Vector3:
        """A corner: x from max if right, y from max if top, z from max if front (Magnum:
        "front" is +Z, "back" is -Z)."""
        pick = [self._max if flag else self._min for flag in (right, top, front)]
        return Vector3(pick[0][0], pick[1][1], pick[2][2])

    back = property(lambda self: float(self._min[2]))
    front = property(lambda self: float(self._max[2]))
    back_bottom_left = property(lambda self: self._corner(False, False, False))
    back_bottom_right = property(lambda self: self._corner(True, False, False))
    back_top_left = property(lambda self: self._corner(False, True, False))
    back_top_right = property(lambda self: self._corner(True, True, False))
    front_bottom_left = property(lambda self: self._corner(False, False, True))
    front_bottom_right = property(lambda self: self._corner(True, False, True))
    front_top_left = property(lambda self: self._corner(False, True, True))
    front_top_right = property(lambda self: self._corner(True, True, True))

    def size_z(self) -> float:
        return float(self._max[2] - self._min[2])

    def center_z(self) -> float:
        return float(0.5 * (self._min[2] + self._max[2]))

    def z(self) -> Range1D:
        return Range1D(self._min[2], self._max[2])

    def _plane(self, a: int, b: int) -> Range2D:
        return Range2D(self._min[[a, b]], self._max[[a, b]])

    def xy(self) -> Range2D:
        return self._plane(0, 1)

    def yz(self) -> Range2D:
        return self._plane(1, 2)

    def xz(self) -> Range2D:
        return self._plane(0, 2)
