"""The Simulator facade: stage loading, managers, agents, sensors, reset, navmesh wiring."""

import math

import numpy as np
import pytest

import engine as habitat_sim


def make_sim(scene_id="NONE", sensors=(), **sim_kwargs):
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = str(scene_id)
    for key, value in sim_kwargs.items():
        setattr(sim_cfg, key, value)
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.sensor_specifications = list(sensors)
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def camera(uuid, sensor_type=habitat_sim.SensorType.COLOR, resolution=(48, 64), **kwargs):
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid, spec.sensor_type, spec.resolution = uuid, sensor_type, list(resolution)
    for key, value in kwargs.items():
        setattr(spec, key, value)
    return spec


def test_empty_world_defaults_and_context_manager():
    with make_sim() as sim:
        assert sim.get_physics_time_step() == pytest.approx(0.008)
        assert sim.get_gravity() == [0, -9.8, 0]
        assert sim.get_world_time() == 0.0
        assert sim.get_object_template_manager().get_num_templates() == 12
        sim.set_gravity([0, -1.0, 0])
        assert sim.get_gravity() == [0, -1, 0]
        # step_filter is the identity without a navmesh
        assert not sim.pathfinder.is_loaded
        assert sim.step_filter([0, 0, 0], [1, 0, 0]) == [1, 0, 0]
    with pytest.raises(RuntimeError):
        sim.step_physics(0.1)


def test_z_up_plane_stage_lands_at_y_zero_and_a_cube_rests_on_it(test_assets):
    with make_sim(test_assets / "scenes/plane.glb") as sim:
        cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
        cube.translation = [0.0, 0.5, 0.0]
        while sim.get_world_time() < 1.5:
            sim.step_physics(1.0 / 60.0)
        # a 0.2 m cube on the plane y = 0 rests with its center at 0.1 m (5 mm resting bar)
        assert cube.translation.y == pytest.approx(0.1, abs=5e-3)


def test_stage_collisions_can_be_turned_off(test_assets):
    with make_sim(test_assets / "scenes/plane.glb") as sim:
        assert sim.get_stage_is_collidable()
        sim.set_stage_is_collidable(False)
        cube = sim.get_rigid_object_manager().add_object_by_template_handle("cubeSolid")
        cube.translation = [0.0, 0.5, 0.0]
        while sim.get_world_time() < 1.0:
            sim.step_physics(1.0 / 60.0)
        assert cube.translation.y < -2.0  # fell through the plane: 1/2 g t^2 ~ 4.9 m


def test_reset_restores_world_time_objects_and_agent(test_assets):
    with make_sim(test_assets / "scenes/plane.glb") as sim:
        agent = sim.initialize_agent(0, habitat_sim.AgentState([1.0, 0.0, 2.0]))
        sphere_ids = sim.get_object_template_manager().load_configs(test_assets / "objects/sphere")
        sphere = sim.get_rigid_object_manager().add_object_by_template_id(sphere_ids[0])
        start = np.asarray(sphere.translation)  # the creation pose reset returns to
        sphere.translation = [0.0, 2.0, 0.0]
        for _ in range(30):
            sim.step_physics(1.0 / 60.0)
        agent.act("move_forward")
        sim.reset()
        assert sim.get_world_time() == 0.0
        np.testing.assert_allclose(np.asarray(sphere.translation), start, atol=1e-12)
        np.testing.assert_allclose(agent.get_state().position, [1.0, 0.0, 2.0], atol=1e-12)


def test_world_time_advances_in_whole_fixed_steps():
    with make_sim() as sim:
        sim.step_physics(1.0 / 60.0)  # 0.01667 s -> two 0.008 s steps, 0.00067 s carried
        assert sim.get_world_time() == pytest.approx(0.016)
        sim.step_physics(0.0)  # dt <= 0 runs one fixed step
        assert sim.get_world_time() == pytest.approx(0.024)


def test_observations_keyed_by_uuid_with_habitat_dtypes(test_assets):
    sensors = [
        camera("rgba"),
        camera("depth", habitat_sim.SensorType.DEPTH),
        camera("third", orientation=[-45.0, 0.0, 0.0], position=[0.0, 1.0, 0.3]),
    ]
    with make_sim(test_assets / "scenes/plane.glb", sensors) as sim:
        sim.initialize_agent(0, habitat_sim.AgentState([0.0, 0.0, 0.0]))
        obs = sim.get_sensor_observations()
        assert set(obs) == {"rgba", "depth", "third"}
        assert obs["rgba"].shape == (48, 64, 4) and obs["rgba"].dtype == np.uint8
        assert obs["depth"].shape == (48, 64) and obs["depth"].dtype == np.float32
        # the first-person camera is 1.5 m above the plane y = 0, looking horizontally:
        # the bottom row at pixel center v = 47.5 sees the floor at z-depth fy*h/(v - cy)
        fy = 32.0 / math.tan(math.radians(45.0))
        expected = fy * 1.5 / (47.5 - 24.0)
        assert obs["depth"][47, 32] == pytest.approx(expected, rel=1e-3)
        assert obs["depth"][0, 32] == 0.0  # the sky: nothing drawn


def test_robot_attached_to_agent_node_moves_the_agent_and_its_cameras(test_assets):
    with make_sim(test_assets / "scenes/plane.glb", [camera("rgba")]) as sim:
        agent = sim.agents[0]
        cube = sim.get_rigid_object_manager().add_object_by_template_handle(
            "cubeSolid", agent.scene_node
        )
        cube.translation = [1.0, 0.1, -2.0]
        np.testing.assert_allclose(agent.get_state().position, [1.0, 0.1, -2.0], atol=1e-9)
        position = agent.get_state().sensor_states["rgba"].position
        np.testing.assert_allclose(position, [1.0, 1.6, -2.0], atol=1e-9)
        sim.get_rigid_object_manager().remove_object_by_id(cube.object_id, delete_object_node=False)
        assert not cube.is_alive
        assert agent.scene_node.parent is sim.root_node  # the node is kept


def test_bad_configuration_raises_clear_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        make_sim(tmp_path / "missing.glb")
    with pytest.raises(TypeError):
        habitat_sim.Simulator("not a config")
    with make_sim() as sim:
        with pytest.raises(KeyError):
            sim.get_agent(3)
        with pytest.raises(ValueError):
            sim.step_filter([math.nan, 0, 0], [0, 0, 0])


def test_stage_navmesh_loads_beside_the_stage_and_sliding_is_read_at_call_time(tmp_path):
    import trimesh

    from engine.scene.assets import load_meshes
    from navmesh import NavMeshSettings, PathFinder

    floor = trimesh.creation.box(extents=[4.0, 0.1, 4.0])
    floor.apply_translation([0, -0.05, 0])
    stage = tmp_path / "room.glb"
    floor.export(stage)
    (tmp_path / "room.stage_config.json").write_text('{"up": [0, 1, 0], "front": [0, 0, -1]}')
    mesh = load_meshes(stage)[0]
    builder = PathFinder()
    assert builder.build(mesh.vertices, mesh.faces, NavMeshSettings())
    builder.save_nav_mesh(str(tmp_path / "room.navmesh"))

    with make_sim(stage) as sim:
        assert sim.pathfinder.is_loaded
        start, into_wall = [1.5, 0.0, 0.0], [2.5, 0.0, 0.5]  # east wall at x = 2 - radius
        slid = np.asarray(sim.step_filter(start, into_wall))
        sim.config.sim_cfg.allow_sliding = False
        stopped = np.asarray(sim.step_filter(start, into_wall))
        assert slid[0] < 2.0 and stopped[0] < 2.0
        assert slid[2] > stopped[2]  # sliding keeps moving along the wall (+z)
