"""Sensors and agents without physics: Habitat's sensor pose conventions and actions."""

import math

import numpy as np
import pytest
import quaternion

from engine import mn
from engine.agent import Agent, AgentConfiguration, AgentState
from engine.scene.assets import MeshData
from engine.scene.graph import Drawable, SceneNode
from engine.sensors import CameraSensorSpec, SensorType, euler_xyz_matrix
from engine.sensors.scene_render import SceneRenderer


def test_orientation_minus_45_is_radians_and_pitches_down_58_3_degrees():
    rotation = euler_xyz_matrix([-45.0, 0.0, 0.0])
    forward = rotation @ np.array([0.0, 0.0, -1.0])
    pitch_deg = math.degrees(math.atan2(forward[1], -forward[2]))
    # -45 rad = -45 + 8 * 2 pi rad = 5.265 rad ... wrapped to (-180, 180]: -58.31 degrees
    assert pitch_deg == pytest.approx(-58.31, abs=0.01)


def test_euler_order_is_x_then_y_then_z():
    angles = [0.3, -0.4, 0.5]
    expected = (
        np.asarray(mn.Matrix4.rotation(mn.Rad(0.5), [0, 0, 1]).rotation())
        @ np.asarray(mn.Matrix4.rotation(mn.Rad(-0.4), [0, 1, 0]).rotation())
        @ np.asarray(mn.Matrix4.rotation(mn.Rad(0.3), [1, 0, 0]).rotation())
    )
    np.testing.assert_allclose(euler_xyz_matrix(angles), expected, atol=1e-12)


def test_sensor_spec_defaults_match_habitat():
    spec = CameraSensorSpec()
    assert spec.position == [0.0, 1.5, 0.0] and spec.hfov == 90.0
    assert spec.near == 0.01 and spec.far == 1000.0 and spec.sensor_type is SensorType.COLOR


def test_bad_sensor_specs_raise_naming_the_field():
    spec = CameraSensorSpec()
    spec.resolution = [0, 10]
    with pytest.raises(ValueError, match="resolution"):
        Agent(SceneNode(), AgentConfiguration(sensor_specifications=[spec]))
    spec = CameraSensorSpec()
    spec.hfov = 180.0
    with pytest.raises(ValueError, match="hfov"):
        Agent(SceneNode(), AgentConfiguration(sensor_specifications=[spec]))
    a, b = CameraSensorSpec(), CameraSensorSpec()
    with pytest.raises(ValueError, match="unique"):
        Agent(SceneNode(), AgentConfiguration(sensor_specifications=[a, b]))


def test_agent_state_validation_and_xyzw_list():
    with pytest.raises(ValueError, match="position"):
        AgentState(position=[math.nan, 0, 0])
    state = AgentState([1, 2, 3], [0.0, 1.0, 0.0, 0.0])  # [x, y, z, w]: 180 degrees about Y
    # Habitat's attrs field keeps what was assigned; set_state reads it as [x, y, z, w]
    assert state.rotation == [0.0, 1.0, 0.0, 0.0]
    agent = Agent(SceneNode(), AgentConfiguration())
    agent.set_state(state)
    assert isinstance(agent.get_state().rotation, np.quaternion)  # get_state: numpy-quaternion
    assert quaternion.allclose(agent.get_state().rotation, np.quaternion(0.0, 0.0, 1.0, 0.0))
    assert AgentState().rotation == np.quaternion(1.0, 0.0, 0.0, 0.0)
    state.rotation = np.quaternion(-0.83147, 0, 0.55557, 0)  # the tutorial's line
    agent.set_state(state)  # normalized when used
    w = agent.get_state().rotation.w
    assert abs(w) == pytest.approx(0.83147 / math.hypot(0.83147, 0.55557))
    for bad in ([0.0, 0.0, 0.0, 0.0], np.quaternion(math.nan, 0, 0, 1)):
        with pytest.raises(ValueError):
            state.rotation = bad


def test_actions_move_along_minus_z_and_turn_about_y():
    agent = Agent(SceneNode(), AgentConfiguration())
    assert agent.act("move_forward") is False
    np.testing.assert_allclose(agent.get_state().position, [0, 0, -0.25], atol=1e-12)
    agent.act("turn_left")  # +10 degrees about +Y turns -Z towards -X
    agent.act("move_forward")
    step = 0.25 * np.array([-math.sin(math.radians(10)), 0, -math.cos(math.radians(10))])
    np.testing.assert_allclose(agent.get_state().position, [0, 0, -0.25] + step, atol=1e-12)
    with pytest.raises(KeyError):
        agent.act("fly")


def test_act_reports_collision_when_the_filter_shortens_the_step():
    def wall_at_minus_point_one(start, end):
        return np.array([end[0], end[1], max(end[2], -0.1)])

    agent = Agent(SceneNode(), AgentConfiguration())
    agent.controls.move_filter_fn = wall_at_minus_point_one
    assert agent.act("move_forward") is True
    np.testing.assert_allclose(agent.get_state().position, [0, 0, -0.1], atol=1e-12)


def test_set_state_round_trips_world_pose_and_sensors_follow():
    spec = CameraSensorSpec()
    spec.uuid = "cam"
    agent = Agent(SceneNode(), AgentConfiguration(sensor_specifications=[spec]))
    q = mn.Quaternion.rotation(mn.Deg(30), [0, 1, 0])
    agent.set_state(AgentState([1.0, 0.5, -2.0], q))
    state = agent.get_state()
    np.testing.assert_allclose(state.position, [1.0, 0.5, -2.0], atol=1e-12)
    coeffs = [state.rotation.x, state.rotation.y, state.rotation.z, state.rotation.w]
    np.testing.assert_allclose(np.abs(coeffs), np.abs(q.xyzw), atol=1e-12)
    cam_position = state.sensor_states["cam"].position
    np.testing.assert_allclose(cam_position, [1.0, 2.0, -2.0], atol=1e-12)  # 1.5 m above


def _quad(z: float, half: float, color) -> MeshData:
    vertices = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]])
    return MeshData(
        vertices=vertices,
        faces=np.array([[0, 1, 2], [0, 2, 3]]),
        base_color=np.array(color, np.uint8),
    )


def test_color_and_depth_sensors_share_a_pose_and_see_a_plane_at_its_z_depth():
    root = SceneNode()
    wall = SceneNode(root)
    wall.drawables = [Drawable(_quad(-3.0, 1.0, [255, 0, 0, 255]), lit=False, semantic_id=7)]
    specs = []
    for uuid, kind in (
        ("rgba", SensorType.COLOR),
        ("depth", SensorType.DEPTH),
        ("sem", SensorType.SEMANTIC),
    ):
        spec = CameraSensorSpec()
        spec.uuid, spec.sensor_type = uuid, kind
        spec.resolution, spec.position = [40, 60], [0, 0, 0]
        specs.append(spec)
    agent = Agent(SceneNode(root), AgentConfiguration(sensor_specifications=specs))
    obs = SceneRenderer(root).observe(agent.sensors)
    assert obs["rgba"].shape == (40, 60, 4) and obs["rgba"].dtype == np.uint8
    assert obs["depth"].dtype == np.float32 and obs["sem"].dtype == np.uint32
    # the quad spans x in [-1, 1] at 3 m: fx = 30 px, so it covers columns 20..39
    covered = obs["depth"] > 0
    np.testing.assert_allclose(obs["depth"][covered], 3.0, rtol=1e-6)
    assert covered[20, 30] and not covered[20, 5]
    np.testing.assert_array_equal(obs["rgba"][20, 30], [255, 0, 0, 255])
    assert obs["sem"][20, 30] == 7 and obs["sem"][20, 5] == 0
    obs["depth"][:] = 9.0  # observations are fresh copies
    again = SceneRenderer(root).observe(agent.sensors)
    np.testing.assert_allclose(again["depth"][20, 30], 3.0, rtol=1e-6)
