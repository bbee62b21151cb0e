"""User attributes: Habitat's ``Configuration``, a typed key-value store with sub-configurations.

Templates carry the free JSON found under ``"user_defined"`` in their config files as a
:class:`Configuration`; every object created from the template starts with a copy of it
(``obj.user_attributes``). Values are typed when set: bool, int, float, str, a 3-vector
(:class:`mn.Vector3`), a 4-vector, a :class:`mn.Quaternion`, or a nested ``Configuration``.

``get_as_string`` reproduces Habitat's exact formats:

==========  ====================  =============================
type        format                example
==========  ====================  =============================
bool        ``True`` / ``False``  ``True``
int         decimal               ``7``
float       ``%.15g``             ``19.7``
str         as is                 ``hello``
Vector3     ``[%.6g %.6g %.6g]``  ``[2.5 0 0.2]``
Quaternion  ``w [x y z]`` (%.6g)  ``0.707107 [-0.707107 0 0]``
==========  ====================  =============================
"""

from __future__ import annotations

import copy
import warnings
from enum import Enum
from typing import Any

import numpy as np

from engine import mn
from engine.mn.vectors import finite_array

__all__ = ["ConfigValType", "Configuration"]


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


def _fmt(value: float) -> str:
    return f"{value:.6g}"


class Configuration:
    """A typed key-value store with nested sub-configurations (Habitat's user attributes)."""

    def __init__(self) -> None:
        self._values: dict[str, tuple[ConfigValType, Any]] = {}
        self._subconfigs: dict[str, Configuration] = {}

    # -- typing ---------------------------------------------------------------------------------
    @staticmethod
    def _typed(key: str, value: Any) -> tuple[ConfigValType, Any]:
        """The (type, stored value) of ``value``; ValueError for an unsupported value."""
        if isinstance(value, bool | np.bool_):
            return ConfigValType.Boolean, bool(value)
        if isinstance(value, int | np.integer):
            return ConfigValType.Integer, int(value)
        if isinstance(value, float | np.floating):
            return ConfigValType.Float, float(value)
        if isinstance(value, str):
            return ConfigValType.String, value
        if isinstance(value, mn.Quaternion) or all(hasattr(value, a) for a in "wxyz"):
            return ConfigValType.MagnumQuat, mn.to_quaternion(value, key)
        if isinstance(value, mn.Vector3 | list | tuple | np.ndarray):
            array = np.asarray(value, dtype=np.float64) if len(value) in (3, 4) else None
            if array is not None and array.shape == (3,):
                return ConfigValType.MagnumVec3, mn.to_vector3(array, key)
            if array is not None and array.shape == (4,) and np.all(np.isfinite(array)):
                return ConfigValType.MagnumVec4, array
        raise ValueError(f"user attribute {key!r}: unsupported value {value!r}")

    # -- values -----------------------------------------------------------------------------------
    def set(self, key: str, value: Any) -> None:
        """Store ``value`` under ``key`` (a ``Configuration`` value becomes a sub-configuration)."""
        if not isinstance(key, str) or not key:
            raise ValueError(f"configuration key must be a non-empty string, got {key!r}")
        if isinstance(value, Configuration):
            self._subconfigs[key] = value.copy()
            return
        typed = self._typed(key, value)
        self._values[key] = typed

    def get(self, key: str) -> Any:
        """The value stored under ``key`` (a copy for vectors); KeyError if absent."""
        if key in self._values:
            return copy.deepcopy(self._values[key][1])
        if key in self._subconfigs:
            return self._subconfigs[key]
        raise KeyError(f"user attribute {key!r} not found")

    def get_type(self, key: str) -> ConfigValType:
        if key not in self._values:
            raise KeyError(f"user attribute {key!r} not found")
        return self._values[key][0]

    def get_as_string(self, key: str) -> str:
        """The value formatted as Habitat does (see the module docstring)."""
        if key not in self._values:
            raise KeyError(f"user attribute {key!r} not found")
        value_type, value = self._values[key]
        if value_type is ConfigValType.Boolean:
            return "True" if value else "False"
        if value_type is ConfigValType.Integer:
            return str(value)
        if value_type is ConfigValType.Float:
            return f"{value:.15g}"
        if value_type is ConfigValType.String:
            return value
        if value_type is ConfigValType.MagnumQuat:
            x, y, z = value.vector
            return f"{_fmt(value.scalar)} [{_fmt(x)} {_fmt(y)} {_fmt(z)}]"
        return "[" + " ".join(_fmt(c) for c in np.asarray(value)) + "]"

    def has_value(self, key: str) -> bool:
        return key in self._values

    def remove(self, key: str) -> Any:
        """Remove ``key`` (a value or a sub-configuration) and return what it held."""
        if key in self._values:
            return self._values.pop(key)[1]
        if key in self._subconfigs:
            return self._subconfigs.pop(key)
        raise KeyError(f"user attribute {key!r} not found")

    def get_keys_by_type(self, value_type: ConfigValType | type) -> list[str]:
        """Keys whose values have ``value_type`` (a ConfigValType or a Python type), sorted."""
        by_python_type: dict[type, ConfigValType] = {
            bool: ConfigValType.Boolean,
            int: ConfigValType.Integer,
            float: ConfigValType.Float,
            str: ConfigValType.String,
            mn.Vector3: ConfigValType.MagnumVec3,
            mn.Quaternion: ConfigValType.MagnumQuat,
        }
        wanted = (
            value_type
            if isinstance(value_type, ConfigValType)
            else by_python_type.get(value_type)  # None (matches nothing) for other types
        )
        return sorted(k for k, (t, _) in self._values.items() if t is wanted)

    def get_keys(self) -> list[str]:
        return sorted(self._values)

    def get_num_entries(self) -> int:
        return len(self._values)

    # -- sub-configurations -------------------------------------------------------------------
    def get_subconfig(self, key: str) -> Configuration:
        """The editable sub-configuration under ``key``, created empty if absent (Habitat)."""
        return self._subconfigs.setdefault(key, Configuration())

    def get_subconfig_copy(self, key: str) -> Configuration:
        if key not in self._subconfigs:
            raise KeyError(f"sub-configuration {key!r} not found")
        return self._subconfigs[key].copy()

    def has_subconfig(self, key: str) -> bool:
        return key in self._subconfigs

    def get_subconfig_keys(self) -> list[str]:
        return sorted(self._subconfigs)

    def get_num_subconfigs(self) -> int:
        return len(self._subconfigs)

    # -- copying and JSON -----------------------------------------------------------------------
    def copy(self) -> Configuration:
        return copy.deepcopy(self)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Configuration):
            return False
        return self.to_dict() == other.to_dict()

    # No __hash__ (mutable): __eq__ alone sets it to None.

    @classmethod
    def from_dict(cls, data: dict, source: str = "user_defined") -> Configuration:
        """Build from JSON data: objects become sub-configurations, 3-lists Vector3,
        4-lists a Quaternion ``[w, x, y, z]`` when the key names a rotation, else a 4-vector."""
        if not isinstance(data, dict):
            raise ValueError(f"{source} must be a JSON object, got {type(data).__name__}")
        config = cls()
        for key, value in data.items():
            if value is None or (isinstance(value, list) and any(v is None for v in value)):
                # Habitat's JSON reader skips a null (and a numeric array holding one) with a
                # warning instead of failing the whole file
                warnings.warn(
                    f"{source}.{key} is null (or holds a null): skipped, as Habitat does",
                    stacklevel=2,
                )
                continue
            if isinstance(value, dict):
                config._subconfigs[key] = cls.from_dict(value, f"{source}.{key}")
            elif isinstance(value, list) and len(value) == 4 and _is_rotation_key(key):
                w, x, y, z = finite_array(value, 4, f"{source}.{key}")
                config.set(key, mn.Quaternion((x, y, z), w))
            else:
                config.set(key, value)
        return config

    def to_dict(self) -> dict:
        out: dict[str, Any] = {}
        for key, (value_type, value) in self._values.items():
            if value_type is ConfigValType.MagnumQuat:
                out[key] = [value.scalar, *value.vector]
            elif value_type in (ConfigValType.MagnumVec3, ConfigValType.MagnumVec4):
                out[key] = [float(c) for c in np.asarray(value)]
            else:
                out[key] = value
        for key, sub in self._subconfigs.items():
            out[key] = sub.to_dict()
        return out

    def __repr__(self) -> str:
        return f"Configuration({self.to_dict()!r})"


def _is_rotation_key(key: str) -> bool:
    lowered = key.lower()
    return any(word in lowered for word in ("rotation", "quat", "orient"))
