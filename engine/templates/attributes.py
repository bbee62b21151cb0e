"""Templates: the attributes objects, stages and the physics world are created from.

Mirrors ``habitat_sim.attributes``. A template is a bag of typed fields with Habitat's names
and defaults, read from a ``*.object_config.json`` / ``*.stage_config.json`` /
``*.physics_config.json`` file and editable in Python before it is registered with its
manager. Each field is declared once in a table (:data:`OBJECT_FIELDS` ...) giving its JSON
key, its kind (``float``, ``vec3``, ``bool``, ...) and its default; the JSON reader and the
property setters share one validator, so bad values raise the same clear ``ValueError``.

The shared machinery lives in :mod:`engine.templates.base` (fields, validator, JSON loading),
file checks in :mod:`engine.templates.config_json`, primitive templates in
:mod:`engine.templates.primitive_attributes`; every name stays importable from here.

Conventions: asset paths in a config are relative to the config file; they are stored as
absolute paths unless they name a built-in primitive (``cubeSolid``...). JSON quaternions are
``[w, x, y, z]``; vectors are ``[x, y, z]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from engine.core.named_enum import NamedIntEnum
from engine.scene.primitives import is_primitive_handle
from engine.templates.base import AbstractAttributes, Field, check_inertia, validate
from engine.templates.config_json import checked_path, read_json_object
from engine.templates.primitive_attributes import PrimitiveAssetAttributes

__all__ = [
    "AbstractAttributes",
    "AssetType",
    "ObjectAttributes",
    "PhysicsManagerAttributes",
    "PrimitiveAssetAttributes",
    "StageAttributes",
    "check_inertia",
    "checked_path",
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
    "timestep": Field("timestep", "timestep", 0.008),
    "gravity": Field("gravity", "vec3", np.array([0.0, -9.8, 0.0])),
    "friction_coefficient": Field("friction_coefficient", "nonnegative", 0.4),
    "restitution_coefficient": Field("restitution_coefficient", "restitution", 0.1),
    "max_substeps": Field("max_substeps", "int", 10),
}


def _asset_type(handle: str) -> AssetType:
    """Habitat's asset type of ``handle``: a built-in primitive or (as Habitat reports a mesh
    file) ``UNKNOWN``."""
    return AssetType.PRIMITIVE if is_primitive_handle(handle) else AssetType.UNKNOWN


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
    def _collision_handle(self) -> str:
        """The handle the body collides with: the collision asset, the render asset when empty."""
        return self.collision_asset_handle or self.render_asset_handle

    @property
    def render_asset_type(self) -> AssetType:
        """``PRIMITIVE`` for a built-in primitive, else ``UNKNOWN`` (a mesh file), as Habitat."""
        return _asset_type(self.render_asset_handle)

    @property
    def collision_asset_type(self) -> AssetType:
        """As ``render_asset_type``, for the handle collided with."""
        return _asset_type(self._collision_handle)

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
        if validate("compute_COM_from_shape", "bool", value):
            self._explicit.discard("com")
        else:
            self._explicit.add("com")

    @property
    def render_asset_is_primitive(self) -> bool:
        return is_primitive_handle(self.render_asset_handle)

    @property
    def collision_asset_is_primitive(self) -> bool:
        return is_primitive_handle(self._collision_handle)

    @property
    def use_mesh_for_collision(self) -> bool:
        return not self.bounding_box_collisions


class StageAttributes(_AssetPaths, AbstractAttributes):
    """A stage template (``*.stage_config.json``), Habitat's ``StageAttributes``.

    A bare ``.glb`` with no config beside it is Z-up: see
    :meth:`engine.templates.managers.StageAttributesManager.create_template_for_asset`.
    """

    FIELDS = STAGE_FIELDS


class PhysicsManagerAttributes(AbstractAttributes):
    """The physics world's settings (``*.physics_config.json``)."""

    FIELDS = PHYSICS_FIELDS
