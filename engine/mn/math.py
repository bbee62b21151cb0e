"""``mn.math``: the free functions and constants of Magnum's ``magnum.math`` module.

Only names Magnum's Python bindings have are defined, with their meaning:

* constants ``pi``, ``pi_half``, ``pi_quarter``, ``tau``, ``e``, ``sqrt2``, ``sqrt3``,
  ``sqrt_half``, ``nan``, ``inf`` (Python floats, as Magnum puts them);
* trigonometry taking :class:`Rad` / :class:`Deg` (a plain number is radians): ``sin``,
  ``cos``, ``sincos``, ``tan``; inverses returning :class:`Rad`: ``asin``, ``acos``, ``atan``;
* scalar and component-wise functions: ``min``, ``max``, ``minmax``, ``clamp``, ``sign``,
  ``abs``, ``floor``, ``ceil``, ``round``, ``fmod``, ``sqrt``, ``sqrt_inverted``, ``log``,
  ``exp``, ``pow``, ``isinf``, ``isnan``, ``lerp``, ``lerp_inverted``, ``select``;
* vectors: ``dot``, ``cross`` (Vector3: a vector; Vector2: the scalar ``a.x b.y - a.y b.x``),
  ``angle(a, b) = acos(clamp(a . b, -1, 1))`` of normalized vectors;
* quaternions: ``dot``, ``half_angle(a, b) = acos(clamp(a . b, -1, 1))`` (half the rotation
  between two unit quaternions; Magnum's older name ``angle`` is accepted for quaternions
  too), ``lerp`` / ``lerp_shortest_path`` (normalized ``(1 - t) a + t b``), ``slerp`` /
  ``slerp_shortest_path`` (``(sin((1 - t) theta) a + sin(t theta) b) / sin(theta)`` with
  ``cos(theta) = a . b``; the shortest-path versions flip ``b`` when ``a . b < 0``).
"""

from __future__ import annotations

import builtins
import math as _math
from typing import Any

import numpy as np

from engine.mn.rotations import Quaternion
from engine.mn.vectors import Rad, Vector2, Vector3, _VectorN, radians

pi = _math.pi
pi_half = _math.pi / 2.0
pi_quarter = _math.pi / 4.0
tau = 2.0 * _math.pi
e = _math.e
sqrt2 = _math.sqrt(2.0)
sqrt3 = _math.sqrt(3.0)
sqrt_half = _math.sqrt(0.5)
nan = _math.nan
inf = _math.inf


# -- trigonometry -----------------------------------------------------------------------------
def sin(angle: Any) -> float:
    return _math.sin(radians(angle))


def cos(angle: Any) -> float:
    return _math.cos(radians(angle))


def sincos(angle: Any) -> tuple[float, float]:
    return sin(angle), cos(angle)


def tan(angle: Any) -> float:
    return _math.tan(radians(angle))


def asin(value: float) -> Rad:
    return Rad(_math.asin(value))


def acos(value: float) -> Rad:
    return Rad(_math.acos(value))


def atan(value: float) -> Rad:
    return Rad(_math.atan(value))


# -- scalar and component-wise ----------------------------------------------------------------
def _apply(function, *values: Any) -> Any:
    """``function`` on plain numbers, or component-wise on vectors (returning the vector type
    of the first vector argument)."""
    vector_type = next((type(v) for v in values if isinstance(v, _VectorN)), None)
    if vector_type is None:
        return function(*values)
    result = function(*(np.asarray(v, dtype=np.float64) for v in values))
    return vector_type(result)


def min(value: Any, min: Any) -> Any:  # noqa: A001, A002 - Magnum's names
    return (
        _apply(np.minimum, value, min) if isinstance(value, _VectorN) else builtins.min(value, min)
    )


def max(value: Any, max: Any) -> Any:  # noqa: A001, A002
    return (
        _apply(np.maximum, value, max) if isinstance(value, _VectorN) else builtins.max(value, max)
    )


def minmax(a: Any, b: Any) -> tuple[Any, Any]:
    return min(a, b), max(a, b)


def clamp(value: Any, min: Any, max: Any) -> Any:  # noqa: A002
    if isinstance(value, _VectorN):
        return _apply(np.clip, value, min, max)
    return builtins.min(builtins.max(value, min), max)


def sign(value: Any) -> Any:
    return (
        _apply(np.sign, value)
        if isinstance(value, _VectorN)
        else type(value)((value > 0) - (value < 0))
    )


def abs(value: Any) -> Any:  # noqa: A001
    return _apply(np.abs, value) if isinstance(value, _VectorN) else builtins.abs(value)


def floor(value: Any) -> Any:
    return _apply(np.floor, value) if isinstance(value, _VectorN) else float(_math.floor(value))


def ceil(value: Any) -> Any:
    return _apply(np.ceil, value) if isinstance(value, _VectorN) else float(_math.ceil(value))


def round(value: Any) -> Any:  # noqa: A001
    """Half away from zero, as C's ``round`` (not Python's banker's rounding)."""

    def half_away(x):
        return np.sign(x) * np.floor(np.abs(x) + 0.5)

    return _apply(half_away, value) if isinstance(value, _VectorN) else float(half_away(value))


def fmod(a: Any, b: Any) -> Any:
    return _apply(np.fmod, a, b) if isinstance(a, _VectorN) else _math.fmod(a, b)


def sqrt(value: Any) -> Any:
    return _apply(np.sqrt, value) if isinstance(value, _VectorN) else _math.sqrt(value)


def sqrt_inverted(value: Any) -> Any:
    return (
        _apply(lambda x: 1.0 / np.sqrt(x), value)
        if isinstance(value, _VectorN)
        else (1.0 / _math.sqrt(value))
    )


def log(value: float) -> float:
    return _math.log(value)


def exp(value: float) -> float:
    return _math.exp(value)


def pow(base: float, exponent: float) -> float:  # noqa: A001
    return _math.pow(base, exponent)


def isinf(value: Any) -> Any:
    if isinstance(value, _VectorN):
        return bool(np.any(np.isinf(np.asarray(value))))
    return _math.isinf(value)


def isnan(value: Any) -> Any:
    if isinstance(value, _VectorN):
        return bool(np.any(np.isnan(np.asarray(value))))
    return _math.isnan(value)


def lerp(a: Any, b: Any, t: Any) -> Any:
    """``(1 - t) a + t b`` (a bool ``t`` selects ``a`` or ``b``); quaternions: normalized."""
    if isinstance(a, Quaternion):
        return _quaternion_lerp(a, b, float(t))
    if isinstance(t, bool):
        return b if t else a
    return _apply(lambda x, y: (1.0 - t) * x + t * y, a, b)


def lerp_inverted(a: float, b: float, lerp: float) -> float:
    """The ``t`` with ``lerp(a, b, t) == lerp``: ``(lerp - a) / (b - a)``."""
    return (lerp - a) / (b - a)


def select(a: Any, b: Any, t: float) -> Any:
    """Constant interpolation: ``a`` for ``t < 1``, else ``b``."""
    return b if t >= 1.0 else a


# -- vectors and quaternions ------------------------------------------------------------------
def dot(a: Any, b: Any) -> float:
    if isinstance(a, Quaternion):
        return a.dot(b)
    return float(np.asarray(a, dtype=np.float64) @ np.asarray(b, dtype=np.float64))


def cross(a: Any, b: Any) -> Any:
    """Vector3: ``a x b``; Vector2: the scalar ``a.x b.y - a.y b.x``."""
    if isinstance(a, Vector2):
        return float(a[0] * b[1] - a[1] * b[0])
    return Vector3(np.cross(np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)))


def angle(normalized_a: Any, normalized_b: Any) -> Rad:
    """Angle between two unit vectors ``acos(clamp(a . b, -1, 1))``; for quaternions the
    half-angle (Magnum's older spelling of :func:`half_angle`)."""
    cosine = dot(normalized_a, normalized_b)
    return Rad(_math.acos(builtins.min(1.0, builtins.max(-1.0, cosine))))


def half_angle(normalized_a: Quaternion, normalized_b: Quaternion) -> Rad:
    """Half the angle of the rotation between two unit quaternions."""
    return angle(normalized_a, normalized_b)


def _quaternion_lerp(a: Quaternion, b: Quaternion, t: float) -> Quaternion:
    return ((1.0 - t) * a + t * b).normalized()


def lerp_shortest_path(normalized_a: Quaternion, normalized_b: Quaternion, t: float) -> Quaternion:
    b = -normalized_b if dot(normalized_a, normalized_b) < 0.0 else normalized_b
    return _quaternion_lerp(normalized_a, b, float(t))


def slerp(normalized_a: Quaternion, normalized_b: Quaternion, t: float) -> Quaternion:
    """Spherical interpolation; falls back to :func:`lerp` when ``|a . b| ~ 1``."""
    cosine = dot(normalized_a, normalized_b)
    if builtins.abs(cosine) >= 1.0 - 1e-5:
        return _quaternion_lerp(normalized_a, normalized_b, float(t))
    theta = _math.acos(cosine)
    weight_a = _math.sin((1.0 - t) * theta) / _math.sin(theta)
    weight_b = _math.sin(t * theta) / _math.sin(theta)
    return weight_a * normalized_a + weight_b * normalized_b


def slerp_shortest_path(normalized_a: Quaternion, normalized_b: Quaternion, t: float) -> Quaternion:
    b = -normalized_b if dot(normalized_a, normalized_b) < 0.0 else normalized_b
    return slerp(normalized_a, b, t)
