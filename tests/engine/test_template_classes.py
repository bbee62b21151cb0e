"""Template class keys, asset types, dirty paths and ``create_template`` (Habitat's
``ECCV_2020_Advanced_Features`` reads them to list a template's properties)."""

from __future__ import annotations

import pytest

from engine.attributes import (
    AssetType,
    ObjectAttributes,
    PhysicsManagerAttributes,
    StageAttributes,
)
from engine.attributes_managers import AssetAttributesManager, ObjectAttributesManager


def test_template_class_is_habitats_class_key():
    assert ObjectAttributes("a").template_class == "ObjectAttributes"
    assert StageAttributes("b").template_class == "StageAttributes"
    assert PhysicsManagerAttributes("c").template_class == "PhysicsManagerAttributes"
    assets = AssetAttributesManager()
    keys = {
        assets.get_default_capsule_template(False).template_class,
        assets.get_default_cone_template(True).template_class,
        assets.get_default_cube_template(False).template_class,
        assets.get_default_cylinder_template(False).template_class,
        assets.get_default_icosphere_template(False).template_class,
        assets.get_default_UVsphere_template(True).template_class,
    }
    assert keys == {
        "CapsulePrimitiveAttributes",
        "ConePrimitiveAttributes",
        "CubePrimitiveAttributes",
        "CylinderPrimitiveAttributes",
        "IcospherePrimitiveAttributes",
        "UVSpherePrimitiveAttributes",
    }
    with pytest.raises(AttributeError):
        ObjectAttributes("a").template_class = "StageAttributes"  # read only


def test_asset_types_and_dirty_paths():
    objects = ObjectAttributesManager()
    cube = objects.get_template_by_handle("cubeSolid")
    assert cube.render_asset_type == AssetType.PRIMITIVE == 4
    assert cube.collision_asset_type == AssetType.PRIMITIVE
    assert not cube.filenames_are_dirty
    cube.render_asset_handle = "/data/chair.glb"
    assert cube.render_asset_type == AssetType.UNKNOWN
    assert cube.collision_asset_type == AssetType.PRIMITIVE  # still the cube
    assert cube.filenames_are_dirty
    cube.mass = 3.0  # not a path
    objects.register_template(cube, "chair")
    assert not cube.filenames_are_dirty
    assert not objects.get_template_by_handle("chair").filenames_are_dirty
    assert str(AssetType.NAVMESH) == "AssetType.NAVMESH"


def test_create_template_from_a_custom_primitive_handle():
    assets = AssetAttributesManager()
    capsule = assets.get_default_capsule_template(False)
    capsule.hemisphere_rings = 6
    assets.register_template(capsule)
    handle = capsule.handle
    assert handle != "capsule3DSolid" and handle.startswith("capsule3DSolid_")
    objects = ObjectAttributesManager()
    template = objects.create_template(handle)
    assert template is not None and objects.get_library_has_handle(handle)
    assert template.render_asset_handle == handle == template.collision_asset_handle
    assert list(template.scale) == [0.1, 0.1, 0.1]
    unregistered = objects.create_template("cubeWireframe", register_template=False)
    assert unregistered is not None and unregistered.render_asset_type == AssetType.PRIMITIVE
    with pytest.warns(UserWarning, match="capsule3DSolid_oops"):
        assert objects.create_template("capsule3DSolid_oops") is None
