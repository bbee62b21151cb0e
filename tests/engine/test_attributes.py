"""Templates and their managers: Habitat's defaults, handles, copies, ids, locks, files."""

import json
from pathlib import Path

import numpy as np
import pytest

from engine.attributes import ObjectAttributes, PhysicsManagerAttributes, StageAttributes
from engine.attributes_managers import (
    PRIMITIVE_ASSET_HANDLES,
    AssetAttributesManager,
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)


def test_object_attributes_defaults_match_habitat():
    t = ObjectAttributes("x")
    assert t.mass == 1.0 and t.margin == 0.04
    assert t.friction_coefficient == 0.5 and t.restitution_coefficient == 0.1
    assert t.linear_damping == 0.2 and t.angular_damping == 0.2
    assert t.scale == [1, 1, 1] and t.orient_up == [0, 1, 0] and t.orient_front == [0, 0, -1]
    assert t.units_to_meters == 1.0 and t.compute_COM_from_shape
    assert not t.bounding_box_collisions and not t.join_collision_meshes
    assert t.semantic_id == 0 and t.is_collidable


def test_physics_defaults_and_config_file(habitat_data):
    default = PhysicsAttributesManager().load(None)
    assert default.timestep == 0.008 and default.gravity == [0, -9.8, 0]
    assert default.friction_coefficient == 0.4 and default.restitution_coefficient == 0.1
    testing = PhysicsAttributesManager().load(habitat_data / "test_assets/testing.physics_config")
    assert testing.timestep == pytest.approx(0.0041666666)
    assert isinstance(testing, PhysicsManagerAttributes)


def test_twelve_primitive_templates_with_scale_point_one():
    manager = ObjectAttributesManager()
    assert manager.get_num_templates() == 12
    assert sorted(manager.get_synth_template_handles()) == sorted(PRIMITIVE_ASSET_HANDLES)
    cube = manager.get_template_by_handle("cubeSolid")
    assert cube.scale == [0.1, 0.1, 0.1] and cube.render_asset_is_primitive
    assets = AssetAttributesManager()
    assert assets.get_num_templates() == 12
    assert assets.get_default_template_handle("Icosphere") == "icosphereSolid_subdivs_1"
    with pytest.warns(UserWarning, match="locked"):  # the primitive defaults are undeletable
        assert manager.remove_template_by_handle("cubeSolid") is None
    assert manager.get_library_has_handle("cubeSolid")


def test_load_configs_folder_file_and_suffixless_path(test_assets):
    manager = ObjectAttributesManager()
    ids = manager.load_configs(test_assets / "objects")
    handles = manager.get_file_template_handles()
    assert len(ids) == len(handles) == 4
    assert all(Path(h).is_absolute() and h.endswith(".object_config.json") for h in handles)
    again = manager.load_configs(str(test_assets / "objects/sphere"))  # suffix appended
    sphere_handle = str(test_assets / "objects/sphere.object_config.json")
    assert again == [manager.get_template_id_by_handle(sphere_handle)]
    assert manager.get_num_templates() == 16  # re-loading keeps the id, adds nothing


def test_every_shared_object_config_reads_its_fields(test_assets):
    manager = ObjectAttributesManager()
    manager.load_configs(test_assets / "objects")
    donut = manager.get_template_by_handle(manager.get_template_handles("donut")[0])
    assert donut.mass == pytest.approx(0.038) and donut.margin == pytest.approx(0.03)
    assert donut.restitution_coefficient == pytest.approx(0.2) and donut.join_collision_meshes
    assert not donut.compute_COM_from_shape  # the file gives COM
    assert donut.render_asset_handle == str(test_assets / "objects/donut.glb")
    sphere = manager.get_template_by_handle(manager.get_template_handles("sphere")[0])
    assert sphere.collision_asset_handle == "icosphereSolid_subdivs_1"
    assert sphere.collision_asset_size == [0.25, 0.25, 0.25]
    chair = manager.get_template_by_handle(manager.get_template_handles("chair")[0])
    user = chair.get_user_config().get_subconfig("receptacle_aabb_chair_test")
    assert user.get("parent_object") == "chair"
    assert user.get_as_string("scale") == "[0.158802 0.11 0.19]"


def test_handles_search_is_case_insensitive_and_sorted():
    manager = ObjectAttributesManager()
    handles = manager.get_template_handles("CUBE")
    assert handles == ["cubeSolid", "cubeWireframe"]
    others = manager.get_template_handles("cube", contains=False)
    assert len(others) == 10 and others == sorted(others, key=str.lower)


def test_get_returns_copies_and_register_overwrites_keeping_id(test_assets):
    manager = ObjectAttributesManager()
    sphere_id = manager.load_configs(test_assets / "objects/sphere")[0]
    template = manager.get_template_by_id(sphere_id)
    template.scale = [0.5, 0.5, 0.5]
    assert manager.get_template_by_id(sphere_id).scale == [1, 1, 1]  # not registered yet
    assert manager.register_template(template) == sphere_id
    assert manager.get_template_by_id(sphere_id).scale == [0.5, 0.5, 0.5]
    new_id = manager.register_template(template, "my_sphere")
    assert new_id != sphere_id and manager.get_library_has_handle("my_sphere")


def test_lock_prevents_overwrite_and_removal(test_assets):
    manager = ObjectAttributesManager()
    sphere_id = manager.load_configs(test_assets / "objects/sphere")[0]
    handle = manager.get_template_handle_by_id(sphere_id)
    manager.set_template_lock(handle, True)
    edited = manager.get_template_by_id(sphere_id)
    edited.mass = 7.0
    with pytest.warns(UserWarning, match="locked"):  # Habitat: logs and returns -1 / None
        assert manager.register_template(edited) == -1
    with pytest.warns(UserWarning, match="locked"):
        assert manager.remove_template_by_handle(handle) is None
    assert manager.get_template_by_id(sphere_id).mass != 7.0
    manager.set_template_lock(handle, False)
    assert manager.remove_template_by_handle(handle).handle == handle
    assert not manager.get_library_has_handle(handle)


def test_stage_frames_bare_glb_is_z_up_and_configs_override(test_assets):
    stages = StageAttributesManager()
    plane = stages.create_template_for_asset(test_assets / "scenes/plane.glb")
    assert plane.orient_up == [0, 0, 1] and plane.orient_front == [0, 1, 0]
    floor = stages.create_template_for_asset(test_assets / "scenes/stage_floor1.glb")
    assert floor.orient_up == [0, 1, 0] and floor.scale == [2, 2, 2]
    assert floor.friction_coefficient == pytest.approx(0.3) and floor.margin == pytest.approx(0.03)
    room = stages.create_template_for_asset(test_assets / "scenes/simple_room.glb")
    assert room.orient_up == [0, 0, 1] and room.render_asset_handle.endswith("simple_room.glb")
    assert isinstance(room, StageAttributes)


def test_a_bare_mesh_stage_keeps_the_scene_path_as_given(test_assets, monkeypatch):
    """Habitat's ``get_stage_initialization_template().render_asset_fullpath`` equals the
    scene path the configuration gave, relative paths included."""
    monkeypatch.chdir(test_assets)
    plane = StageAttributesManager().create_template_for_asset("scenes/plane.glb")
    assert plane.render_asset_fullpath == "scenes/plane.glb" == plane.handle
    assert plane.orient_up == [0, 0, 1]


def test_bad_files_and_values_raise_clear_errors(tmp_path):
    manager = ObjectAttributesManager()
    with pytest.raises(FileNotFoundError):
        manager.load_configs(tmp_path / "missing")
    (tmp_path / "broken.object_config.json").write_text("{not json")
    with pytest.raises(ValueError, match="broken.object_config.json"):
        manager.load_configs(tmp_path)
    (tmp_path / "broken.object_config.json").write_text(json.dumps({"mass": -1}))
    with pytest.raises(ValueError, match="mass"):
        manager.load_configs(tmp_path)
    (tmp_path / "broken.object_config.json").write_text(json.dumps({"scale": [1, "a", 1]}))
    with pytest.raises(ValueError, match="scale"):
        manager.load_configs(tmp_path)
    assert manager.get_num_templates() == 12  # nothing half-registered
    template = ObjectAttributes("t")
    with pytest.raises(ValueError, match="mass"):
        template.mass = float("nan")
    with pytest.raises(ValueError):
        template.com = [np.inf, 0, 0]
    with pytest.raises(AttributeError):
        template.not_a_field = 3
    with pytest.warns(UserWarning, match="nope"):  # Habitat returns None (and logs)
        assert manager.get_template_by_handle("nope") is None
    with pytest.raises(TypeError):
        manager.register_template(StageAttributes("s"))


def test_nothing_registered_when_one_file_of_a_folder_is_bad(tmp_path):
    (tmp_path / "a.object_config.json").write_text(json.dumps({"mass": 2.0}))
    (tmp_path / "b.object_config.json").write_text(json.dumps({"mass": "heavy"}))
    manager = ObjectAttributesManager()
    with pytest.raises(ValueError, match="b.object_config.json"):
        manager.load_configs(tmp_path)
    assert manager.get_num_templates() == 12
