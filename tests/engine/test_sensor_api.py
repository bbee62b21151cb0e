"""Habitat's sensor API: spec defaults, the simulator's sensor wrappers, render_camera,
create/remove on any node, wide-angle sensors in a simulator, asynchronous rendering, and
per-object lights and semantic parts (after Habitat's simulator.py, sensor_wrapper.py,
SensorBindings.cpp and its semantic_id / lighting / async tutorials)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.gfx import NO_LIGHT_KEY

WALL_DEPTH = 2.9  # the wall's front face, seen from the sensor at z = 0


def make_sim(*specs, enable_physics=False):
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = "NONE"
    sim_cfg.enable_physics = enable_physics
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = list(specs)
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def camera(uuid, sensor_type=habitat_sim.SensorType.COLOR, resolution=(48, 64)):
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid, spec.sensor_type, spec.resolution = uuid, sensor_type, list(resolution)
    return spec


def add_wall(sim, semantic_id=5):
    """A static 4 x 4 x 0.2 m box centred 3 m ahead of the sensor (front face 2.9 m away)."""
    templates = sim.get_object_template_manager()
    template = templates.get_template_by_handle(templates.get_template_handles("cubeSolid")[0])
    template.scale = [2.0, 2.0, 0.1]
    template.semantic_id = semantic_id
    wall = sim.get_rigid_object_manager().add_object_by_template_id(
        templates.register_template(template, "wall")
    )
    wall.translation = [0.0, 1.5, -3.0]
    wall.motion_type = habitat_sim.physics.MotionType.STATIC
    return wall


# -- specs ---------------------------------------------------------------------------------
def test_spec_defaults_are_habitats():
    base = habitat_sim.SensorSpec()
    assert base.uuid == "" and base.sensor_type == habitat_sim.SensorType.NONE
    assert list(base.position) == [0.0, 1.5, 0.0] and base.noise_model == "None"
    spec = habitat_sim.CameraSensorSpec()
    assert spec.uuid == "rgba_camera"
    assert spec.sensor_type == habitat_sim.SensorType.COLOR
    assert spec.sensor_subtype == habitat_sim.SensorSubType.PINHOLE
    assert list(spec.resolution) == [128, 128] and spec.channels == 4
    assert (spec.hfov, spec.near, spec.far, spec.ortho_scale) == (90.0, 0.01, 1000.0, 0.1)
    assert spec.is_visual_sensor_spec() and not base.is_visual_sensor_spec()
    fisheye = habitat_sim.FisheyeSensorDoubleSphereSpec()
    assert (fisheye.uuid, fisheye.alpha, fisheye.xi) == ("fisheye", 0.59, -0.18)
    assert fisheye.sensor_subtype == habitat_sim.SensorSubType.FISHEYE
    assert fisheye.principal_point_offset is None and fisheye.cubemap_size is None
    equirect = habitat_sim.EquirectangularSensorSpec()
    assert equirect.uuid == "equirectangular"
    assert equirect.sensor_subtype == habitat_sim.SensorSubType.EQUIRECTANGULAR
    assert habitat_sim.CameraSensorSpec() == habitat_sim.CameraSensorSpec()
    with pytest.raises(AttributeError, match="resolution"):
        spec.resolutoin = [1, 1]  # type: ignore[attr-defined]


def test_bad_wide_angle_specs_name_the_field():
    fisheye = habitat_sim.FisheyeSensorDoubleSphereSpec()
    with pytest.raises(ValueError, match="focal_length"):
        fisheye.validate()  # Habitat has no default focal length
    fisheye.focal_length = [30.0, 30.0]
    fisheye.alpha = 1.5
    with pytest.raises(ValueError, match="alpha"):
        fisheye.validate()
    spec = habitat_sim.CameraSensorSpec()
    spec.sensor_subtype = habitat_sim.SensorSubType.FISHEYE
    with pytest.raises(ValueError, match="PINHOLE or ORTHOGRAPHIC"):
        spec.validate()


# -- wrappers, render_camera -----------------------------------------------------------------
def test_sim_sensors_are_wrappers_of_the_agents_sensor_objects():
    with make_sim(camera("rgb"), camera("depth", habitat_sim.SensorType.DEPTH)) as sim:
        assert list(sim.sensors) == ["rgb", "depth"] and sim._sensors is sim.sensors
        wrapper = sim._sensors["rgb"]
        assert wrapper._sensor_object is sim.agents[0].sensors["rgb"]
        assert wrapper.sensor_object is wrapper._sensor_object and wrapper.uuid == "rgb"
        assert wrapper.node is wrapper._sensor_object.node
        assert wrapper._sensor_object.specification() is wrapper.spec
        assert wrapper.node.parent is sim.agents[0].scene_node
        wrapper.draw_observation()
        image = wrapper.get_observation()
        assert image.shape == (48, 64, 4) and image.dtype == np.uint8
        sensor = wrapper._sensor_object
        sensor.node.translation = [0.0, 3.0, 0.0]
        sensor.set_transformation_from_spec()
        np.testing.assert_allclose(sensor.node.translation, [0.0, 1.5, 0.0])


def test_render_camera_projects_a_point_to_its_pixel_and_unprojects_rays():
    with make_sim(camera("rgb")) as sim:
        agent = sim.get_agent(0)
        state = agent.get_state()
        state.rotation = mn.Quaternion.rotation(mn.Deg(90), mn.Vector3.y_axis())
        agent.set_state(state)
        rc = sim._sensors["rgb"]._sensor_object.render_camera
        assert rc.viewport == mn.Vector2i(64, 48) and rc.node is sim._sensors["rgb"].node
        # camera point (0.5, 0.25, -2): fx = 32 px -> pixel (32 + 32 * 0.25, 24 - 32 * 0.125)
        point_world = rc.node.absolute_transformation().transform_point([0.5, 0.25, -2.0])
        ndc = rc.projection_matrix.transform_point(rc.camera_matrix.transform_point(point_world))
        pixel = ((ndc[0] + 1) / 2 * 64, (1 - ndc[1]) / 2 * 48)
        np.testing.assert_allclose(pixel, (40.0, 20.0), atol=1e-9)
        # the advanced-features tutorial's formula (projection_size()[0] = 2 tan 45 = 2)
        np.testing.assert_allclose(rc.projection_size(), (2.0, 1.5), atol=1e-12)
        # unproject: Habitat's integer pixel rule, the direction turned with the agent (+90 y)
        ray = rc.unproject(mn.Vector2i(48, 12))
        local = np.array([(2 * 48 / 64 - 1), (2 * (48 - 12 - 1) / 48 - 1) * 0.75, -1.0])
        expected = mn.Matrix4(rc.node.world_matrix()).transform_vector(local)
        np.testing.assert_allclose(ray.direction, expected / np.linalg.norm(expected), atol=1e-9)
        np.testing.assert_allclose(ray.origin, rc.node.absolute_translation, atol=1e-12)


def test_zoom_hfov_and_clip_setters_change_the_projection():
    with make_sim(camera("rgb")) as sim:
        sensor = sim._sensors["rgb"]._sensor_object
        p00 = sensor.render_camera.projection_matrix[0, 0]
        sensor.zoom(2.0)
        np.testing.assert_allclose(sensor.render_camera.projection_matrix[0, 0], 2 * p00)
        sensor.reset_zoom()
        sensor.fov = mn.Deg(60)
        assert sensor.hfov == mn.Deg(60)
        expected = 1.0 / math.tan(math.radians(30))
        np.testing.assert_allclose(sensor.render_camera.projection_matrix[0, 0], expected)
        sensor.far_plane_dist = 50.0
        assert sensor.far_plane_dist == 50.0 and sensor.specification().far == 50.0
        with pytest.raises(ValueError, match="near"):
            sensor.near_plane_dist = 60.0  # beyond far: refused, nothing changes
        assert sensor.near_plane_dist == 0.01


def test_create_sensor_on_a_static_node_and_on_an_object_then_remove_it():
    with make_sim(camera("rgb")) as sim:
        wall = add_wall(sim)
        node = sim.get_active_scene_graph().get_root_node().create_child()
        node.translation = [0.0, 0.0, 0.0]
        spec = camera("static_depth", habitat_sim.SensorType.DEPTH)
        wrapper = sim.create_sensor(spec, node)
        assert sim.get_sensor("static_depth") is wrapper and "static_depth" in sim.sensors
        assert "static_depth" not in sim.get_sensor_observations()  # not under the agent
        depth = sim.render_sensors([wrapper])["static_depth"]
        assert depth[24, 32] == pytest.approx(WALL_DEPTH, abs=1e-5)
        with pytest.raises(ValueError, match="already exists"):
            sim.create_sensor(spec, node)
        # a sensor on the wall's node moves with the wall
        on_wall = sim.create_sensor(camera("wall_cam"), wall.root_scene_node)
        wall.motion_type = habitat_sim.physics.MotionType.KINEMATIC  # STATIC ignores setters
        before = on_wall.node.absolute_translation
        wall.translation = wall.translation + mn.Vector3(1.0, 0.0, 0.0)
        np.testing.assert_allclose(on_wall.node.absolute_translation - before, [1, 0, 0])
        sim.remove_sensor("static_depth")
        assert "static_depth" not in sim.sensors and not node.subtree_sensors
        with pytest.raises(KeyError, match="static_depth"):
            sim.remove_sensor("static_depth")


def test_add_sensor_joins_the_agents_observations_and_config():
    with make_sim(camera("rgb")) as sim:
        spec = camera("extra", habitat_sim.SensorType.SEMANTIC)
        sim.add_sensor(spec)
        assert spec in sim.agents[0].agent_config.sensor_specifications
        assert set(sim.get_sensor_observations()) == {"rgb", "extra"}
        factory = habitat_sim.SensorFactory
        created = factory.create_sensors(sim.agents[0].scene_node, [camera("third")])
        assert created["third"] is sim.agents[0].sensors["third"]
        factory.delete_subtree_sensor(sim.agents[0].scene_node, "third")
        assert "third" not in sim.agents[0].sensors


# -- wide-angle sensors in the simulator -----------------------------------------------------
def wide_specs():
    specs = []
    for kind, suffix in (
        (habitat_sim.SensorType.DEPTH, "depth"),
        (habitat_sim.SensorType.SEMANTIC, "sem"),
    ):
        fisheye = habitat_sim.FisheyeSensorDoubleSphereSpec()
        fisheye.uuid, fisheye.sensor_type, fisheye.resolution = f"fisheye_{suffix}", kind, [64, 64]
        fisheye.focal_length = [20.0, 20.0]
        equirect = habitat_sim.EquirectangularSensorSpec()
        equirect.uuid, equirect.sensor_type, equirect.resolution = f"pano_{suffix}", kind, [32, 64]
        specs += [fisheye, equirect]
    return specs


def test_fisheye_and_panorama_see_the_wall_at_its_z_depth():
    with make_sim(camera("depth", habitat_sim.SensorType.DEPTH), *wide_specs()) as sim:
        add_wall(sim, semantic_id=5)
        obs = sim.get_sensor_observations()
        assert obs["fisheye_depth"].shape == (64, 64) and obs["fisheye_depth"].dtype == np.float32
        assert obs["pano_sem"].shape == (32, 64) and obs["pano_sem"].dtype == np.uint32
        for uuid in ("depth", "fisheye_depth"):  # the center looks straight at the wall
            assert obs[uuid][32 if uuid != "depth" else 24, 32] == pytest.approx(WALL_DEPTH, 1e-5)
        assert obs["pano_depth"][16, 32] == pytest.approx(WALL_DEPTH, 1e-5)
        assert obs["pano_depth"][16, 0] == 0.0  # behind: empty world
        assert obs["fisheye_sem"][32, 32] == 5 and obs["pano_sem"][16, 32] == 5
        assert obs["fisheye_depth"][0, 0] == 0.0  # outside the image circle


# -- asynchronous rendering ------------------------------------------------------------------
@pytest.mark.parametrize("path", ["worker", "thread", "plain"])
def test_async_render_returns_the_frame_before_the_physics_step(path):
    fisheye = wide_specs()[0]
    with make_sim(
        camera("depth", habitat_sim.SensorType.DEPTH), fisheye, enable_physics=True
    ) as sim:
        sim.get_renderer().processes = 1 if path == "worker" else 0
        sim._async_render.use_worker = path == "worker"
        sim._async_render.threaded = path == "thread"
        wall = add_wall(sim)
        wall.motion_type = habitat_sim.physics.MotionType.KINEMATIC
        wall.velocity_control.controlling_lin_vel = True
        wall.velocity_control.linear_velocity = [0.0, 0.0, 3.0]  # towards the camera
        expected = sim.get_sensor_observations()
        time_before = sim.get_world_time()
        sim.start_async_render_and_step_physics(1.0 / 60.0)
        assert sim.get_world_time() > time_before
        with pytest.raises(RuntimeError, match="already called"):
            sim.start_async_render_and_step_physics(1.0 / 60.0)
        with pytest.raises(RuntimeError, match="asynchronous render"):
            sim.get_sensor_observations()
        observed = sim.get_sensor_observations_async_finish()
        np.testing.assert_array_equal(observed["depth"], expected["depth"])
        np.testing.assert_array_equal(observed["fisheye_depth"], expected["fisheye_depth"])
        if path == "worker":  # rendered by the worker process while the physics stepped
            assert set(sim.get_renderer().last_places.values()) == {"worker"}
        after = sim.get_sensor_observations()["depth"]
        assert after[24, 32] < expected["depth"][24, 32]  # the wall moved closer meanwhile
        with pytest.raises(RuntimeError, match="before calling"):
            sim.get_sensor_observations_async_finish()


# -- per-object lights and semantic parts ----------------------------------------------------
def test_transform_box_visual_nodes_and_per_part_semantic_ids(test_assets):
    spec = camera("sem", habitat_sim.SensorType.SEMANTIC, (64, 64))
    with make_sim(spec) as sim:
        templates = sim.get_object_template_manager()
        template = templates.create_new_template("box")
        template.render_asset_handle = str(test_assets / "objects" / "transform_box.glb")
        template.scale = [0.2, 0.2, 0.2]
        template.semantic_id = 10
        box = sim.get_rigid_object_manager().add_object_by_template_id(
            templates.register_template(template, "box")
        )
        box.translation = [0.0, 1.5, -1.0]
        nodes = box.visual_scene_nodes
        # visual node, scale node, asset root, then the file's 9 nodes in glTF order
        assert len(nodes) == 12
        assert [n.name for n in nodes[3:]] == [
            "Light", "Camera", "-x", "+x", "+z", "-y", "+y", "orig(-z)", "Lamp",
        ]  # fmt: skip
        assert set(np.unique(sim.get_sensor_observations()["sem"])) == {0, 10}
        # each part its own id: the camera (on +Z of the box) sees the face on the file's +Z,
        # the node named "-y" (Blender's axis names, glTF translation (0, 0, 1))
        for index, node in enumerate(nodes):
            node.semantic_id = 20 + index
        image = sim.get_sensor_observations()["sem"]
        names = {20 + i: n.name for i, n in enumerate(nodes)}
        assert names[int(image[32, 32])] == "-y"
        assert {names[int(i)] for i in np.unique(image) if i} <= {
            "-y",
            "+y",
            "+z",
            "orig(-z)",
            "+x",
            "-x",
        }
        box.semantic_id = 4  # the object's id relabels every part
        assert set(np.unique(sim.get_sensor_observations()["sem"])) == {0, 4}


def test_object_light_setup_key_changes_its_shading():
    with make_sim(camera("rgb")) as sim:
        wall = add_wall(sim)
        lit = sim.get_sensor_observations()["rgb"][24, 32].copy()
        wall.set_light_setup(NO_LIGHT_KEY)  # flat: the material color as is
        flat = sim.get_sensor_observations()["rgb"][24, 32]
        assert not np.array_equal(lit, flat)
        assert all(d.light_setup_key == NO_LIGHT_KEY for d in wall.visual_drawables())
        with pytest.raises(TypeError, match="light_setup_key"):
            wall.set_light_setup(3)  # type: ignore[arg-type]


# -- debug lines -----------------------------------------------------------------------------
def test_debug_lines_appear_in_the_next_color_observation_only():
    with make_sim(camera("rgb"), camera("depth", habitat_sim.SensorType.DEPTH)) as sim:
        add_wall(sim)
        plain = sim.get_sensor_observations()
        lines = sim.get_debug_line_render()
        lines.set_line_width(3)
        # a red line 1 m in front of the sensor (at height 1.5), left to right
        lines.push_transform(mn.Matrix4.translation(mn.Vector3(0.0, 1.5, 0.0)))
        lines.draw_transformed_line(
            mn.Vector3(-0.3, 0.0, -1.0), mn.Vector3(0.3, 0.0, -1.0), mn.Color4(1, 0, 0, 1)
        )
        lines.pop_transform()
        drawn = sim.get_sensor_observations()
        np.testing.assert_array_equal(drawn["rgb"][24, 32], [255, 0, 0, 255])
        np.testing.assert_array_equal(drawn["depth"], plain["depth"])  # color only
        changed = np.any(drawn["rgb"] != plain["rgb"], axis=-1)
        assert set(np.nonzero(changed)[0].tolist()) == {23, 24, 25}  # 3 px wide
        again = sim.get_sensor_observations()  # drawn once, then forgotten
        np.testing.assert_array_equal(again["rgb"], plain["rgb"])
        lines.draw_box(
            mn.Vector3(-0.1, 1.4, -1.1), mn.Vector3(0.1, 1.6, -0.9), mn.Color4(0, 1, 0, 1)
        )
        lines.draw_circle(
            mn.Vector3(0, 1.5, -1.0), 0.2, mn.Color4(0, 0, 1, 1), normal=mn.Vector3(0, 0, 1)
        )
        lines.draw_path_with_endpoint_circles(
            [mn.Vector3(-0.5, 1.0, -2), mn.Vector3(0.5, 1.0, -2)], 0.1, mn.Color4(1, 1, 0, 1)
        )
        assert len(lines._starts) == 12 + 24 + 48 + 1
        with pytest.raises(RuntimeError, match="pop_transform"):
            lines.pop_transform()
