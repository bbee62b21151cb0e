"""Templates: the attributes objects, stages and the physics world are created from.

Mirrors ``habitat_sim.attributes``. A template is a bag of typed fields with Habitat's names
and defaults, read from a ``*.object_config.json`` / ``*.stage_config.json`` /
``*.physics_config.json`` file and editable in Python before it is registered with its
manager. Each field is declared once in a table (:data:`OBJECT_FIELDS` ...) giving its JSON
key, its kind (``float``, ``vec3``, ``bool``, ...) and its default; the JSON reader and the
property setters share one validator, so bad values raise the same clear ``ValueError``.

Conventions: asset paths in a config are relative to the config file; they are stored as
absolute paths unless they name a built-in primitive (``cubeSolid``...). JSON quaternions are
``[w, x, y, z]``; vectors are ``[x, y, z]``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from engine import mn
from engine.fixed_fields import public_names, unknown_attribute_error
from engine.logging import get_logger
from engine.named_enum import NamedIntEnum
from engine.primitives import is_primitive_handle
from engine.user_config import Configuration

__all__ = [
    "AbstractAttributes",
    "AssetType",
    "ObjectAttributes",
    "PhysicsManagerAttributes",
    "PrimitiveAssetAttributes",
    "StageAttributes",
    "is_primitive_handle",
    "read_json_object",
]


class AssetType(NamedIntEnum):
    """What kind of asset a template renders or collides with (Habitat's ``AssetType``;
    rigidsim tells only primitives from meshes, which Habitat reports as ``UNKNOWN``)."""

    UNKNOWN = 0
    MP3D = 1
    SEMANTIC = 2
    NAVMESH = 3
    PRIMITIVE = 4


#: longest path string accepted (Linux PATH_MAX); longer text is not a file name
MAX_PATH_CHARS = 4096
#: deepest nesting of objects/arrays accepted in a config file (real configs nest < 10 deep)
MAX_JSON_DEPTH = 100


def checked_path(path: Any, name: str = "path") -> Path:
    """``path`` (a str or PathLike) as a ``Path``, refused up front when it cannot be a file
    name: not a string, longer than ``MAX_PATH_CHARS`` or holding a NUL character. The error
    names the length and the start of the text, never the whole (possibly huge) value."""
    if not isinstance(path, str | Path):
        raise TypeError(f"{name} must be a str or Path, got {type(path).__name__}")
    text = str(path)
    if len(text) > MAX_PATH_CHARS or "\0" in text:
        raise ValueError(
            f"{name} is not a file name: {len(text)} characters starting {text[:60]!r} "
            f"(at most {MAX_PATH_CHARS}, no NUL); pass the path of a config file or folder"
        )
    return Path(text)


def json_depth(text: str) -> int:
    """Deepest bracket nesting of JSON ``text`` (brackets inside strings count too, so this
    bounds the real depth from above); linear time, no recursion."""
    opens = text.count("{") + text.count("[")
    if opens <= MAX_JSON_DEPTH:
        return opens
    depth = deepest = 0
    for char in text:
        if char in "{[":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "}]":
            depth -= 1
    return deepest


def read_json_object(path: Path) -> dict:
    """The JSON object in the file at ``path``; ``ValueError`` for malformed JSON, nesting
    deeper than ``MAX_JSON_DEPTH`` (refused before parsing) or any other top-level value."""
    text = path.read_text()
    if json_depth(text) > MAX_JSON_DEPTH:
        raise ValueError(
            f"{path} nests objects/arrays more than {MAX_JSON_DEPTH} deep; "
            f"a template config is a shallow JSON object"
        )
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise ValueError(f"malformed JSON in {path}: {error}") from error
    if not isinstance(data, dict):
        raise ValueError(f"{path} must hold a JSON object")
    return data


@dataclass(frozen=True)
class Field:
    """One template field: its JSON key, its kind, its default value."""

    json_key: str | None
    # "float", "positive", "nonnegative", "unit" ([0, 1]), "vec3", "scale" (vec3 > 0),
    # "inertia" (zero or a physical diagonal), "bool", "int", "str", "asset",
    # "restitution", "damping" (>= 0; above 1 stored with a warning, as Habitat stores it)
    kind: str
    default: Any


#: |up . front| allowed between a template's unit ``up`` and ``front`` (the asset loader's).
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


def _validate(name: str, kind: str, value: Any, source: str = "") -> Any:
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
        return value
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"{name}{where} must be a number, got {value!r}")
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"{name}{where} must be finite, got {value!r}")
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
        object.__setattr__(self, "_values", {k: _copy_value(v) for k, v in values.items()})
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
            self._values[name] = _validate(name, self.FIELDS[name].kind, value)
            self._explicit.add(name)
            if self.FIELDS[name].kind == "asset":
                object.__setattr__(self, "_paths_dirty", True)
        elif name in ("handle", "file_directory"):
            object.__setattr__(self, name, _validate(name, "str", value))
        elif name == "template_id":
            object.__setattr__(self, name, _validate(name, "int", value))
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
            object.__setattr__(clone, key, _copy_value(value))
        return clone

    def as_dict(self) -> dict[str, Any]:
        return {name: _copy_value(value) for name, value in self._values.items()}

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
            value = _validate(field.json_key, field.kind, data[field.json_key], str(path))
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


def _copy_value(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.copy()
    if isinstance(value, Configuration):
        return value.copy()
    if isinstance(value, set | dict | list):
        return type(value)(value)
    return value


_VEC_ONE = np.ones(3)
_VEC_ZERO = np.zeros(3)
_UP = np.array([0.0, 1.0, 0.0])
_FRONT = np.array([0.0, 0.0, -1.0])

# Fields shared by objects and stages (Habitat's AbstractObjectAttributes).
_ASSET_FIELDS = {
    "render_asset_handle": Field("render_asset", "asset", ""),
    "collision_asset_handle": Field("collision_asset", "asset", ""),
    "collision_asset_size": Field("collision_asset_size", "scale", _VEC_ONE),
    "scale": Field("scale", "scale", _VEC_ONE),
    "margin": Field("margin", "nonnegative", 0.04),
    "orient_up": Field("up", "vec3", _UP),
    "orient_front": Field("front", "vec3", _FRONT),
    "units_to_meters": Field("units_to_meters", "positive", 1.0),
    "friction_coefficient": Field("friction_coefficient", "nonnegative", 0.5),
    "rolling_friction_coefficient": Field("rolling_friction_coefficient", "nonnegative", 0.0),
    "spinning_friction_coefficient": Field("spinning_friction_coefficient", "nonnegative", 0.0),
    "restitution_coefficient": Field("restitution_coefficient", "restitution", 0.1),
    "force_flat_shading": Field("force_flat_shading", "bool", False),
    "is_collidable": Field("is_collidable", "bool", True),
    "shader_type": Field("shader_type", "str", "material"),
}

OBJECT_FIELDS = {
    **_ASSET_FIELDS,
    "mass": Field("mass", "positive", 1.0),
    "com": Field("COM", "vec3", _VEC_ZERO),
    "inertia": Field("inertia", "inertia", _VEC_ZERO),
    "linear_damping": Field("linear_damping", "damping", 0.2),
    "angular_damping": Field("angular_damping", "damping", 0.2),
    "bounding_box_collisions": Field("use_bounding_box_for_collision", "bool", False),
    "join_collision_meshes": Field("join_collision_meshes", "bool", False),
    "is_visibile": Field("is_visible", "bool", True),
    "semantic_id": Field("semantic_id", "int", 0),
}

STAGE_FIELDS = {
    **_ASSET_FIELDS,
    "friction_coefficient": Field("friction_coefficient", "nonnegative", 0.4),
    "restitution_coefficient": Field("restitution_coefficient", "restitution", 0.1),
    "gravity": Field("gravity", "vec3", np.array([0.0, -9.8, 0.0])),
    "origin": Field("origin", "vec3", _VEC_ZERO),
    "navmesh_asset_handle": Field("nav_asset", "asset", ""),
}

PHYSICS_FIELDS = {
    "simulator": Field("physics_simulator", "str", "bullet"),
    "timestep": Field("timestep", "positive", 0.008),
    "gravity": Field("gravity", "vec3", np.array([0.0, -9.8, 0.0])),
    "friction_coefficient": Field("friction_coefficient", "nonnegative", 0.4),
    "restitution_coefficient": Field("restitution_coefficient", "restitution", 0.1),
    "max_substeps": Field("max_substeps", "int", 10),
}


class _AssetPaths:
    """``render_asset_fullpath`` / ``collision_asset_fullpath`` (Habitat's names): the asset
    handle as a full path, joined to the template's folder when relative; a primitive
    handle (``cubeSolid``) or an empty one is returned as is."""

    render_asset_handle: str
    collision_asset_handle: str
    file_directory: str

    def _fullpath(self, handle: str) -> str:
        if not handle or is_primitive_handle(handle) or Path(handle).is_absolute():
            return handle
        return str(Path(self.file_directory or ".") / handle)

    @property
    def render_asset_type(self) -> AssetType:
        """``PRIMITIVE`` for a built-in primitive, else ``UNKNOWN`` (a mesh file), as Habitat."""
        handle = self.render_asset_handle
        return AssetType.PRIMITIVE if is_primitive_handle(handle) else AssetType.UNKNOWN

    @property
    def collision_asset_type(self) -> AssetType:
        """As ``render_asset_type``, for the collision asset (the render asset when empty)."""
        handle = self.collision_asset_handle or self.render_asset_handle
        return AssetType.PRIMITIVE if is_primitive_handle(handle) else AssetType.UNKNOWN

    @property
    def render_asset_fullpath(self) -> str:
        return self._fullpath(self.render_asset_handle)

    @property
    def collision_asset_fullpath(self) -> str:
        return self._fullpath(self.collision_asset_handle)


class ObjectAttributes(_AssetPaths, AbstractAttributes):
    """An object template (``*.object_config.json``), Habitat's ``ObjectAttributes``.

    ``compute_COM_from_shape`` is True unless the config (or a setter) gave ``COM``: then the
    object's origin (its ``translation``) is the center of its render mesh's AABB.
    An ``inertia`` of zero means "compute from the collision shape".
    """

    FIELDS = OBJECT_FIELDS

    @property
    def compute_COM_from_shape(self) -> bool:  # noqa: N802 - Habitat's spelling
        return "com" not in self._explicit

    @compute_COM_from_shape.setter
    def compute_COM_from_shape(self, value: bool) -> None:  # noqa: N802
        if _validate("compute_COM_from_shape", "bool", value):
            self._explicit.discard("com")
        else:
            self._explicit.add("com")

    @property
    def render_asset_is_primitive(self) -> bool:
        return is_primitive_handle(self.render_asset_handle)

    @property
    def collision_asset_is_primitive(self) -> bool:
        return is_primitive_handle(self.collision_asset_handle or self.render_asset_handle)

    @property
    def use_mesh_for_collision(self) -> bool:
        return not self.bounding_box_collisions


class StageAttributes(_AssetPaths, AbstractAttributes):
    """A stage template (``*.stage_config.json``), Habitat's ``StageAttributes``.

    A bare ``.glb`` with no config beside it is Z-up: see
    :meth:`engine.attributes_managers.StageAttributesManager.create_template_for_asset`.
    """

    FIELDS = STAGE_FIELDS


class PhysicsManagerAttributes(AbstractAttributes):
    """The physics world's settings (``*.physics_config.json``)."""

    FIELDS = PHYSICS_FIELDS


PRIMITIVE_FIELDS: dict[str, Field] = {}
_PRIMITIVE_FLAGS = ("useTexCoords", "useTangents", "capEnd", "capEnds")


class PrimitiveAssetAttributes(AbstractAttributes):
    """A built-in primitive asset (Magnum primitive) known by its handle, e.g. ``cubeSolid``.

    ``primitive_class`` is the Magnum class name (``cubeSolid`` -> ``Cube``); ``is_wireframe``
    tells the wireframe variants (rendered and collided as their solid surface in rigidsim).
    """

    FIELDS = PRIMITIVE_FIELDS

    def __init__(self, handle: str = "") -> None:
        super().__init__(handle)
        prefix, _, rest = handle.partition("_")
        tokens = rest.split("_") if rest else []
        params = {key: value for key, value in zip(tokens[0::2], tokens[1::2], strict=False)}
        object.__setattr__(self, "_prefix", prefix)
        object.__setattr__(self, "_params", params)

    # -- construction parameters (Habitat's names; each is one ``key_value`` of the handle) --
    def _param(self, key: str, kind: type) -> Any:
        text = self._params.get(key)
        if text is None:
            raise AttributeError(f"{self._prefix} templates have no {key!r} parameter")
        if kind is bool:
            return text == "true"
        return kind(float(text)) if kind is int else kind(text)

    def _set_param(self, key: str, value: Any, kind: type) -> None:
        if key not in self._params:
            raise AttributeError(f"{self._prefix} templates have no {key!r} parameter")
        if kind is bool:
            self._params[key] = "true" if _validate(key, "bool", value) else "false"
        elif kind is int:
            self._params[key] = str(_validate(key, "int", value))
        else:
            self._params[key] = f"{_validate(key, 'positive', value):g}"

    num_segments = property(
        lambda self: self._param("segments", int),
        lambda self, v: self._set_param("segments", v, int),
    )
    num_rings = property(
        lambda self: self._param("rings", int), lambda self, v: self._set_param("rings", v, int)
    )
    half_length = property(
        lambda self: self._param("halfLen", float),
        lambda self, v: self._set_param("halfLen", v, float),
    )
    hemisphere_rings = property(
        lambda self: self._param("hemiRings", int),
        lambda self, v: self._set_param("hemiRings", v, int),
    )
    cylinder_rings = property(
        lambda self: self._param("cylRings", int),
        lambda self, v: self._set_param("cylRings", v, int),
    )
    subdivisions = property(
        lambda self: self._param("subdivs", int), lambda self, v: self._set_param("subdivs", v, int)
    )
    use_texture_coords = property(
        lambda self: self._param("useTexCoords", bool),
        lambda self, v: self._set_param("useTexCoords", v, bool),
    )
    use_tangents = property(
        lambda self: self._param("useTangents", bool),
        lambda self, v: self._set_param("useTangents", v, bool),
    )
    use_cap_end = property(
        lambda self: self._param("capEnd", bool), lambda self, v: self._set_param("capEnd", v, bool)
    )
    use_cap_ends = property(
        lambda self: self._param("capEnds", bool),
        lambda self, v: self._set_param("capEnds", v, bool),
    )

    def build_handle(self) -> str:
        """Rebuild the handle from the parameters (Habitat's ``build_handle``)."""
        pairs = "".join(f"_{key}_{value}" for key, value in self._params.items())
        self.handle = f"{self._prefix}{pairs}"
        return self.handle

    @property
    def is_valid_template(self) -> bool:
        """Whether Magnum can build the primitive (Habitat's rules): solid primitives need
        ``segments >= 3``, wireframes ``segments >= 4`` and a multiple of 4; rings and capsule
        rings ``>= 1``; UV spheres ``rings >= 2`` (even for wireframes); subdivisions >= 0."""
        p = {
            key: self._param(
                key, bool if key in _PRIMITIVE_FLAGS else (float if key == "halfLen" else int)
            )
            for key in self._params
        }
        wire = self.is_wireframe
        if "segments" in p:
            if wire and (p["segments"] < 4 or p["segments"] % 4):
                return False
            if not wire and p["segments"] < 3:
                return False
        minimum_rings = 2 if self._prefix.startswith("uvSphere") else 1
        if p.get("rings", minimum_rings) < minimum_rings:
            return False
        if wire and self._prefix.startswith("uvSphere") and p["rings"] % 2:
            return False
        if min(p.get("hemiRings", 1), p.get("cylRings", 1)) < 1 or p.get("subdivs", 0) < 0:
            return False
        return p.get("halfLen", 1.0) > 0.0

    @property
    def primitive_class(self) -> str:
        names = {
            "capsule3D": "Capsule3D",
            "cone": "Cone",
            "cube": "Cube",
            "cylinder": "Cylinder",
            "icosphere": "Icosphere",
            "uvSphere": "UVSphere",
        }
        for prefix, name in names.items():
            if self.handle.startswith(prefix):
                return name
        raise ValueError(f"not a primitive handle: {self.handle!r}")

    @property
    def is_wireframe(self) -> bool:
        return "Wireframe" in self._prefix

    @property
    def template_class(self) -> str:
        """Habitat's class key: ``CapsulePrimitiveAttributes``, ``CubePrimitiveAttributes``..."""
        return f"{self.primitive_class.removesuffix('3D')}PrimitiveAttributes"

    @property
    def prim_obj_class_name(self) -> str:
        """Habitat's name for the Magnum primitive class (``primitive_class``)."""
        return self.primitive_class
