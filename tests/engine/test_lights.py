"""Light setups (Habitat's ``habitat_sim.gfx``) driving the rasterizer: the API of Habitat's
``tests/test_light_setup.py`` and pixels checked against the hand-computed Lambert factor
``clamp(0.4 + sum_k c_k max(0, n . l_k), 0, 1)``."""

from __future__ import annotations

import math

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.gfx import DEFAULT_LIGHTING_KEY, NO_LIGHT_KEY, LightInfo, LightPositionModel
from engine.simulator import Configuration, Simulator, SimulatorConfiguration
from render.camera import Camera
from render.frame import RenderMesh, render_frame
from render.shade import Lights

BASE = np.array([200, 100, 50, 255], np.uint8)


def lit_level(channel: int, factor: float) -> int:
    """A channel scaled by a light factor as the rasterizer's 8-bit fixed point does:
    ``(c round(256 f) + 128) >> 8`` (within one level of ``c f``)."""
    return (int(channel) * round(256 * factor) + 128) >> 8


# -- the rasterizer with plain arrays ----------------------------------------------------------
def quad_facing_camera(depth: float = 2.0, half: float = 0.5, lights=None) -> RenderMesh:
    vertices = np.array(
        [[-half, -half, -depth], [half, -half, -depth], [half, half, -depth], [-half, half, -depth]]
    )
    return RenderMesh(
        vertices, np.array([[0, 1, 2], [0, 2, 3]]), base_color=BASE, lit=True, lights=lights
    )


def center_pixel(mesh: RenderMesh, world_from_camera=None) -> np.ndarray:
    camera = Camera((32, 32))
    pose = np.eye(4) if world_from_camera is None else world_from_camera
    return render_frame([mesh], camera, pose).rgba[16, 16, :3].astype(int)


def test_directional_light_gives_the_lambert_factor():
    # one light shining from +Z (towards the camera side) of intensity 0.5: n . l = 1
    lights = Lights([[0.0, 0.0, 1.0, 0.0]], [0.5], ("world",))
    expected = [lit_level(c, 0.4 + 0.5) for c in BASE[:3]]
    np.testing.assert_array_equal(center_pixel(quad_facing_camera(lights=lights)), expected)
    # from 60 degrees off the normal: 0.4 + 0.5 cos(60) = 0.65
    slanted = Lights([[math.sin(math.pi / 3), 0.0, math.cos(math.pi / 3), 0.0]], [0.5], ("world",))
    expected = [lit_level(c, 0.65) for c in BASE[:3]]
    np.testing.assert_array_equal(center_pixel(quad_facing_camera(lights=slanted)), expected)
    # from behind: ambient only; empty setup: flat (the base color)
    behind = Lights([[0.0, 0.0, -1.0, 0.0]], [0.5], ("world",))
    assert list(center_pixel(quad_facing_camera(lights=behind))) == [
        lit_level(c, 0.4) for c in BASE[:3]
    ]
    flat = Lights(np.zeros((0, 4)), [], ())
    np.testing.assert_array_equal(center_pixel(quad_facing_camera(lights=flat)), BASE[:3])


def test_point_light_uses_the_direction_from_each_face():
    light_position = np.array([0.0, 0.0, 0.0])  # at the camera, 2 m in front of the quad
    lights = Lights([[*light_position, 1.0]], [0.5], ("world",))
    pixel = center_pixel(quad_facing_camera(lights=lights))
    # the two triangles' centroids sit (+-1/6, -+1/6) m from the quad center
    factors = []
    for centroid in ([1 / 6, -1 / 6, -2.0], [-1 / 6, 1 / 6, -2.0]):
        to_light = light_position - centroid
        factors.append(0.4 + 0.5 * to_light[2] / np.linalg.norm(to_light))
    assert any(list(pixel) == [lit_level(c, f) for c in BASE[:3]] for f in factors)


def test_camera_frame_lights_move_with_the_camera():
    # a light along the camera's +X: the quad facing the camera gets ambient only...
    lights = Lights([[1.0, 0.0, 0.0, 0.0]], [0.5], ("camera",))
    assert list(center_pixel(quad_facing_camera(lights=lights))) == [
        lit_level(c, 0.4) for c in BASE[:3]
    ]
    # ...and a light along the camera's +Z lights it fully, wherever the camera turns
    lights = Lights([[0.0, 0.0, 1.0, 0.0]], [0.5], ("camera",))
    turn = np.eye(4)
    turn[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]  # camera turned 90 deg about Y
    vertices = quad_facing_camera().vertices @ turn[:3, :3].T  # the quad turned with it
    mesh = RenderMesh(
        vertices, np.array([[0, 1, 2], [0, 2, 3]]), base_color=BASE, lit=True, lights=lights
    )
    assert list(center_pixel(mesh, turn)) == [lit_level(c, 0.9) for c in BASE[:3]]


def test_mesh_frame_lights_move_with_the_mesh():
    # the quad lies in its mesh's x-y plane facing mesh +Z; the mesh is turned 60 degrees
    # about Y and pushed 2 m in front of the camera: a world light along +Z sees it at 60
    # degrees, a mesh-frame light along mesh +Z head on
    c, s = math.cos(math.pi / 3), math.sin(math.pi / 3)
    pose = np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, -2.0], [0, 0, 0, 1]])
    vertices = np.array([[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]])
    for frame, factor in (("world", 0.4 + 0.5 * c), ("mesh", 0.9)):
        lights = Lights([[0.0, 0.0, 1.0, 0.0]], [0.5], (frame,))
        mesh = RenderMesh(
            vertices,
            np.array([[0, 1, 2], [0, 2, 3]]),
            world_from_mesh=pose,
            base_color=BASE,
            lit=True,
            lights=lights,
        )
        assert list(center_pixel(mesh)) == [lit_level(ch, factor) for ch in BASE[:3]]


# -- Habitat's API on the simulator ----------------------------------------------------------
@pytest.fixture
def sim():
    with Simulator(Configuration(SimulatorConfiguration(scene_id="NONE"))) as simulator:
        yield simulator


def test_no_light_setup_is_empty_and_custom_keys_start_empty(sim):
    assert len(sim.get_light_setup(NO_LIGHT_KEY)) == 0
    assert sim.get_light_setup("custom_setup_key") == []
    assert habitat_sim.gfx.DEFAULT_LIGHTING_KEY == DEFAULT_LIGHTING_KEY == ""
    assert sim.config.sim_cfg.scene_light_setup == NO_LIGHT_KEY  # the stage is drawn flat


def test_set_and_get_light_setups_are_copies(sim):
    light_setup = [LightInfo(vector=[1.0, 1.0, 1.0, 0.0])]
    sim.set_light_setup(light_setup)
    assert sim.get_light_setup() == light_setup
    light_setup[0].model = LightPositionModel.Camera  # local edits do not reach the sim
    assert sim.get_light_setup() != light_setup
    sim.set_light_setup(light_setup, DEFAULT_LIGHTING_KEY)
    assert sim.get_light_setup() == light_setup
    custom = sim.get_light_setup("custom_setup_key")
    custom.append(LightInfo(vector=[1.0, 1.0, 1.0, 1.0]))  # a point light
    assert sim.get_light_setup() != custom
    sim.set_light_setup(custom, "custom_setup_key")
    assert sim.get_light_setup("custom_setup_key") == custom
    with pytest.raises(ValueError):
        LightInfo(vector=[0.0, 1.0, 0.0, 0.5])  # w must be 0 or 1
    with pytest.raises(AttributeError, match="color"):
        LightInfo().colour = [1.0, 1.0, 1.0]


def _cube_in_front(sim, light_setup_key=DEFAULT_LIGHTING_KEY):
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid = "rgba"
    spec.resolution = [32, 32]
    sim.close()
    config = Configuration(
        SimulatorConfiguration(scene_id="NONE"),
        [habitat_sim.agent.AgentConfiguration(sensor_specifications=[spec])],
    )
    new_sim = Simulator(config)
    cube = new_sim.get_rigid_object_manager().add_object_by_template_handle(
        "cubeSolid", light_setup_key=light_setup_key
    )
    cube.motion_type = habitat_sim.physics.MotionType.KINEMATIC
    cube.translation = [0.0, 1.5, -1.0]  # in front of the 1.5 m high camera
    return new_sim


def test_per_object_light_keys_drive_the_pixels(sim):
    flat_sim = _cube_in_front(sim, NO_LIGHT_KEY)
    with flat_sim:
        base = flat_sim.get_sensor_observations()["rgba"][16, 16, :3].astype(int)
    lit_sim = _cube_in_front(sim)
    with lit_sim:
        # the +Z face under rigidsim's default 4 lights: 0.4 + 0.5 (1 / sqrt(1.25))
        default = 0.4 + 0.5 / math.sqrt(1.25)
        pixel = lit_sim.get_sensor_observations()["rgba"][16, 16, :3].astype(int)
        assert list(pixel) == [lit_level(c, default) for c in base]
        lit_sim.set_light_setup(
            [LightInfo(vector=[0.0, 0.0, 1.0, 0.0], color=mn.Color3(0.5, 0.5, 0.5))]
        )
        pixel = lit_sim.get_sensor_observations()["rgba"][16, 16, :3].astype(int)
        assert list(pixel) == [lit_level(c, 0.9) for c in base]
        lit_sim.set_light_setup([], DEFAULT_LIGHTING_KEY)  # empty: flat
        pixel = lit_sim.get_sensor_observations()["rgba"][16, 16, :3].astype(int)
        assert list(pixel) == list(base)
