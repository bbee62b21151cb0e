"""Habitat's ``habitat_sim.attributes_managers``: the template managers (defined in
:mod:`engine.templates.managers`)."""

from engine.templates.managers import (
    PRIMITIVE_ASSET_HANDLES,
    AssetAttributesManager,
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)

__all__ = [
    "PRIMITIVE_ASSET_HANDLES",
    "AssetAttributesManager",
    "ObjectAttributesManager",
    "PhysicsAttributesManager",
    "StageAttributesManager",
]
