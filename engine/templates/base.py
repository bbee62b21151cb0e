"""The machinery every template shares: typed fields declared in a table, one validator.

A template (:mod:`engine.templates.attributes`) is a bag of typed fields with Habitat's names and
defaults. Each field is declared once (:class:`Field`: JSON key, kind, default); the JSON
reader (:meth:`AbstractAttributes.from_json_file`) and the attribute setters share one
validator (:func:`validate`), so a bad value raises the same clear ``ValueError`` naming the
field (and the file) either way, before anything is stored.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from engine import mn
from engine.core.fixed_fields import public_names, unknown_attribute_error
from engine.logging import get_logger
from engine.scene.primitives import is_primitive_handle
from engine.templates.config_json import MAX_PATH_CHARS, checked_path, read_json_object
from engine.templates.user_config import Configuration

__all__ = ["AbstractAttributes", "Field", "check_inertia", "copy_value", "validate"]


@dataclass(frozen=True)
class Field:
    """One template field: its JSON key, its kind, its default value."""

    json_key: str | None
    # "float", "positive", "nonnegative", "unit" ([0, 1]), "vec3", "scale" (vec3 > 0),
    # "inertia" (zero or a physical diagonal), "bool", "int", "str", "asset",
    # "restitution", "damping" (>= 0; above 1 stored with a warning, as Habitat stores it),
    # "timestep" (within _RANGES["timestep"])
    kind: str
    default: Any


#: ``|up . front|`` allowed between a template's unit ``up`` and ``front`` (the asset loader's).
FRAME_ORTHOGONAL_TOLERANCE = 1e-6


def check_inertia(inertia: Any, name: str) -> np.ndarray:
    """A diagonal inertia must be finite, > 0 and obey the triangle inequality
    ``I_a + I_b >= I_c`` of every rigid mass distribution (1e-6 relative slack: flat bodies
    reach equality). Returns it as a float64 array, else ValueError naming ``name``."""
    inertia = np.asarray(inertia, dtype=np.float64)
    if not np.all(np.isfinite(inertia)) or np.any(inertia <= 0):
        raise ValueError(f"{name} must be finite and > 0, got {inertia.tolist()}")
    biggest = float(inertia.max())
    total = float(np.sum(inertia / biggest)) * biggest  # sum without overflow
    if np.any(2.0 * (inertia / biggest) > (total / biggest) * (1.0 + 1e-6)):  # I_c > I_a + I_b
        raise ValueError(
            f"{name} {inertia.tolist()} breaks the triangle inequality "
            f"(each component must be <= the sum of the other two)"
        )
    return inertia


def validate(name: str, kind: str, value: Any, source: str = "") -> Any:
    """``value`` converted to the field's kind; ValueError naming the field (and file)."""
    where = f" in {source}" if source else ""
    if kind in ("vec3", "scale", "inertia"):
        vector = np.asarray(mn.to_vector3(value, f"{name}{where}"))
        if kind == "scale" and np.any(vector <= 0.0):
            raise ValueError(
                f"{name}{where} must be > 0 on every axis (zero collapses the "
                f"object, negative mirrors it), got {vector.tolist()}"
            )
        if kind == "inertia" and np.any(vector != 0.0):  # all zero: computed from the shape
            check_inertia(vector, f"{name}{where}")
        return vector
    if kind == "bool":
        if not isinstance(value, bool | np.bool_):
            raise ValueError(f"{name}{where} must be a bool, got {value!r}")
        return bool(value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise ValueError(f"{name}{where} must be an integer, got {value!r}")
        return int(value)
    if kind in ("str", "asset"):
        if not isinstance(value, str):
            raise ValueError(f"{name}{where} must be a string, got {value!r}")
        if len(value) > MAX_PATH_CHARS:
            raise ValueError(
                f"{name}{where} is a string of {len(value)} characters starting "
                f"{value[:40]!r}; at most {MAX_PATH_CHARS} (a file name or handle)"
            )
        return value
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"{name}{where} must be a number, got {value!r}")
    try:
        number = float(value)
    except OverflowError:  # an int beyond the float range (a JSON literal of 400 digits)
        raise ValueError(
            f"{name}{where} is an integer of {int(value).bit_length()} bits, beyond the "
            f"largest float {sys.float_info.max:.4g}"
        ) from None
    if not math.isfinite(number):
        raise ValueError(f"{name}{where} must be finite, got {value!r}")
    if kind in _RANGES and not _RANGES[kind][0] <= number <= _RANGES[kind][1]:
        low, high, why = _RANGES[kind]
        raise ValueError(f"{name}{where} must be in [{low:g}, {high:g}] {why}, got {value!r}")
    if kind == "positive" and number <= 0.0:
        raise ValueError(f"{name}{where} must be > 0, got {value!r}")
    if kind == "nonnegative" and number < 0.0:
        raise ValueError(f"{name}{where} must be >= 0, got {value!r}")
    if kind == "unit" and not 0.0 <= number <= 1.0:
        raise ValueError(f"{name}{where} must be in [0, 1], got {value!r}")
    if kind in _ABOVE_ONE_WARNING:
        if number < 0.0:
            raise ValueError(f"{name}{where} must be >= 0, got {value!r}")
        if number > 1.0:  # Habitat stores it silently
            get_logger("metadata").warning(
                "%s%s = %r is above 1: stored, but %s", name, where, value, _ABOVE_ONE_WARNING[kind]
            )
    return number


#: kinds with a closed range: (low, high, what the range is)
_RANGES = {
    # measured: a stack of three 20 cm cubes stands at 0.1 s and falls apart at 0.2 s; below
    # 1e-5 s a 1/60 s frame runs more than 1667 steps (minutes of CPU time per second) and,
    # far below, more than the 100000 steps one step_physics call may run
    "timestep": (1e-5, 0.1, "seconds (the fixed steps the physics is tested with)"),
}

#: kinds stored above 1 (as Habitat stores them) with a warning saying what that means here
_ABOVE_ONE_WARNING = {
    "restitution": "bounces will gain energy",
    "damping": "the physics uses 1 (all velocity lost each second), as Bullet clamps it",
}

_Attributes = TypeVar("_Attributes", bound="AbstractAttributes")  # a template's own class


class AbstractAttributes:
    """Shared machinery: typed fields from a table, JSON loading, copying, user config."""

    FIELDS: dict[str, Field] = {}

    def __init__(self, handle: str = "") -> None:
        values = {name: field.default for name, field in self.FIELDS.items()}
        object.__setattr__(self, "_values", {k: copy_value(v) for k, v in values.items()})
        object.__setattr__(self, "_user_config", Configuration())
        object.__setattr__(self, "handle", handle)
        object.__setattr__(self, "template_id", -1)
        object.__setattr__(self, "file_directory", "")
        object.__setattr__(self, "_explicit", set())
        object.__setattr__(self, "_paths_dirty", False)

    # -- typed field access -----------------------------------------------------------------------
    def __getattr__(self, name: str) -> Any:
        values = self.__dict__.get("_values")
        if values is not None and name in values:
            value = values[name]
            return mn.Vector3(value) if isinstance(value, np.ndarray) else value
        if name.startswith("__") or values is None:
            raise AttributeError(name)
        raise unknown_attribute_error(type(self).__name__, name, self._field_names())

    @classmethod
    def _field_names(cls) -> list[str]:
        """Every name a template answers to: its fields, properties and methods."""
        return sorted({*cls.FIELDS, "handle", "file_directory", "template_id", *public_names(cls)})

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(getattr(type(self), name, None), property):
            object.__setattr__(self, name, value)  # a property's own setter validates
        elif name in self.FIELDS:
            self._values[name] = validate(name, self.FIELDS[name].kind, value)
            self._explicit.add(name)
            if self.FIELDS[name].kind == "asset":
                object.__setattr__(self, "_paths_dirty", True)
        elif name in ("handle", "file_directory"):
            object.__setattr__(self, name, validate(name, "str", value))
        elif name == "template_id":
            object.__setattr__(self, name, validate(name, "int", value))
        else:
            raise unknown_attribute_error(type(self).__name__, name, self._field_names())

    @property
    def ID(self) -> int:  # noqa: N802 - Habitat's spelling
        return self.template_id

    @property
    def filenames_are_dirty(self) -> bool:
        """True when an asset path was set since the template was made or registered (Habitat:
        it must be registered again before objects are built from it)."""
        return bool(self.__dict__.get("_paths_dirty", False))

    def _mark_paths_clean(self) -> None:
        object.__setattr__(self, "_paths_dirty", False)

    @property
    def template_class(self) -> str:
        """Habitat's class key of the template (read only): ``"ObjectAttributes"``,
        ``"StageAttributes"``, ``"PhysicsManagerAttributes"``, ``"CubePrimitiveAttributes"``..."""
        return type(self).__name__

    @property
    def num_user_configs(self) -> int:
        """Number of values in the user configuration (Habitat's ``num_user_configs``)."""
        return self._user_config.get_num_entries()

    def get_user_config(self) -> Configuration:
        """The editable user configuration (``user_defined`` in the JSON), by reference."""
        return self._user_config

    def check_frame(self, source: str = "") -> None:
        """Refuse an ``up``/``front`` pair that is not a rotation frame: both non-zero and
        orthogonal (a skewed pair would shear the asset). ValueError naming the fields."""
        if "orient_up" not in self.FIELDS:
            return
        where = f" in {source}" if source else ""
        up, front = np.asarray(self._values["orient_up"]), np.asarray(self._values["orient_front"])
        lengths = [float(mn.stable_norm(v)) for v in (up, front)]
        if min(lengths) < 1e-12:
            raise ValueError(
                f"orient_up {up.tolist()} and orient_front {front.tolist()}{where} must be non-zero"
            )
        if abs(float((up / lengths[0]) @ (front / lengths[1]))) > FRAME_ORTHOGONAL_TOLERANCE:
            raise ValueError(
                f"orient_up {up.tolist()} and orient_front {front.tolist()}{where} "
                f"must be orthogonal (a skewed frame would shear the asset)"
            )

    def is_set_explicitly(self, name: str) -> bool:
        """True when the field was given by the JSON file or a setter (not left at default)."""
        return name in self._explicit

    def copy(self: _Attributes) -> _Attributes:
        clone = type(self).__new__(type(self))
        for key, value in self.__dict__.items():
            object.__setattr__(clone, key, copy_value(value))
        return clone

    def as_dict(self) -> dict[str, Any]:
        return {name: copy_value(value) for name, value in self._values.items()}

    def __repr__(self) -> str:
        return f"{type(self).__name__}(handle={self.handle!r}, id={self.template_id})"

    # -- JSON ------------------------------------------------------------------------------
    @classmethod
    def from_json_file(cls: type[_Attributes], path: str | Path) -> _Attributes:
        """Read a config file; the template handle is its full path."""
        path = checked_path(path).resolve()
        if not path.is_file():
            raise FileNotFoundError(f"config file not found: {path}")
        data = read_json_object(path)
        template = cls(str(path))
        template.file_directory = str(path.parent)
        template._apply_json(data, path)
        return template

    def _apply_json(self, data: dict, path: Path) -> None:
        """Validate every known key first, then assign (nothing half-applied on error)."""
        staged: dict[str, Any] = {}
        for name, field in self.FIELDS.items():
            if field.json_key is None or field.json_key not in data:
                continue
            value = validate(field.json_key, field.kind, data[field.json_key], str(path))
            if field.kind == "asset" and not is_primitive_handle(value):
                value = str((path.parent / value).resolve())
            staged[name] = value
        user = Configuration.from_dict(data.get("user_defined", {}), f"user_defined in {path}")
        candidate = self.copy()
        candidate._values.update(staged)
        candidate.check_frame(str(path))
        self._values.update(staged)
        self._explicit.update(staged)
        object.__setattr__(self, "_user_config", user)


def copy_value(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, Configuration):
        return value.copy()
    if isinstance(value, set | dict | list):
        return type(value)(value)
    return value
