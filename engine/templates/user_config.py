"""User attributes: Habitat's ``Configuration``, a typed key-value store with sub-configurations.

Templates carry the free JSON found under ``"user_defined"`` in their config files as a
:class:`Configuration`; every object created from the template starts with a copy of it
(``obj.user_attributes``). Values are typed when set (:mod:`engine.templates.config_values` has the
whole table): bool, int, float, ``Rad``/``Deg``, str, 2-, 3- and 4-vectors, quaternions, 3x3
and 4x4 matrices, or a nested ``Configuration``; ``get`` returns the Magnum type.

``get_as_string`` reproduces Habitat's exact formats, among them:

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

import builtins
import copy
import warnings
from typing import Any

import numpy as np

from engine import mn
from engine.mn.vectors import finite_array
from engine.templates.config_values import ConfigValType, format_value, typed_value

__all__ = ["ConfigValType", "Configuration"]


class Configuration:
    """A typed key-value store with nested sub-configurations (Habitat's user attributes)."""

    def __init__(self) -> None:
        self._values: dict[str, tuple[ConfigValType, Any]] = {}
        self._subconfigs: dict[str, Configuration] = {}

    @staticmethod
    def _typed(key: str, value: Any) -> tuple[ConfigValType, Any]:
        """The (type, stored value) of ``value`` (:func:`.config_values.typed_value`)."""
        return typed_value(key, value)

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

    def init(self, key: str, value: Any) -> None:
        """Habitat's ``init``: store an initial value (here the same as :meth:`set`)."""
        self.set(key, value)

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
        return format_value(*self._values[key])

    def has_value(self, key: str) -> bool:
        return key in self._values

    def remove(self, key: str) -> Any:
        """Remove ``key`` (a value or a sub-configuration) and return what it held."""
        if key in self._values:
            return self._values.pop(key)[1]
        if key in self._subconfigs:
            return self._subconfigs.pop(key)
        raise KeyError(f"user attribute {key!r} not found")

    def get_keys_by_type(self, value_type: ConfigValType | type, sorted: bool = True) -> list[str]:  # noqa: A002
        """Keys whose values have ``value_type`` (a ConfigValType or a Python type), sorted."""
        by_python_type: dict[type, ConfigValType] = {
            bool: ConfigValType.Boolean,
            int: ConfigValType.Integer,
            float: ConfigValType.Float,
            str: ConfigValType.String,
            mn.Vector2: ConfigValType.MagnumVec2,
            mn.Vector3: ConfigValType.MagnumVec3,
            mn.Vector4: ConfigValType.MagnumVec4,
            mn.Quaternion: ConfigValType.MagnumQuat,
            mn.Matrix3: ConfigValType.MagnumMat3,
            mn.Matrix4: ConfigValType.MagnumMat4,
        }
        wanted = (
            value_type
            if isinstance(value_type, ConfigValType)
            else by_python_type.get(value_type)  # None (matches nothing) for other types
        )
        keys = [k for k, (t, _) in self._values.items() if t is wanted]
        return builtins.sorted(keys) if sorted else keys

    def get_keys(self) -> list[str]:
        return sorted(self._values)

    def get_num_entries(self) -> int:
        return len(self._values)

    # -- sub-configurations -------------------------------------------------------------------
    def get_subconfig(self, key: str) -> Configuration:
        """The editable sub-configuration under ``key``, created empty if absent (Habitat)."""
        return self._subconfigs.setdefault(key, Configuration())

    def get_subconfig_copy(self, key: str) -> Configuration:
        """A copy of the sub-configuration ``key`` (created empty first if absent, as Habitat)."""
        return self.get_subconfig(key).copy()

    def save_subconfig(self, key: str, subconfig: Configuration) -> None:
        """Store (a copy of) ``subconfig`` under ``key``, replacing what was there."""
        if not isinstance(subconfig, Configuration):
            raise TypeError(f"subconfig {key!r} must be a Configuration, got {subconfig!r}")
        self.set(key, subconfig)

    def remove_subconfig(self, key: str) -> Configuration:
        """Remove and return the sub-configuration ``key`` (KeyError if absent)."""
        if key not in self._subconfigs:
            raise KeyError(f"sub-configuration {key!r} not found")
        return self._subconfigs.pop(key)

    def find_value_location(self, key: str) -> list[str]:
        """The sub-configuration keys leading to ``key``, then ``key`` ([] if nowhere).

        Depth first in key order; this configuration's own values and sub-configurations first.
        """
        if key in self._values or key in self._subconfigs:
            return [key]
        for name in sorted(self._subconfigs):
            path = self._subconfigs[name].find_value_location(key)
            if path:
                return [name, *path]
        return []

    def has_key_to_type(self, key: str, value_type: ConfigValType) -> bool:
        """True when ``key`` holds a value of ``value_type``."""
        return key in self._values and self._values[key][0] is value_type

    def get_keys_and_types(self) -> dict[str, ConfigValType]:
        """Every value key with its type."""
        return {key: value_type for key, (value_type, _) in self._values.items()}

    @property
    def top_level_num_entries(self) -> int:
        return len(self._values) + len(self._subconfigs)

    @property
    def top_level_num_configs(self) -> int:
        return len(self._subconfigs)

    @property
    def top_level_num_values(self) -> int:
        return len(self._values)

    @property
    def total_num_configs(self) -> int:
        return sum(1 + sub.total_num_configs for sub in self._subconfigs.values())

    @property
    def total_num_values(self) -> int:
        return len(self._values) + sum(s.total_num_values for s in self._subconfigs.values())

    @property
    def total_num_entries(self) -> int:
        return self.total_num_values + self.total_num_configs

    def has_subconfig(self, key: str) -> bool:
        return key in self._subconfigs

    def get_subconfig_keys(self, sorted: bool = True) -> list[str]:  # noqa: A002
        keys = list(self._subconfigs)
        return builtins.sorted(keys) if sorted else keys

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
            elif isinstance(value, mn.Vector2i):
                out[key] = [int(c) for c in np.asarray(value)]
            elif isinstance(value, mn.Rad | mn.Deg):
                out[key] = float(value)
            elif not isinstance(value, bool | int | float | str):  # vectors and matrices
                out[key] = np.asarray(value, dtype=np.float64).tolist()
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
