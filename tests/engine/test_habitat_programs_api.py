"""The API surface Habitat's own example programs and tests stop on: ``habitat_sim.bindings``,
simulator queries, templates made from asset files, typed user configurations, logging,
``datasets_download``, types as Habitat returns them, and bad inputs refused up front."""

import logging
from pathlib import Path

import numpy as np
import pytest
import quaternion

import engine as habitat_sim
from engine import mn
from engine.agent import Agent, AgentConfiguration, AgentState
from engine.attributes_managers import ObjectAttributesManager
from engine.bindings import Configuration, ConfigValType
from engine.logging import parse_filter
from engine.physics import MotionType
from engine.scene import SceneGraph
from engine.scene.graph import SceneNode
from engine.utils import datasets_download


def empty_sim(scene_id: str = "NONE") -> habitat_sim.Simulator:
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = scene_id
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [AgentConfiguration()]))


def test_bindings_flags_and_classes_are_the_engine_ones():
    assert habitat_sim.bindings.built_with_bullet is True  # dynamics exist (our solver)
    assert habitat_sim.bindings.cuda_enabled is False
    assert habitat_sim.bindings.audio_enabled is False
    assert habitat_sim.stage_id == 0
    assert habitat_sim.bindings.RigidState is habitat_sim.RigidState
    assert habitat_sim.bindings.CameraSensorSpec is habitat_sim.CameraSensorSpec
    with pytest.raises(AttributeError, match="no_such_name"):
        _ = habitat_sim.bindings.no_such_name


def test_none_scene_in_any_case_is_empty_with_queries():
    with empty_sim("none") as sim:
        assert sim.curr_scene_name == "NONE"
        assert sim.get_stage_initialization_template() is None
        assert sim.semantic_scene.levels == [] and sim.semantic_scene.objects == []
        with pytest.raises(KeyError, match="semantic index 3"):
            sim.semantic_scene.semantic_index_to_object_index(3)
        assert sim.get_metadata_mediator() is sim.metadata_mediator
        assert sim.get_physics_step_collision_summary() == "(no active collision manifolds)\n"
        assert sim._previous_step_time == 0.0
        sim.step("move_forward")
        assert sim._previous_step_time > 0.0


def test_scene_aabb_and_collision_summary_name_the_touching_pair():
    with empty_sim() as sim:
        rom = sim.get_rigid_object_manager()
        floor = rom.add_object_by_template_handle("cubeSolid")
        floor.motion_type = MotionType.STATIC  # 0.2 m cube at the origin
        box = rom.add_object_by_template_handle("cubeSolid")
        box.translation = [0.0, 0.2, 0.0]  # resting on it
        sim.step_physics(0.1)
        summary = sim.get_physics_step_collision_summary()
        assert summary.startswith("[RigidObject, cubeSolid, id ")
        assert summary.endswith(" points\n") and " vs [RigidObject, cubeSolid, id " in summary
        aabb = sim.scene_aabb
        np.testing.assert_allclose(aabb.min, [-0.1, -0.1, -0.1], atol=0.02)  # settles < 2 cm
        np.testing.assert_allclose(aabb.max[1], 0.3, atol=0.02)


def test_datasets_download_links_stand_ins_and_refuses_unknown_uids(tmp_path):
    datasets_download.main(["--uids", "habitat_test_scenes", "--data-path", str(tmp_path)])
    castle = tmp_path / "scene_datasets/habitat-test-scenes/skokloster-castle.glb"
    assert castle.is_symlink() and castle.resolve().name == "apartment.glb"
    with pytest.raises(ValueError, match="'mp3d_full'"):
        datasets_download.main(["--uids", "habitat_example_objects", "mp3d_full"])


def test_logging_filter_follows_habitats_grammar():
    levels = parse_filter("quiet:physics,sim=verbose")
    assert levels["physics"] == logging.DEBUG and levels["gfx"] == logging.ERROR
    with pytest.raises(ValueError, match="'loud'"):
        parse_filter("loud")
    with pytest.raises(ValueError, match="'robots'"):
        parse_filter("robots=debug")


def test_magnum_ranges_matrices_and_colors():
    box = mn.Range3D((0.0, 1.0, 2.0), (2.0, 4.0, 6.0))
    assert box.x() == mn.Range1D(0.0, 2.0) and box.y().size() == 3.0 and box.z().center() == 4.0
    assert box.yz() == mn.Range2D((1.0, 2.0), (4.0, 6.0))
    assert (box.left, box.bottom, box.back, box.front) == (0.0, 1.0, 2.0, 6.0)
    assert box.scaled_from_center(2.0) == mn.Range3D((-1.0, -0.5, 0.0), (3.0, 5.5, 8.0))
    eye = mn.Vector3(1.0, 1.0, 1.0)
    pose = mn.Matrix4.look_at(eye, mn.Vector3(0.0, 0.0, 0.0), mn.Vector3(0.0, 1.0, 0.0))
    assert pose.transform_vector([0.0, 0.0, -1.0]) == -eye.normalized()  # -Z looks at target
    pose.translation = [1.0, 2.0, 3.0]
    assert pose.translation == mn.Vector3(1.0, 2.0, 3.0)
    assert mn.Color4.from_linear_rgb_int(0xFF8000) == mn.Color4(1.0, 128 / 255, 0.0, 1.0)
    assert mn.Color4.yellow() == mn.Color4(1.0, 1.0, 0.0, 1.0)
    turned = habitat_sim.geo.get_transformed_bb(
        mn.Range3D((-1.0, -0.5, -0.1), (1.0, 0.5, 0.1)), mn.Matrix4.rotation_y(mn.Deg(90.0))
    )
    assert turned == mn.Range3D((-0.1, -0.5, -1.0), (0.1, 0.5, 1.0))  # x and z swap extents
    node = SceneNode()
    node.translation = [1.0, 2.0, 3.0]
    assert node.absolute_transformation_matrix().translation == mn.Vector3(1.0, 2.0, 3.0)


def test_configuration_stores_habitats_value_types():
    config = Configuration()
    config.set("vec2", np.array([1.5, 2.0]))
    config.set("mat3", mn.Matrix3((1.0, 2.0, 3.0), (4.0, 5.0, 6.0), (7.0, 8.0, 9.0)))
    config.set("quat", mn.Quaternion(((1.0, 2.0, -3.0), 4.0)))  # kept as given
    config.set("zero_d", np.array(2.5))
    assert config.get("vec2") == mn.Vector2(1.5, 2.0)
    assert config.get_type("mat3") is ConfigValType.MagnumMat3
    assert config.get_as_string("mat3") == "[[1 4 7][2 5 8][3 6 9]]"  # rows of column input
    assert config.get("quat") == mn.Quaternion(((1.0, 2.0, -3.0), 4.0))
    assert config.get("zero_d") == 2.5
    config.get_subconfig("a").get_subconfig("b").set("deep", 1)
    assert config.find_value_location("deep") == ["a", "b", "deep"]
    with pytest.raises(ValueError, match="'names'.*'x'"):
        config.set("names", ["x", "y", "z"])


def test_create_new_template_from_an_asset_file(habitat_data):
    mesh = Path(habitat_data) / "test_assets/scenes/simple_room.glb"
    template = ObjectAttributesManager().create_new_template(str(mesh))
    assert template.render_asset_handle == str(mesh.resolve())
    assert template.collision_asset_fullpath == str(mesh.resolve())
    template.restitution_coefficient = 1.5  # Habitat stores it: a warning, no refusal
    assert template.restitution_coefficient == 1.5
    template.linear_damping = 1.5
    with pytest.raises(ValueError, match="restitution_coefficient"):
        template.restitution_coefficient = -0.1


def test_agent_state_rotation_reads_back_what_was_assigned():
    state = AgentState()
    assert isinstance(state.rotation, quaternion.quaternion)
    magnum = mn.Quaternion.rotation(mn.Deg(90.0), mn.Vector3(0.0, 1.0, 0.0))
    state.rotation = magnum
    assert state.rotation is magnum
    agent = Agent(SceneNode(), AgentConfiguration())
    agent.set_state(state)
    assert isinstance(agent.get_state().rotation, quaternion.quaternion)


def test_enums_print_names_and_pathfinder_points_compare_with_eq():
    assert str(MotionType.DYNAMIC) == "MotionType.DYNAMIC" and MotionType.DYNAMIC == 2
    assert f"{MotionType.KINEMATIC}" == "MotionType.KINEMATIC"
    assert issubclass(habitat_sim.PathFinder, habitat_sim.nav.PathFinder)


def test_path_like_text_and_deep_json_are_refused_up_front(tmp_path):
    manager = ObjectAttributesManager()
    with pytest.raises(ValueError, match="5000 characters"):
        manager.load_configs("x" * 5000)
    deep = tmp_path / "deep.object_config.json"
    deep.write_text('{"user_defined": ' + "[" * 100_000 + "]" * 100_000 + "}")
    with pytest.raises(ValueError, match="deep"):
        manager.load_configs(str(deep))
    assert manager.get_num_templates() == ObjectAttributesManager().get_num_templates()


def test_profiling_ranges_nest_and_capture_a_step_window(monkeypatch):
    from engine.utils import profiling_utils

    monkeypatch.setattr(profiling_utils, "_enable_profiling", True)
    with profiling_utils.RangeContext("A"):
        profiling_utils.range_push("B")
        assert profiling_utils._helper.range_depth == 2
        profiling_utils.range_pop()
    assert profiling_utils._helper.range_depth == 0
    profiling_utils.configure(capture_start_step=2, num_steps_to_capture=3)
    depths = []
    for _ in range(7):
        profiling_utils.on_start_step()
        depths.append(profiling_utils._helper.range_depth)
    assert depths == [0, 0, 1, 1, 1, 0, 0]  # steps 2, 3, 4 inside the capture range
    with pytest.raises(ValueError, match="num_steps_to_capture"):
        profiling_utils.configure(capture_start_step=1, num_steps_to_capture=0)


def test_island_colored_map_has_habitats_size_and_orientation():
    from engine.utils.common import d3_40_colors_rgb
    from engine.utils.viz_utils import get_island_colored_map

    islands = np.full((4, 3), -1)  # 4 map rows, 3 map columns
    islands[1, 0] = 0  # Habitat writes pixel (x=1, y=-0) -> image row 0, column 1
    islands[2, 1] = 1  # pixel (x=2, y=-1) -> image row 2 (the last), column 2
    image = np.asarray(get_island_colored_map(islands))
    assert image.shape == (3, 4, 3)  # PIL size (4, 3): shape[0] wide, shape[1] tall
    np.testing.assert_array_equal(image[0, 1], d3_40_colors_rgb[0])
    np.testing.assert_array_equal(image[2, 2], d3_40_colors_rgb[1])
    assert (image == 255).all(axis=2).sum() == 10  # everything else white


@pytest.mark.parametrize(
    ("name", "keyword", "value", "rgb"),
    [
        ("red", "red", 0.25, (0.25, 0.0, 0.0)),
        ("green", "green", 0.25, (0.0, 0.25, 0.0)),
        ("blue", "blue", 0.25, (0.0, 0.0, 0.25)),
        ("cyan", "red", 0.25, (0.25, 1.0, 1.0)),
        ("magenta", "green", 0.25, (1.0, 0.25, 1.0)),
        ("yellow", "blue", 0.25, (1.0, 1.0, 0.25)),
    ],
)
def test_named_colors_take_magnums_arguments(name, keyword, value, rgb):
    default = 1.0 if name in ("red", "green", "blue") else 0.0
    full = [1.0 - default] * 3
    full[("red", "green", "blue").index(keyword)] = default
    assert getattr(mn.Color3, name)() == mn.Color3(*full)
    assert getattr(mn.Color3, name)(**{keyword: value}) == mn.Color3(*rgb)
    color = getattr(mn.Color4, name)(value, alpha=0.5)
    assert isinstance(color, mn.Color4) and color == mn.Color4(*rgb, 0.5)
    assert getattr(mn.Color4, name)() == mn.Color4(*full, 1.0)
    with pytest.raises(TypeError, match="alpha"):
        getattr(mn.Color3, name)(value, alpha=0.5)  # Color3 has no alpha


def test_scene_module_exports_the_scene_graph_agents_are_built_on():
    """Habitat's noisy-controls test builds an agent on ``habitat_sim.scene.SceneGraph()``."""
    graph = SceneGraph()
    agent = Agent(graph.get_root_node().create_child(), AgentConfiguration())
    agent.act("move_forward")  # default 0.25 m along -Z (Habitat's forward)
    assert np.allclose(agent.get_state().position, [0.0, 0.0, -0.25], atol=1e-9)
    assert agent.scene_node.parent is graph.get_root_node()
