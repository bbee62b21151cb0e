"""Issue 11, item 7: templates, object wrappers and simulator calls as Habitat has them.

Ported in our own words from Habitat-sim's ``tests/test_attributes_managers.py`` (the general
register / lock / remove flow, blank templates, asset defaults) and the object API of
``tests/test_physics.py`` (collision groups, ``is_articulated``, AABBs).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.attributes import ObjectAttributes
from engine.attributes_managers import AssetAttributesManager, ObjectAttributesManager
from engine.geo import Ray
from engine.physics import (
    CollisionGroupHelper,
    CollisionGroups,
    MotionType,
    PhysicsSimulationLibrary,
)
from engine.simulator import Configuration, Simulator, SimulatorConfiguration


@pytest.fixture
def sim():
    with Simulator(Configuration(SimulatorConfiguration(scene_id="NONE"))) as simulator:
        yield simulator


@pytest.fixture(autouse=True)
def default_collision_masks():
    yield
    CollisionGroupHelper.reset()  # the masks are global, as in Habitat


# -- template managers ---------------------------------------------------------------------------
def test_register_writes_id_and_handle_into_the_callers_template():
    manager = ObjectAttributesManager()
    count = manager.get_num_templates()
    template = manager.create_new_template("new template", False)
    template.get_user_config().set("test_key", "new_template_test")
    template.render_asset_handle = "cubeSolid"
    assert template.template_id == -1
    new_id = manager.register_template(template, "new template")
    assert template.template_id == new_id != -1  # Habitat shares the template with the library
    stored = manager.get_template_by_handle("new template")
    assert (stored.handle, stored.template_id) == (template.handle, template.template_id)
    assert stored.get_user_config().get("test_key") == "new_template_test"
    # registering under another handle renames the caller's template too
    other_id = manager.register_template(template, "renamed")
    assert template.handle == "renamed" and template.template_id == other_id != new_id
    removed = manager.remove_template_by_handle("renamed")
    assert removed.template_id == other_id
    manager.remove_template_by_handle("new template")
    assert manager.get_num_templates() == count


def test_lock_by_substring_and_remove_templates_by_str():
    manager = ObjectAttributesManager()
    count = manager.get_num_templates()
    base = manager.get_template_by_handle("cubeSolid")
    for i in range(10):
        assert manager.register_template(base, f"new_template_{i}") != -1
    found = manager.get_templates_by_handle_substring("new_template_")
    assert len(found) == 10 and all(k == v.handle for k, v in found.items())
    locked = manager.set_lock_by_substring(True, "new_template_", True)
    assert len(locked) == 10
    assert manager.remove_templates_by_str("new_template_", True) == []  # locked: kept
    unlocked = manager.set_lock_by_substring(False, "new_template_", True)
    assert sorted(unlocked) == sorted(locked)
    assert len(manager.remove_templates_by_str("new_template_", True)) == 10
    assert manager.get_num_templates() == count
    with pytest.warns(UserWarning):
        assert manager.get_template_id_by_handle("new_template_0") == -1
    with pytest.warns(UserWarning):
        assert manager.remove_template_by_handle("new_template_0") is None


def test_load_configs_save_as_defaults_makes_templates_undeletable(test_assets):
    manager = ObjectAttributesManager()
    ids = manager.load_configs(str(test_assets / "objects"), True)
    assert ids and all(i >= 0 for i in ids)
    handle = manager.get_template_handle_by_id(ids[0])
    assert handle in manager.get_undeletable_handles()
    with pytest.warns(UserWarning):
        assert manager.remove_template_by_handle(handle) is None
    other = ObjectAttributesManager()
    other.load_configs(str(test_assets / "objects"))  # save_as_defaults=False by default
    assert other.remove_template_by_handle(handle) is not None


def test_asset_manager_default_primitive_templates():
    assets = AssetAttributesManager()
    getters = {
        "Capsule3D": assets.get_default_capsule_template,
        "Cone": assets.get_default_cone_template,
        "Cube": assets.get_default_cube_template,
        "Cylinder": assets.get_default_cylinder_template,
        "Icosphere": assets.get_default_icosphere_template,
        "UVSphere": assets.get_default_UVsphere_template,
    }
    for primitive_class, getter in getters.items():
        for wireframe in (False, True):
            template = getter(wireframe)
            assert template.primitive_class == primitive_class
            assert template.is_wireframe == wireframe
            assert assets.get_library_has_handle(template.handle)
    assert assets.get_default_cube_template(False).handle == "cubeSolid"


def test_rolling_and_spinning_friction_are_template_fields(tmp_path, sim):
    config = tmp_path / "ball.object_config.json"
    config.write_text(
        json.dumps(
            {
                "render_asset": "icosphereSolid_subdivs_1",
                "rolling_friction_coefficient": 0.02,
                "spinning_friction_coefficient": 0.01,
            }
        )
    )
    manager = sim.get_object_template_manager()
    template = manager.get_template_by_id(manager.load_configs(str(config))[0])
    assert template.rolling_friction_coefficient == pytest.approx(0.02)
    assert template.spinning_friction_coefficient == pytest.approx(0.01)
    assert ObjectAttributes("x").rolling_friction_coefficient == 0.0  # Habitat's default
    ball = sim.get_rigid_object_manager().add_object_by_template_handle(template.handle)
    assert ball.rolling_friction_coefficient == pytest.approx(0.02)
    ball.spinning_friction_coefficient = 0.5
    assert ball.spinning_friction_coefficient == 0.5
    with pytest.raises(ValueError):
        ball.rolling_friction_coefficient = -1.0


def test_unknown_attributes_raise_and_name_the_closest_field(sim):
    template = ObjectAttributes("t")
    with pytest.raises(AttributeError, match="friction_coefficient"):
        template.frictoin_coefficient = 0.3
    with pytest.raises(AttributeError, match="mass"):
        _ = template.mas
    cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    with pytest.raises(AttributeError, match="'friction_coefficient'"):
        cube.frction_coefficient = 0.3
    with pytest.raises(AttributeError, match="translation"):
        cube.translaton = [0.0, 1.0, 0.0]
    with pytest.raises(AttributeError, match="linear_velocity"):
        _ = cube.linear_velocty
    cube.friction_coefficient = 0.3  # real fields still work
    assert cube.friction_coefficient == 0.3


# -- object wrappers and simulator ---------------------------------------------------------------
def test_is_articulated_collision_shape_aabb_and_cumulative_bb(sim):
    cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    assert cube.is_articulated is False
    box = mn.Range3D((-0.1, -0.1, -0.1), (0.1, 0.1, 0.1))  # unit cube primitive at scale 0.1
    assert cube.collision_shape_aabb == box
    assert cube.aabb == box
    cube.translation = [3.0, 2.0, 1.0]
    cube.rotation = mn.Quaternion.rotation(mn.Deg(30.0), mn.Vector3.y_axis())
    assert cube.root_scene_node.cumulative_bb == box  # in the node's own frame
    assert sim.get_active_scene_graph().get_root_node().cumulative_bb.max.x > 3.0
    assert habitat_sim.SceneNode().cumulative_bb == mn.Range3D()


def test_physics_simulation_library():
    config = SimulatorConfiguration(scene_id="NONE")
    with Simulator(Configuration(config)) as simulator:
        assert simulator.get_physics_simulation_library() == PhysicsSimulationLibrary.Bullet
    config.enable_physics = False
    with Simulator(Configuration(config)) as simulator:
        assert simulator.get_physics_simulation_library() == PhysicsSimulationLibrary.NoPhysics


# -- collision groups ----------------------------------------------------------------------------
def test_default_group_masks_are_habitats():
    everything_but_noncollidable = CollisionGroupHelper.get_mask_for_group(CollisionGroups.Default)
    assert not everything_but_noncollidable & CollisionGroups.Noncollidable
    assert everything_but_noncollidable & CollisionGroups.Dynamic
    static_mask = CollisionGroupHelper.get_mask_for_group(CollisionGroups.Static)
    assert not static_mask & (CollisionGroups.Static | CollisionGroups.Kinematic)
    assert static_mask & CollisionGroups.Dynamic
    assert CollisionGroupHelper.get_mask_for_group(CollisionGroups.Noncollidable) == 0
    assert CollisionGroupHelper.get_group("UserGroup3") == CollisionGroups.UserGroup3
    assert CollisionGroupHelper.get_group_name(CollisionGroups.Robot) == "Robot"
    with pytest.raises(ValueError):
        CollisionGroupHelper.get_group("NoSuchGroup")


def _floor_and_box(sim):
    manager = sim.get_object_template_manager()
    floor_template = manager.get_template_by_handle("cubeSolid")
    floor_template.scale = [2.0, 0.1, 2.0]  # a 4 m x 0.2 m x 4 m slab
    manager.register_template(floor_template, "floor_slab")
    rom = sim.get_rigid_object_manager()
    floor = rom.add_object_by_template_handle("floor_slab")
    floor.motion_type = MotionType.STATIC
    box = rom.add_object_by_template_handle("cubeSolid")
    box.translation = [0.0, 0.5, 0.0]
    return floor, box


def test_groups_and_masks_decide_whether_bodies_collide(sim):
    floor, box = _floor_and_box(sim)
    sim.step_physics(1.0)
    assert box.translation.y == pytest.approx(0.2, abs=0.01)  # resting on the slab (top 0.1)
    box.translation = [0.0, 0.5, 0.0]
    box.linear_velocity = [0.0, 0.0, 0.0]
    box.override_collision_group(CollisionGroups.Noncollidable)
    assert box.collision_group == CollisionGroups.Noncollidable
    sim.step_physics(1.0)
    assert box.translation.y < -1.0  # falls through the slab


def test_user_groups_that_do_not_interact_pass_through(sim):
    floor, box = _floor_and_box(sim)
    CollisionGroupHelper.set_group_interacts_with(
        CollisionGroups.UserGroup1, CollisionGroups.UserGroup2, False
    )
    floor.override_collision_group(CollisionGroups.UserGroup1)  # copies the group's mask
    box.override_collision_group(CollisionGroups.UserGroup2)
    sim.step_physics(1.0)
    assert box.translation.y < -1.0
    CollisionGroupHelper.set_group_interacts_with(
        CollisionGroups.UserGroup1, CollisionGroups.UserGroup2, True
    )
    floor.override_collision_group(CollisionGroups.UserGroup1)  # take the new masks
    box.override_collision_group(CollisionGroups.UserGroup2)
    box.translation = [0.0, 0.5, 0.0]
    box.linear_velocity = [0.0, 0.0, 0.0]
    sim.step_physics(1.0)
    assert box.translation.y == pytest.approx(0.2, abs=0.01)


def test_ray_casts_and_contact_tests_honour_groups(sim):
    floor, box = _floor_and_box(sim)
    ray = Ray(np.array([0.0, 3.0, 0.0]), np.array([0.0, -1.0, 0.0]))
    assert [hit.object_id for hit in sim.cast_ray(ray).hits] == [box.object_id, floor.object_id]
    box.translation = [0.0, 0.15, 0.0]  # overlapping the slab
    assert box.contact_test()
    box.override_collision_group(CollisionGroups.Noncollidable)
    assert [hit.object_id for hit in sim.cast_ray(ray).hits] == [floor.object_id]
    assert not box.contact_test()
    # a mask without Default hides a group from rays (Habitat's rays are in Default)
    CollisionGroupHelper.set_mask_for_group(
        CollisionGroups.UserGroup4, int(CollisionGroups.Dynamic)
    )
    floor.override_collision_group(CollisionGroups.UserGroup4)
    assert sim.cast_ray(ray).hits == []


# -- issue 11 item 9: a kinematic object's rotation keeps its sign ------------------------------
@pytest.mark.parametrize("drive", ["velocity_control", "rotation", "node", "transformation"])
def test_kinematic_rotation_keeps_its_sign_from_step_to_step(sim, drive):
    cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    cube.motion_type = MotionType.KINEMATIC
    if drive == "velocity_control":
        cube.velocity_control.controlling_ang_vel = True
        cube.velocity_control.angular_velocity = [0.0, 3.0, 0.5]
    previous, previous_node = cube.rotation, cube.root_scene_node.rotation
    angle = 0.0
    for _ in range(300):  # several full turns: every sign ambiguity is crossed
        angle += 0.05
        turn = mn.Quaternion.rotation(mn.Rad(angle), [0.0, 1.0, 0.0])
        if drive == "rotation":
            cube.rotation = mn.Quaternion.rotation(mn.Rad(0.05), [0.0, 1.0, 0.0]) * cube.rotation
        elif drive == "node":
            cube.root_scene_node.rotate_y(mn.Rad(0.05))
        elif drive == "transformation":
            cube.transformation = mn.Matrix4.from_(turn.to_matrix(), [0.0, 0.0, 0.0])
        sim.step_physics(1.0 / 60.0)
        current, node = cube.rotation, cube.root_scene_node.rotation
        assert current.dot(previous) > 0.0 and node.dot(previous_node) > 0.0
        previous, previous_node = current, node


def test_habitats_collision_group_sequence(sim):
    """The sequence of Habitat's ``test_collision_groups`` (rigid objects only)."""
    cgh, cg = CollisionGroupHelper, CollisionGroups
    assert cgh.get_group_name(cg.UserGroup1) == "UserGroup1"
    assert cgh.set_group_name(cg.UserGroup1, "my_custom_group_1")
    assert cgh.get_group("my_custom_group_1") == cg.UserGroup1
    assert cgh.get_mask_for_group(cg.UserGroup1) == cgh.get_mask_for_group("my_custom_group_1")
    cgh.set_mask_for_group(cg.UserGroup1, cg.Static | cg.Kinematic)
    rom = sim.get_rigid_object_manager()
    cube1 = rom.add_object_by_template_handle("cubeSolid")
    cube2 = rom.add_object_by_template_handle("cubeSolid")
    cube1.translation = [1.0, 0.0, 4.5]
    cube2.translation = [3.0, 0.0, 4.5]
    assert not cube1.contact_test()
    cube2.translation = [1.1, 0.0, 4.6]
    assert cube1.contact_test() and cube2.contact_test()
    cube1.override_collision_group(cg.UserGroup1)  # STATIC | KINEMATIC only
    assert not cube1.contact_test() and not cube2.contact_test()
    # a mask edit applies once the group is set again
    cgh.set_mask_for_group(cg.UserGroup1, cg.Static | cg.Kinematic | cg.UserGroup2)
    assert not cube1.contact_test()
    cube1.override_collision_group(cg.UserGroup1)
    cube2.override_collision_group(cg.UserGroup2)
    assert cube1.contact_test() and cube2.contact_test()
    cube2.motion_type = MotionType.DYNAMIC  # the same type: the group stays
    assert cube1.contact_test()
    cube2.motion_type = MotionType.KINEMATIC  # a new type resets the group
    cube2.motion_type = MotionType.DYNAMIC
    assert not cube1.contact_test() and not cube2.contact_test()
    cube2.motion_type = MotionType.KINEMATIC  # UserGroup1 interacts with Kinematic
    assert cube1.contact_test() and cube2.contact_test()
    cgh.set_group_interacts_with(cg.UserGroup1, cg.Kinematic, False)
    assert not cgh.get_mask_for_group(cg.UserGroup1) & cg.Kinematic
    cube1.override_collision_group(cg.UserGroup1)
    assert not cube1.contact_test() and not cube2.contact_test()
    cgh.set_group_interacts_with(cg.UserGroup1, cg.Kinematic, True)
    cube1.override_collision_group(cg.UserGroup1)
    assert cube1.contact_test() and cube2.contact_test()
    cube2.override_collision_group(cg.Noncollidable)
    assert not cube1.contact_test() and not cube2.contact_test()
    cube1.override_collision_group(cg.Noncollidable)
    assert not cube1.contact_test() and not cube2.contact_test()


@pytest.mark.parametrize(
    "getter, legal_solid",
    [
        ("get_default_capsule_template", 5),
        ("get_default_cone_template", 5),
        ("get_default_cylinder_template", 5),
        ("get_default_UVsphere_template", 5),
    ],
)
@pytest.mark.parametrize("wireframe", [False, True])
def test_primitive_asset_templates_modify_validate_and_register(getter, legal_solid, wireframe):
    """Habitat's ``perform_asset_attrib_mgr_tests``: legal 5 / illegal 0 segments for solid
    primitives, legal 64 / illegal 25 for wireframes (a multiple of 4 is needed)."""
    assets = AssetAttributesManager()
    count = assets.get_num_templates()
    template = getattr(assets, getter)(wireframe)
    old_handle = template.handle
    assert template.is_valid_template
    template.num_segments = 25 if wireframe else 0
    assert not template.is_valid_template
    with pytest.warns(UserWarning, match="not valid"):
        assert assets.register_template(template, "broken") == -1
    template.num_segments = 64 if wireframe else legal_solid
    assert template.is_valid_template
    new_handle = template.build_handle()
    assert new_handle != old_handle
    assets.register_template(template)
    assert assets.get_library_has_handle(new_handle) and assets.get_library_has_handle(old_handle)
    assert (
        assets.get_template_by_handle(old_handle).num_segments
        != assets.get_template_by_handle(new_handle).num_segments
    )
    assert assets.remove_template_by_handle(new_handle) is not None
    assert assets.get_num_templates() == count


def test_objects_use_the_modified_primitive(sim):
    assets = sim.get_asset_template_manager()
    cylinder = assets.get_default_cylinder_template(False)
    cylinder.half_length = 2.0
    cylinder.num_segments = 16
    handle = cylinder.build_handle()
    assets.register_template(cylinder)
    objects = sim.get_object_template_manager()
    template = objects.create_new_template("tall_cylinder")
    template.render_asset_handle = handle
    template.collision_asset_handle = handle
    objects.register_template(template)
    tall = sim.get_rigid_object_manager().add_object_by_template_handle("tall_cylinder")
    assert tall.aabb.size_y() == pytest.approx(4.0)  # radius 1, half length 2
    assert tall.collision_shape_aabb.size_y() == pytest.approx(4.0)
