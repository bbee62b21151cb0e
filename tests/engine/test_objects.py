"""The rigid-object API (docs/habitat_api.md, "Objects"), ported Habitat tests included."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine import mn
from engine.geo import Ray
from engine.physics import DeadObjectError, MotionType, RigidState
from engine.simulator import Configuration, Simulator, SimulatorConfiguration


def make_sim(scene="NONE"):
    return Simulator(Configuration(SimulatorConfiguration(scene_id=str(scene))))


@pytest.fixture
def sim():
    with make_sim() as simulator:
        yield simulator


def test_ids_handles_lookup_and_removal(sim):
    rom = sim.get_rigid_object_manager()
    first = rom.add_object_by_template_handle("cubeSolid")
    second = rom.add_object_by_template_handle("cubeSolid")
    ball = rom.add_object_by_template_handle("icosphereSolid_subdivs_1")
    assert (first.object_id, second.object_id, ball.object_id) == (1, 2, 3)  # stage is 0
    assert first.handle == "cubeSolid_:0000" and second.handle == "cubeSolid_:0001"
    assert rom.get_num_objects() == 3
    assert rom.get_object_handles("cube") == ["cubeSolid_:0000", "cubeSolid_:0001"]
    assert rom.get_object_handles("cube", contains=False) == ["icosphereSolid_subdivs_1_:0000"]
    assert rom.get_object_by_id(2) is second
    assert rom.get_object_by_handle("cubeSolid_:0000") is first
    assert set(rom.get_objects_by_handle_substring("Solid")) == set(rom.get_object_handles())
    rom.remove_object_by_handle("cubeSolid_:0000")
    assert not first.is_alive and rom.get_num_objects() == 2
    with pytest.raises(DeadObjectError):
        _ = first.translation
    with pytest.raises(DeadObjectError):
        first.translation = [0.0, 1.0, 0.0]
    # the counter continues after the largest one in use
    assert rom.add_object_by_template_handle("cubeSolid").handle == "cubeSolid_:0002"
    with pytest.raises(KeyError):
        rom.remove_object_by_id(99)
    rom.remove_all_objects()
    assert rom.get_num_objects() == 0 and not second.is_alive


def test_unknown_templates_return_none_with_a_warning(sim):
    rom = sim.get_rigid_object_manager()
    with pytest.warns(UserWarning, match="no_such_template"):
        assert rom.add_object_by_template_handle("no_such_template") is None
    with pytest.warns(UserWarning, match="12345"):
        assert rom.add_object_by_template_id(12345) is None


def test_translation_is_the_aabb_center_and_the_visual_node_is_offset(sim, test_assets):
    templates = sim.get_object_template_manager()
    template_id = templates.load_configs(str(test_assets / "objects" / "chair"))[0]
    chair = sim.get_rigid_object_manager().add_object_by_template_id(template_id)
    chair.translation = [1.0, 2.0, 3.0]
    visual = chair.visual_scene_nodes[0]
    # the meshes hang on the component nodes below the visual node (identity transforms)
    drawables = [d for node in chair.visual_scene_nodes for d in node.drawables]
    vertices = np.concatenate([np.asarray(d.mesh.vertices) for d in drawables])
    world = vertices @ visual.world_matrix()[:3, :3].T + visual.world_matrix()[:3, 3]
    center = 0.5 * (world.min(0) + world.max(0))
    np.testing.assert_allclose(center, [1.0, 2.0, 3.0], atol=1e-9)  # COM = AABB center
    np.testing.assert_allclose(chair.root_scene_node.translation, [1.0, 2.0, 3.0])
    aabb = chair.aabb
    np.testing.assert_allclose(np.asarray(aabb.min) + np.asarray(aabb.max), 0.0, atol=1e-9)


def test_property_copies_setters_and_motion_types(sim):
    rom = sim.get_rigid_object_manager()
    box = rom.add_object_by_template_handle("cubeSolid")
    box.translation = [0.0, 1.0, 0.0]
    box.translation += [0.0, 0.0, 0.01]  # goes through the setter
    np.testing.assert_allclose(box.translation, [0.0, 1.0, 0.01])
    vector = box.translation
    vector.x = 5.0
    assert box.translation.x == 0.0  # getters return copies
    box.rotation = mn.Quaternion.rotation(mn.Deg(90.0), [0.0, 1.0, 0.0])
    expected = np.eye(4)
    expected[:3, :3] = np.asarray(box.rotation.to_matrix())
    expected[:3, 3] = [0.0, 1.0, 0.01]
    np.testing.assert_allclose(np.asarray(box.transformation), expected, atol=1e-12)
    box.rigid_state = RigidState(mn.Quaternion(), [1.0, 2.0, 3.0])
    assert box.rigid_state.rotation == mn.Quaternion()
    np.testing.assert_allclose(box.rigid_state.translation, [1.0, 2.0, 3.0])
    box.motion_type = MotionType.STATIC
    box.translation = [9.0, 9.0, 9.0]  # STATIC ignores pose setters
    np.testing.assert_allclose(box.translation, [1.0, 2.0, 3.0])
    box.motion_type = MotionType.KINEMATIC
    box.linear_velocity = [1.0, 0.0, 0.0]  # stored, not simulated
    sim.step_physics(0.1)
    assert box.linear_velocity == mn.Vector3(1.0, 0.0, 0.0)
    np.testing.assert_allclose(box.translation, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="motion_type"):
        box.motion_type = MotionType.UNDEFINED
    assert MotionType.KINEMATIC.__doc__.startswith("Moved only")


def test_defaults_mass_inertia_and_user_attributes_are_copies(sim):
    templates = sim.get_object_template_manager()
    template = templates.get_template_by_handle("cubeSolid")
    template.get_user_config().set("color", "red")
    templates.register_template(template, "red_cube")
    box = sim.get_rigid_object_manager().add_object_by_template_handle("red_cube")
    assert box.mass == 1.0 and box.friction_coefficient == 0.5
    assert box.restitution_coefficient == pytest.approx(0.1)
    # 0.2 m cube of 1 kg: I = m (b^2 + c^2) / 3 with b = c = 0.1
    np.testing.assert_allclose(box.intertia_diagonal, [0.02 / 3] * 3)
    assert box.user_attributes.get("color") == "red"
    box.user_attributes.set("color", "blue")
    assert templates.get_template_by_handle("red_cube").get_user_config().get("color") == "red"
    assert box.creation_attributes.handle == "red_cube"
    assert box.velocity_control is box.velocity_control  # by reference


def test_forces_act_at_a_world_offset_and_impulses_are_instant(sim):
    sim.set_gravity([0.0, 0.0, 0.0])
    box = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    box.linear_damping = box.angular_damping = 0.0
    box.apply_impulse([0.0, 0.0, 1.0], [0.1, 0.0, 0.0])
    np.testing.assert_allclose(box.linear_velocity, [0.0, 0.0, 1.0])  # v = J / m
    # w = I^-1 (r x J) = (0, -0.1, 0) / (0.02 / 3)
    np.testing.assert_allclose(box.angular_velocity, [0.0, -15.0, 0.0])
    box.apply_impulse_torque([0.0, 0.02 / 3, 0.0])
    np.testing.assert_allclose(box.angular_velocity, [0.0, -14.0, 0.0])


def test_attached_agent_node_moves_with_the_object(sim):
    agent_node = sim.agents[0].scene_node
    rom = sim.get_rigid_object_manager()
    robot = rom.add_object_by_template_handle("cubeSolid", agent_node)
    assert robot.root_scene_node is agent_node
    robot.translation = [0.3, 0.4, 0.5]
    np.testing.assert_allclose(agent_node.translation, [0.3, 0.4, 0.5])
    robot.motion_type = MotionType.KINEMATIC
    agent_node.translation = [1.0, 0.0, 0.0]  # the user moves the agent: read back
    sim.step_physics(1.0 / 60.0)
    np.testing.assert_allclose(robot.translation, [1.0, 0.0, 0.0])
    rom.remove_object_by_id(robot.object_id, delete_object_node=False)
    assert agent_node.parent is sim.get_active_scene_graph().get_root_node()


def test_reset_restores_creation_poses(sim):
    box = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
    sim.step_physics(0.5)
    assert box.translation[1] < -0.5
    sim.reset()
    assert sim.get_world_time() == 0.0
    np.testing.assert_allclose(box.translation, [0.0, 0.0, 0.0])
    assert box.linear_velocity == mn.Vector3(0.0, 0.0, 0.0)


@pytest.mark.parametrize("kinematic", [False, True])
def test_habitat_velocity_control(test_assets, kinematic):
    """Port of Habitat's ``test_velocity_control`` (same tolerances)."""
    with make_sim() as sim:
        sim.set_gravity([0.0, 0.0, 0.0])
        templates = sim.get_object_template_manager()
        ids = templates.load_configs(str(test_assets / "objects" / "nested_box"))
        template = templates.get_template_by_id(ids[0])
        template.linear_damping = 0.0
        template.angular_damping = 0.0
        templates.register_template(template)
        box = sim.get_rigid_object_manager().add_object_by_template_handle(template.handle)
        if kinematic:
            box.motion_type = MotionType.KINEMATIC
        vc = box.velocity_control
        vc.linear_velocity = [1.0, 0.0, 0.0]
        vc.angular_velocity = [0.0, 1.0, 0.0]
        vc.controlling_lin_vel = vc.controlling_ang_vel = True
        while sim.get_world_time() < 1.0:
            sim.step_physics(0.00416)
        np.testing.assert_allclose(
            box.translation, sim.get_world_time() * np.array([1, 0, 0.0]), atol=0.01
        )
        truth = mn.Quaternion((0.0, 0.480551, 0.0), 0.876967)
        assert _angle(truth, box.rotation) < 0.005
        sim.reset()
        vc.lin_vel_is_local = vc.ang_vel_is_local = True
        vc.linear_velocity = [0.0, 0.0, -math.pi]
        vc.angular_velocity = [math.pi * 2.0, 0.0, 0.0]
        box.translation = [0.0, 0.0, 0.0]
        box.rotation = mn.Quaternion()
        while sim.get_world_time() < 0.5:
            sim.step_physics(0.008)
        np.testing.assert_allclose(box.translation, [0.0, 1.0, 0.0], atol=0.07)
        assert _angle(mn.Quaternion((1.0, 0.0, 0.0), 0.0), box.rotation) < 0.05


def _angle(q1, q2) -> float:
    """Magnum's ``math.angle``: 2 acos(|q1 . q2|)."""
    return 2.0 * math.acos(min(1.0, abs(q1.dot(q2))))


def test_habitat_discrete_contact_test_sequence(test_assets):
    """Port of Habitat's ``testDiscreteContactTest`` on plane.glb with transform_box.glb."""
    with make_sim(test_assets / "scenes" / "plane.glb") as sim:
        templates = sim.get_object_template_manager()
        template = templates.create_new_template(str(test_assets / "objects" / "transform_box.glb"))
        template.render_asset_handle = str(test_assets / "objects" / "transform_box.glb")
        template.margin = 0.0
        templates.register_template(template)
        rom = sim.get_rigid_object_manager()
        box0 = rom.add_object_by_template_handle(template.handle)
        box1 = rom.add_object_by_template_handle(template.handle)
        box0.translation = [0.0, 1.1, 0.0]  # 2 m boxes, 0.1 above the plane, 0.2 apart
        box1.translation = [2.2, 1.1, 0.0]
        assert not box0.contact_test() and not box1.contact_test()
        box0.translation = [0.0, 0.9, 0.0]  # into the floor
        assert box0.contact_test() and not box1.contact_test()
        box0.motion_type = MotionType.STATIC
        assert not box0.contact_test()  # STATIC vs STATIC stage
        box0.motion_type = MotionType.KINEMATIC
        assert not box0.contact_test()
        box0.motion_type = MotionType.DYNAMIC
        world = sim.get_physics_world()
        assert world.get_stage_is_collidable()
        world.set_stage_is_collidable(False)
        assert not box0.contact_test()
        box0.translation = [1.1, 1.1, 0.0]  # into box 1
        assert box0.contact_test() and box1.contact_test()
        box0.motion_type = MotionType.STATIC
        assert box0.contact_test() and box1.contact_test()
        box1.motion_type = MotionType.STATIC
        assert not box0.contact_test() and not box1.contact_test()
        box0.motion_type = MotionType.KINEMATIC
        assert not box0.contact_test() and not box1.contact_test()
        box1.motion_type = MotionType.KINEMATIC
        assert not box0.contact_test() and not box1.contact_test()
        box0.motion_type = MotionType.DYNAMIC
        assert box0.contact_test() and box1.contact_test()
        box0.collidable = False
        assert not box0.collidable
        assert not box0.contact_test() and not box1.contact_test()


def test_ray_cast_hits_a_cube_and_the_stage(test_assets):
    with make_sim(test_assets / "scenes" / "plane.glb") as sim:
        cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
        cube.translation = [2.0, 0.5, 2.0]
        cube.motion_type = MotionType.STATIC
        results = sim.cast_ray(Ray([0.0, 0.5, 2.0], [1.0, 0.0, 0.0]))
        assert results.has_hits()
        hit = results.hits[0]
        assert hit.object_id == cube.object_id
        np.testing.assert_allclose(hit.point, [1.9, 0.5, 2.0], atol=1e-9)  # 0.2 m cube face
        np.testing.assert_allclose(hit.normal, [-1.0, 0.0, 0.0], atol=1e-9)
        assert hit.ray_distance == pytest.approx(1.9)
        down = sim.cast_ray(Ray([0.5, 3.0, 0.5], [0.0, -2.0, 0.0]))  # |d| = 2: half distances
        assert down.hits[0].object_id == 0  # the stage
        assert down.hits[0].ray_distance == pytest.approx(1.5)
        hits = sim.cast_ray(Ray([2.0, 3.0, 2.0], [0.0, -1.0, 0.0])).hits
        # nearest first: the cube's top face (a convex body reports one hit), then the stage
        assert [h.object_id for h in hits] == [cube.object_id, 0]
        np.testing.assert_allclose([h.ray_distance for h in hits], [2.4, 3.0], atol=1e-9)


@pytest.mark.parametrize("remove_index", [1, 0])
def test_habitat_removing_a_sleeping_support_wakes_the_stack(sim, remove_index):
    """Port of Habitat's ``testRemoveSleepingSupport`` (stack of 4 cubes, bottom STATIC)."""
    rom = sim.get_rigid_object_manager()
    base = np.array([0.21964, 1.29183, -0.0897472])
    cubes = []
    for i in range(4):
        cube = rom.add_object_by_template_handle("cubeSolid")
        cube.translation = base + [0.0, 0.2 * i, 0.0]
        cubes.append(cube)
    cubes[0].motion_type = MotionType.STATIC
    while sim.get_world_time() < 4.0:
        sim.step_physics(0.1)
    assert not any(c.awake for c in cubes)
    assert sim.get_physics_num_active_contact_points() == 0
    rom.remove_object_by_id(cubes[remove_index].object_id)
    rest = [c for c in cubes if c.is_alive and c.motion_type == MotionType.DYNAMIC]
    assert rest and all(c.awake for c in rest)
    sim.step_physics(0.1)
    assert sim.get_physics_num_active_contact_points() > 0 or remove_index == 0


def test_a_resting_cube_reports_four_contact_points_with_its_weight(test_assets):
    with make_sim(test_assets / "scenes" / "plane.glb") as sim:
        cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
        cube.translation = [0.0, 0.5, 0.0]
        sim.step_physics(1.0)
        points = sim.get_physics_contact_points()
        assert len(points) == 4
        assert sim.get_physics_num_active_contact_points() == 0  # the cube fell asleep
        cube.awake = True
        assert sim.get_physics_num_active_contact_points() == 4
        assert all(p.object_id_a == 0 and p.object_id_b == cube.object_id for p in points)
        # the normal forces carry the weight m g (1 kg): 5 % covers damping and the slop
        total = sum(p.normal_force for p in points)
        assert total == pytest.approx(9.8, rel=0.05)
        for p in points:  # Bullet's convention: the normal on B points from B to A (down)
            np.testing.assert_allclose(p.contact_normal_on_b_in_ws, [0.0, -1.0, 0.0], atol=1e-9)
