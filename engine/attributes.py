"""Habitat's ``habitat_sim.attributes``: the template classes (defined in
:mod:`engine.templates`)."""

from engine.templates.attributes import (
    AbstractAttributes,
    AssetType,
    ObjectAttributes,
    PhysicsManagerAttributes,
    PrimitiveAssetAttributes,
    StageAttributes,
    check_inertia,
    checked_path,
    is_primitive_handle,
    read_json_object,
)

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
