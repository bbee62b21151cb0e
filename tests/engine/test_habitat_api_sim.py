"""Habitat's simulator-level API: settings, the agent loop, seeds, several agents, fixed-field
configs, navmesh helpers and the visualisation helpers (after Habitat's tests/test_simulator.py,
test_sensors.py, test_navmesh.py and its "Basics for Navigation" notebook)."""

import random

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.utils import maps
from engine.utils import viz_utils as vut
from engine.utils.common import colorize_ids, d3_40_colors_rgb
from engine.utils.settings import default_sim_settings, make_cfg

HABITAT_SETTINGS_KEYS = {
    "scene_dataset_config_file",
    "scene",
    "width",
    "height",
    "hfov",
    "zfar",
    "clear_color",
    "sensor_height",
    "default_agent",
    "agent_radius",
    "color_sensor",
    "semantic_sensor",
    "depth_sensor",
    "ortho_rgba_sensor",
    "ortho_depth_sensor",
    "ortho_semantic_sensor",
    "fisheye_rgba_sensor",
    "fisheye_depth_sensor",
    "fisheye_semantic_sensor",
    "equirect_rgba_sensor",
    "equirect_depth_sensor",
    "equirect_semantic_sensor",
    "seed",
    "physics_config_file",
    "enable_physics",
    "default_agent_navmesh",
    "navmesh_include_static_objects",
    "enable_hbao",
}


def xyzw(rotation) -> np.ndarray:
    """``[x, y, z, w]`` of any quaternion type the API hands out."""
    return np.asarray(mn.to_quaternion(rotation).xyzw)


@pytest.fixture()
def apartment_settings(demo_data):
    return {
        **default_sim_settings,
        "scene": str(demo_data / "scene_datasets/demo/apartment.glb"),
        "width": 32,
        "height": 24,
        "depth_sensor": True,
        "physics_config_file": "",
        "default_agent_navmesh": False,
    }  # the dataset's apartment.navmesh loads instead


# -- settings ---------------------------------------------------------------------------------
def test_default_sim_settings_have_habitats_keys_and_defaults():
    assert set(default_sim_settings) == HABITAT_SETTINGS_KEYS
    expected = {
        "scene": "NONE",
        "width": 640,
        "height": 480,
        "hfov": 90,
        "zfar": 1000.0,
        "sensor_height": 1.5,
        "default_agent": 0,
        "agent_radius": 0.1,
        "seed": 1,
        "color_sensor": True,
        "depth_sensor": False,
        "semantic_sensor": False,
        "default_agent_navmesh": True,
        "navmesh_include_static_objects": False,
    }
    assert {k: default_sim_settings[k] for k in expected} == expected


def test_make_cfg_builds_habitats_agent_sensors_and_navmesh_settings():
    settings = {
        **default_sim_settings,
        "depth_sensor": True,
        "semantic_sensor": True,
        "ortho_rgba_sensor": True,
        "hfov": 70,
        "agent_radius": 0.2,
        "seed": 7,
    }
    cfg = make_cfg(settings)
    agent = cfg.agents[0]
    assert agent.height == 1.5 and agent.radius == 0.2
    assert {k: (v.name, v.actuation.amount) for k, v in agent.action_space.items()} == {
        "move_forward": ("move_forward", 0.25),
        "turn_left": ("turn_left", 10.0),
        "turn_right": ("turn_right", 10.0),
    }
    specs = {s.uuid: s for s in agent.sensor_specifications}
    assert list(specs) == ["color_sensor", "depth_sensor", "semantic_sensor", "ortho_rgba_sensor"]
    assert specs["depth_sensor"].sensor_type is habitat_sim.SensorType.DEPTH
    assert specs["depth_sensor"].channels == 1 and specs["color_sensor"].channels == 4
    assert specs["ortho_rgba_sensor"].sensor_subtype is habitat_sim.SensorSubType.ORTHOGRAPHIC
    assert specs["color_sensor"].resolution == [480, 640] and specs["color_sensor"].hfov == 70
    assert specs["color_sensor"].position == [0.0, 1.5, 0.0]
    navmesh = cfg.sim_cfg.navmesh_settings
    assert navmesh.agent_radius == 0.2 and navmesh.agent_height == 1.5
    assert cfg.sim_cfg.scene_id == "NONE" and cfg.sim_cfg.random_seed == 7
    wide = make_cfg(
        {**default_sim_settings, "fisheye_depth_sensor": True, "equirect_rgba_sensor": True}
    )
    fisheye, pano = wide.agents[0].sensor_specifications[1:]
    assert isinstance(fisheye, habitat_sim.FisheyeSensorDoubleSphereSpec)
    assert (fisheye.uuid, fisheye.xi, fisheye.alpha) == ("fisheye_depth_sensor", -0.27, 0.57)
    assert list(fisheye.focal_length) == [364.84, 364.86] and fisheye.channels == 1
    assert isinstance(pano, habitat_sim.EquirectangularSensorSpec)
    assert pano.uuid == "equirect_rgba_sensor" and pano.resolution == [480, 640]
    with pytest.raises(KeyError, match="scene"):
        make_cfg({"width": 10})


def test_empty_scene_with_navmesh_settings_has_no_navmesh_and_warns():
    settings = {
        **default_sim_settings,
        "depth_sensor": True,
        "width": 16,
        "height": 12,
        "physics_config_file": "",
    }
    with pytest.warns(UserWarning, match="no triangles"):
        sim = habitat_sim.Simulator(make_cfg(settings))  # Habitat logs and goes on
    with sim:
        assert not sim.pathfinder.is_loaded and sim.pathfinder.nav_mesh_settings is None
        random.seed(0)
        for _ in range(3):
            obs = sim.step(random.choice(list(sim.config.agents[0].action_space)))
            assert obs["collided"] is False  # no navmesh: nothing to collide with
            assert not obs["depth_sensor"].any()  # nothing drawn: depth 0


def test_missing_physics_config_falls_back_to_defaults_with_a_warning():
    with pytest.warns(UserWarning, match="not found"):
        sim = habitat_sim.Simulator(
            make_cfg(
                {**default_sim_settings, "color_sensor": False, "default_agent_navmesh": False}
            )
        )
    with sim:
        assert sim.get_physics_time_step() == pytest.approx(0.008)


# -- the agent loop ---------------------------------------------------------------------------
def test_step_returns_observations_and_collided_and_moves_through_the_navmesh(apartment_settings):
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        assert sim.pathfinder.is_loaded
        assert list(sim.sensors) == ["color_sensor", "depth_sensor"]
        agent = sim.get_agent(0)
        start = agent.state.position
        assert sim.pathfinder.is_navigable(start)  # initialize_agent: a random navigable point
        obs = sim.step("move_forward")
        assert set(obs) == {"color_sensor", "depth_sensor", "collided"}
        assert obs["color_sensor"].shape == (24, 32, 4) and obs["depth_sensor"].dtype == np.float32
        assert sim.get_world_time() > 0.0  # step() also steps the physics by dt
        moved = np.linalg.norm(agent.state.position - start)
        assert obs["collided"] == (moved**2 + 1e-5 < 0.25**2)
        np.testing.assert_allclose(sim.last_state().position, agent.state.position)
        # walk into walls until a step collides; the agent never leaves the navmesh
        collided = False
        for _ in range(60):
            obs = sim.step("move_forward")
            collided |= obs["collided"]
            assert sim.pathfinder.is_navigable(agent.state.position)
        assert collided
        with pytest.raises(AssertionError):
            sim.step("fly")


def test_seed_makes_initial_placement_reproducible(apartment_settings):
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        first = sim.get_agent(0).state  # placed with the configured seed
        sim.seed(5)
        a = sim.initialize_agent(0).state
        sim.seed(5)
        b = sim.initialize_agent(0).state
        np.testing.assert_array_equal(a.position, b.position)
        np.testing.assert_array_equal(xyzw(a.rotation), xyzw(b.rotation))
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        np.testing.assert_array_equal(sim.get_agent(0).state.position, first.position)


def test_reset_returns_observations_and_restores_every_agent(apartment_settings):
    cfg = make_cfg(apartment_settings)
    cfg.agents = [cfg.agents[0], cfg.agents[0], cfg.agents[0]]  # shared specs, as Habitat's test
    with habitat_sim.Simulator(cfg) as sim:
        initial = [sim.initialize_agent(i).state for i in range(3)]
        random.seed(1)
        for _ in range(5):
            sim.step({i: random.choice(["move_forward", "turn_left"]) for i in range(3)})
        obs = sim.reset()
        assert set(obs) == {"color_sensor", "depth_sensor"}  # the default agent's
        for i, state in enumerate(initial):
            now = sim.get_agent(i).state
            assert all(now.position == state.position)  # exactly, as Habitat's test asks
            np.testing.assert_allclose(
                np.abs(xyzw(now.rotation) @ xyzw(state.rotation)), 1.0, rtol=1e-9
            )
        assert set(sim.reset(agent_ids=[1, 2])) == {1, 2}


def test_several_agents_step_with_a_dict_and_an_idle_agent_is_left_out(apartment_settings):
    cfg = make_cfg(apartment_settings)
    cfg.agents.append(make_cfg(apartment_settings).agents[0])
    cfg.agents.append(make_cfg(apartment_settings).agents[0])
    with habitat_sim.Simulator(cfg) as sim:
        before = [sim.get_agent(i).state for i in range(3)]
        observations = sim.step({0: "turn_left", 2: "turn_right"})
        assert set(observations) == {0, 2}
        assert set(observations[0]) == {"color_sensor", "depth_sensor", "collided"}
        np.testing.assert_array_equal(sim.get_agent(1).state.position, before[1].position)
        assert not np.allclose(xyzw(sim.get_agent(0).state.rotation), xyzw(before[0].rotation))
        per_agent = sim.get_sensor_observations(agent_ids=[0, 1])
        assert set(per_agent) == {0, 1} and "collided" not in per_agent[1]
        # each agent sees from its own pose
        assert not np.array_equal(per_agent[0]["depth_sensor"], per_agent[1]["depth_sensor"])


def test_add_sensor_hfov_and_reconfigure(apartment_settings):
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        spec = habitat_sim.CameraSensorSpec()
        spec.uuid = "extra_depth"
        spec.sensor_type = habitat_sim.SensorType.DEPTH
        spec.resolution = [8, 8]
        sim.add_sensor(spec)
        assert "extra_depth" in sim.step("turn_left")
        sensor = sim.get_agent(0)._sensors["color_sensor"]
        sensor.fov = habitat_sim.mn.Deg(80)
        assert sensor.hfov == habitat_sim.mn.Deg(80) and sensor.specification().hfov == 80.0
        sim.reconfigure(make_cfg({**apartment_settings, "depth_sensor": False}))
        assert list(sim.sensors) == ["color_sensor"]
        assert set(sim.step("move_forward")) == {"color_sensor", "collided"}
        sim.close(destroy=True)
        with pytest.raises(RuntimeError, match="closed"):
            sim.step("move_forward")


# -- fixed-field configuration objects ---------------------------------------------------------
@pytest.mark.parametrize(
    "make, typo, closest",
    [
        (habitat_sim.SimulatorConfiguration, "enable_phyiscs", "enable_physics"),
        (habitat_sim.CameraSensorSpec, "resolutoin", "resolution"),
        (habitat_sim.agent.AgentConfiguration, "sensor_specification", "sensor_specifications"),
        (habitat_sim.NavMeshSettings, "agent_raduis", "agent_radius"),
        (habitat_sim.Configuration, "sim_config", "sim_cfg"),
        (lambda: habitat_sim.ActionSpec("move_forward"), "actuaton", "actuation"),
        (lambda: habitat_sim.ActuationSpec(0.25), "ammount", "amount"),
        (habitat_sim.AgentState, "positon", "position"),
    ],
)
def test_configuration_objects_reject_unknown_attributes(make, typo, closest):
    config = make()
    with pytest.raises(AttributeError, match=f"did you mean '{closest}'"):
        setattr(config, typo, 1)
    assert not hasattr(config, typo)
    setattr(config, closest, getattr(config, closest))  # the real field still assigns


def test_fixed_fields_name_all_fields_when_nothing_is_close():
    with pytest.raises(AttributeError, match="fields are"):
        habitat_sim.SimulatorConfiguration().xyz = 1


# -- navmesh helpers ---------------------------------------------------------------------------
def test_pathfinder_helpers(apartment_settings):
    unloaded = habitat_sim.PathFinder()
    assert unloaded.nav_mesh_settings is None
    record = habitat_sim.HitRecord()
    assert record.hit_dist == np.inf and np.all(record.hit_pos == 0)
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        pf = sim.pathfinder
        assert isinstance(pf.nav_mesh_settings, habitat_sim.NavMeshSettings)
        vertices = np.asarray(pf.build_navmesh_vertices())
        indices = np.asarray(pf.build_navmesh_vertex_indices()).reshape(-1, 3)
        assert vertices.shape[1] == 3 and indices.max() == len(vertices) - 1
        # the triangles cover the navigable area; their normals point up
        a, b, c = (vertices[indices[:, k]] for k in range(3))
        normals = np.cross(b - a, c - a)
        assert np.all(normals[:, 1] > 0)
        assert 0.5 * normals[:, 1].sum() == pytest.approx(pf.navigable_area, rel=1e-9)
        small_vertices = np.asarray(pf.build_navmesh_vertices(1))
        small = small_vertices[np.asarray(pf.build_navmesh_vertex_indices(1)).reshape(-1, 3)]
        small_normals = np.cross(small[:, 1] - small[:, 0], small[:, 2] - small[:, 0])
        assert 0.5 * small_normals[:, 1].sum() == pytest.approx(pf.island_area(1), rel=1e-9)
        point = pf.get_random_navigable_point(island_index=0)
        assert pf.island_radius(point) > pf.island_radius(
            pf.get_random_navigable_point(island_index=1)
        )  # islands are numbered largest first


# -- visualisation helpers ---------------------------------------------------------------------
def test_id_colors_and_island_map():
    assert d3_40_colors_rgb.shape == (40, 3) and d3_40_colors_rgb.dtype == np.uint8
    ids = np.array([[0, -1], [40, 41]])
    colored = colorize_ids(ids)
    np.testing.assert_array_equal(colored[0, 0], [31, 119, 180])  # d3's first color
    np.testing.assert_array_equal(colored[0, 1], [0, 0, 0])  # negative: nothing, black
    np.testing.assert_array_equal(colored[1, 0], d3_40_colors_rgb[0])  # 40 wraps to 0
    np.testing.assert_array_equal(colored[1, 1], d3_40_colors_rgb[1])
    islands = np.array([[-1, 0], [1, 1]])
    image = np.asarray(vut.get_island_colored_map(islands))
    np.testing.assert_array_equal(image[0, 0], [255, 255, 255])
    # Habitat's layout: image[j, i] = islands[i, -j mod H] (transposed, columns upwards)
    np.testing.assert_array_equal(image[1, 0], d3_40_colors_rgb[0])
    np.testing.assert_array_equal(image[0, 1], d3_40_colors_rgb[1])


def test_topdown_map_border_grid_and_path(apartment_settings):
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        pf = sim.pathfinder
        height = pf.get_bounds()[0][1]
        topdown = maps.get_topdown_map(pf, height, meters_per_pixel=0.1)
        navigable = pf.get_topdown_view(0.1, height)
        assert set(np.unique(topdown)) == {0, 1, 2}
        np.testing.assert_array_equal(topdown > 0, navigable)
        point = pf.get_random_navigable_point(island_index=0)
        row, col = maps.to_grid(point[2], point[0], topdown.shape, pathfinder=pf)
        z, x = maps.from_grid(row, col, topdown.shape, pathfinder=pf)
        assert abs(z - point[2]) <= 0.1 + 1e-9 and abs(x - point[0]) <= 0.1 + 1e-9
        colored = maps.colorize_topdown_map(topdown)
        maps.draw_path(colored, [(2, 2), (2, 12)], color=(255, 0, 0), thickness=1)
        np.testing.assert_array_equal(colored[2, 7], [255, 0, 0])
        col_row = vut.convert_points_to_topdown(pf, [point], 0.1)[0]
        assert col_row == pytest.approx([col, row], abs=1.0)


def test_island_meshes_add_up_and_islands_are_queried_by_index(apartment_settings):
    """Habitat's test_navmesh_islands: per-island meshes, radius/area by index, sampling."""
    with habitat_sim.Simulator(make_cfg(apartment_settings)) as sim:
        pf = sim.pathfinder
        sim.navmesh_visualization = True
        assert sim.navmesh_visualization
        total_vertices, total_indices = 0, 0
        for island in range(pf.num_islands):
            vertices = pf.build_navmesh_vertices(island)
            indices = pf.build_navmesh_vertex_indices(island)
            assert len(vertices) > 0 and max(indices) < len(vertices)
            total_vertices += len(vertices)
            total_indices += len(indices)
            point = pf.get_random_navigable_point(island_index=island)
            assert pf.get_island(point) == island
            assert pf.island_radius(island) == pf.island_radius(point) > 0.0
            near = pf.get_random_navigable_point_near(point, 0.5, island_index=island)
            assert np.linalg.norm(point - near) < 0.5 and pf.is_navigable(near)
            assert np.allclose(pf.snap_point(point, island), point)
        assert total_vertices == len(pf.build_navmesh_vertices())
        assert total_indices == len(pf.build_navmesh_vertex_indices())
        with pytest.raises(ValueError, match="island_index"):
            pf.island_radius(pf.num_islands)


def test_recompute_navmesh_third_argument_includes_static_objects(apartment_settings):
    """Habitat's notebook passes ``include_static_objects`` as a third argument."""
    with habitat_sim.Simulator(
        make_cfg({**apartment_settings, "color_sensor": False, "depth_sensor": False})
    ) as sim:
        templates = sim.get_object_template_manager()
        handle = templates.get_template_handles("cubeSolid")[0]
        point = sim.pathfinder.get_random_navigable_point(island_index=0)
        box = sim.get_rigid_object_manager().add_object_by_template_handle(handle)
        box.translation = point + np.array([0.0, 0.1, 0.0])
        box.motion_type = habitat_sim.physics.MotionType.STATIC
        settings = habitat_sim.NavMeshSettings()
        settings.set_defaults()
        assert sim.recompute_navmesh(sim.pathfinder, settings)
        without = sim.pathfinder.navigable_area
        assert sim.pathfinder.is_navigable(point)
        assert sim.recompute_navmesh(sim.pathfinder, settings, True)
        assert sim.pathfinder.navigable_area < without - 0.04  # the 0.2 m box + radius
        assert not sim.pathfinder.is_navigable(point)


def test_seed_reproduces_random_navigable_points(apartment_settings):
    """Habitat's test_random_seed: points are mn.Vector3, so ``==`` answers one bool."""
    with habitat_sim.Simulator(
        make_cfg({**apartment_settings, "color_sensor": False, "depth_sensor": False})
    ) as sim:
        sim.seed(1)
        point1 = sim.pathfinder.get_random_navigable_point()
        sim.seed(1)
        assert point1 == sim.pathfinder.get_random_navigable_point()
        assert isinstance(point1, mn.Vector3)
        sim.seed(2)
        point1 = sim.pathfinder.get_random_navigable_point()
        sim.seed(3)
        assert point1 != sim.pathfinder.get_random_navigable_point()
        sim.seed(4)
        point1 = sim.pathfinder.get_random_navigable_point()
        assert point1 != sim.pathfinder.get_random_navigable_point()


def test_navmesh_without_navigable_area_starts_agents_at_the_origin(tmp_path):
    import trimesh

    floor = trimesh.creation.box(extents=[0.3, 0.02, 0.3])  # smaller than an island may be
    path = tmp_path / "tiny_floor.glb"
    floor.export(path)
    (tmp_path / "tiny_floor.stage_config.json").write_text('{"up": [0, 1, 0], "front": [0, 0, -1]}')
    settings = {
        **default_sim_settings,
        "scene": str(path),
        "color_sensor": False,
        "physics_config_file": "",
    }
    with pytest.warns(UserWarning, match="origin"):
        sim = habitat_sim.Simulator(make_cfg(settings))
    with sim:
        assert sim.pathfinder.is_loaded and sim.pathfinder.navigable_area == 0.0
        np.testing.assert_array_equal(sim.get_agent(0).state.position, [0.0, 0.0, 0.0])
