"""The typed values a :class:`~engine.templates.user_config.Configuration` holds, as Habitat
types them.

Habitat's ``core.Configuration`` stores each value with a type tag (``ConfigValType``) chosen
from the Python value given to ``set``:

=================================  ===============  ==========================================
value given                        type             returned by ``get`` / ``get_as_string``
=================================  ===============  ==========================================
``bool``                           ``Boolean``      ``bool`` / ``True``
``int`` (or a NumPy integer)       ``Integer``      ``int`` / ``7``
``mn.Rad`` / ``mn.Deg``            ``MagnumRad``    ``mn.Rad`` / ``1.570796`` (``%f``)
``float`` (or a 0-d float array)   ``Float``        ``float`` / ``19.7`` (``%.15g``)
``str``                            ``String``       ``str`` / as is
2 numbers (list, array, Vector2)   ``MagnumVec2``   ``mn.Vector2`` / ``[1 2]`` (``%.6g``)
``mn.Vector2i``                    ``MagnumVec2i``  ``mn.Vector2i`` / ``[1 2]``
3 numbers                          ``MagnumVec3``   ``mn.Vector3`` / ``[2.5 0 0.2]``
4 numbers                          ``MagnumVec4``   ``mn.Vector4`` / ``[1 2 3 4]``
a quaternion (Magnum, numpy)       ``MagnumQuat``   ``mn.Quaternion`` as given / ``w [x y z]``
3x3 (``mn.Matrix3``, array)        ``MagnumMat3``   ``mn.Matrix3`` / ``[[a b c][d e f][g h i]]``
4x4 (``mn.Matrix4``, array)        ``MagnumMat4``   ``mn.Matrix4`` / rows the same way
=================================  ===============  ==========================================

Anything else (a list of strings, a 5-vector, a non-finite vector, None) raises ``ValueError``
naming the key and the value, before the configuration changes.
"""

from __future__ import annotations

from enum import Enum
from typing import Any

import numpy as np

from engine import mn

__all__ = ["ConfigValType", "format_value", "typed_value"]


class ConfigValType(Enum):
    """The type tag of a stored value (Habitat's ``ConfigValType``)."""

    Unknown = 0
    Boolean = 1
    Integer = 2
    Float = 3
    String = 4
    MagnumVec3 = 5
    MagnumVec4 = 6
    MagnumQuat = 7
    MagnumRad = 8
    MagnumDeg = 9
    MagnumVec2 = 10
    MagnumVec2i = 11
    MagnumMat3 = 12
    MagnumMat4 = 13


#: array shape -> (type, constructor of the returned Magnum value)
_BY_SHAPE: dict[tuple[int, ...], tuple[ConfigValType, Any]] = {
    (2,): (ConfigValType.MagnumVec2, mn.Vector2),
    (3,): (ConfigValType.MagnumVec3, mn.Vector3),
    (4,): (ConfigValType.MagnumVec4, mn.Vector4),
    (3, 3): (ConfigValType.MagnumMat3, mn.Matrix3),
    (4, 4): (ConfigValType.MagnumMat4, mn.Matrix4),
}


def _scalar(key: str, value: Any) -> tuple[ConfigValType, Any] | None:
    """The typed value of a scalar, or None when ``value`` is not one."""
    if isinstance(value, bool | np.bool_):
        return ConfigValType.Boolean, bool(value)
    if isinstance(value, mn.Rad):
        return ConfigValType.MagnumRad, mn.Rad(value)
    if isinstance(value, mn.Deg):
        return ConfigValType.MagnumDeg, mn.Deg(value)
    if isinstance(value, int | np.integer):
        return ConfigValType.Integer, int(value)
    if isinstance(value, float | np.floating):
        return ConfigValType.Float, float(value)
    if isinstance(value, str):
        return ConfigValType.String, value
    if isinstance(value, np.ndarray) and value.ndim == 0:  # a 0-d array holds one scalar
        return _scalar(key, value.item())
    return None


def typed_value(key: str, value: Any) -> tuple[ConfigValType, Any]:
    """The ``(type, stored value)`` of ``value`` (see the module table); ValueError otherwise."""
    scalar = _scalar(key, value)
    if scalar is not None:
        return scalar
    if isinstance(value, mn.Quaternion) or all(hasattr(value, a) for a in "wxyz"):
        # stored as given, not normalized (Habitat keeps the four numbers)
        is_magnum = isinstance(value, mn.Quaternion)
        xyzw = np.asarray(
            value.xyzw if is_magnum else [getattr(value, a) for a in "xyzw"], dtype=np.float64
        )
        if xyzw.shape != (4,) or not np.all(np.isfinite(xyzw)):
            raise ValueError(f"configuration key {key!r}: quaternion must be finite, got {value!r}")
        return ConfigValType.MagnumQuat, mn.Quaternion.from_xyzw(xyzw)
    if isinstance(value, mn.Vector2i):
        return ConfigValType.MagnumVec2i, mn.Vector2i(value)
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(
            f"configuration key {key!r}: {value!r} is not a number, string, vector, "
            f"quaternion or matrix"
        ) from error
    if isinstance(value, str | bytes | dict | set) or array.shape not in _BY_SHAPE:
        raise ValueError(
            f"configuration key {key!r}: unsupported value {value!r} (shape {array.shape}); "
            f"use a scalar, a string, a 2-, 3- or 4-vector, a quaternion or a 3x3/4x4 matrix"
        )
    if not np.all(np.isfinite(array)):
        raise ValueError(f"configuration key {key!r}: value must be finite, got {value!r}")
    value_type, make = _BY_SHAPE[array.shape]
    return value_type, make(array)


def format_value(value_type: ConfigValType, value: Any) -> str:
    """``value`` as Habitat's ``get_as_string`` writes it (see the module table)."""
    if value_type is ConfigValType.Boolean:
        return "True" if value else "False"
    if value_type is ConfigValType.Integer:
        return str(value)
    if value_type in (ConfigValType.MagnumRad, ConfigValType.MagnumDeg):
        return f"{float(value):f}"
    if value_type is ConfigValType.Float:
        return f"{value:.15g}"
    if value_type is ConfigValType.String:
        return value
    if value_type is ConfigValType.MagnumQuat:
        x, y, z = value.vector
        return f"{_fmt(value.scalar)} [{_fmt(x)} {_fmt(y)} {_fmt(z)}]"
    if value_type in (ConfigValType.MagnumMat3, ConfigValType.MagnumMat4):
        rows = np.asarray(value)
        return "[" + "".join("[" + " ".join(_fmt(c) for c in row) + "]" for row in rows) + "]"
    return "[" + " ".join(_fmt(c) for c in np.asarray(value)) + "]"


def _fmt(value: float) -> str:
    return f"{value:.6g}"
