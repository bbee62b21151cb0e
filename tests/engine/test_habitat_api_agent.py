"""Habitat's agent and control behaviours (after its tests/test_controls.py, test_agent.py).

Agents are built as Habitat's tests build them: ``Agent(SceneGraph().get_root_node()
.create_child(), config)``. Expected deltas are Habitat's: 0.25 m moves along the geo axes,
10 degree turns about UP (left) / GRAVITY (right), look controls acting on the sensors only,
constrained looks clamped to the constraint angle.
"""

import math

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.geo import BACK, FRONT, GRAVITY, LEFT, RIGHT, UP
from engine.utils.common import quat_from_angle_axis


def rotation_angle_between(q1, q2) -> float:
    """Angle (radians) of the rotation taking q2 to q1 (Habitat's angle_between_quats)."""
    a = np.asarray(mn.to_quaternion(q1).xyzw)
    b = np.asarray(mn.to_quaternion(q2).xyzw)
    return 2.0 * math.acos(min(1.0, abs(float(a @ b))))


def axis_angle(degrees: float, axis) -> mn.Quaternion:
    return mn.Quaternion.rotation(mn.Deg(degrees), axis)


def make_agent(actions: dict, with_sensor: bool = True) -> habitat_sim.Agent:
    config = habitat_sim.AgentConfiguration()
    config.action_space = {
        name: habitat_sim.ActionSpec(name, habitat_sim.ActuationSpec(amount))
        for name, amount in actions.items()
    }
    if with_sensor:
        spec = habitat_sim.CameraSensorSpec()
        spec.uuid = "eye"
        config.sensor_specifications = [spec]
    return habitat_sim.Agent(habitat_sim.SceneGraph().get_root_node().create_child(), config)


def check_delta(before, after, delta_pos=(0, 0, 0), delta_rot=None):
    """``after`` = ``before`` moved by ``delta_pos`` (world) and turned by ``delta_rot``."""
    delta_rot = mn.Quaternion() if delta_rot is None else delta_rot
    assert np.linalg.norm(after.position - before.position - np.asarray(delta_pos)) < 1e-5
    turned_back = mn.to_quaternion(after.rotation) * delta_rot.inverted()
    assert rotation_angle_between(turned_back, before.rotation) < 1e-5


BODY_CASES = [
    ("move_backward", 0.25 * BACK, None),
    ("move_forward", 0.25 * FRONT, None),
    ("move_right", 0.25 * RIGHT, None),
    ("move_left", 0.25 * LEFT, None),
    ("turn_right", np.zeros(3), axis_angle(10.0, GRAVITY)),
    ("turn_left", np.zeros(3), axis_angle(10.0, UP)),
]


@pytest.mark.parametrize("action, delta_pos, delta_rot", BODY_CASES)
def test_body_controls_move_the_agent_and_its_sensors(action, delta_pos, delta_rot):
    amount = 10.0 if action.startswith("turn") else 0.25
    agent = make_agent({action: amount})
    before = agent.state
    assert agent.act(action) is False  # no filter: nothing collides
    after = agent.state
    check_delta(before, after, delta_pos, delta_rot)
    assert set(after.sensor_states) == {"eye"}
    # the sensor rides on the body: same world translation for moves, same turn for turns
    check_delta(before.sensor_states["eye"], after.sensor_states["eye"], delta_pos, delta_rot)


SENSOR_CASES = [
    ("move_up", 0.25 * UP, None),
    ("move_down", 0.25 * GRAVITY, None),
    ("look_right", np.zeros(3), axis_angle(-10.0, UP)),
    ("look_left", np.zeros(3), axis_angle(10.0, UP)),
    ("look_up", np.zeros(3), axis_angle(10.0, RIGHT)),
    ("look_down", np.zeros(3), axis_angle(-10.0, RIGHT)),
    ("rotate_sensor_clockwise", np.zeros(3), axis_angle(-10.0, FRONT)),
    ("rotate_sensor_anti_clockwise", np.zeros(3), axis_angle(10.0, FRONT)),
]


@pytest.mark.parametrize("action, delta_pos, delta_rot", SENSOR_CASES)
def test_sensor_controls_move_only_the_sensors(action, delta_pos, delta_rot):
    amount = 0.25 if action.startswith("move") else 10.0
    agent = make_agent({action: amount})
    before = agent.state
    agent.act(action)
    after = agent.state
    check_delta(before, after)  # the body did not move
    check_delta(before.sensor_states["eye"], after.sensor_states["eye"], delta_pos, delta_rot)


def test_unknown_action_or_control_is_an_assertion_error_and_a_key_error():
    agent = make_agent({"move_backward": 0.25})
    with pytest.raises(AssertionError):
        agent.act("move_forward")  # not in the action space
    with pytest.raises(KeyError, match="move_forward"):
        agent.act("move_forward")
    agent.agent_config.action_space = {
        "move_forward": habitat_sim.ActionSpec("DNF", habitat_sim.ActuationSpec(0.25))
    }
    with pytest.raises(AssertionError, match="DNF"):
        agent.act("move_forward")  # no registered control named DNF


@pytest.mark.parametrize(
    "name, axis", [("look_up", 0), ("look_down", 0), ("look_left", 1), ("look_right", 1)]
)
@pytest.mark.parametrize(
    "amount, constraint, start",
    [(30.0, 20.0, 5.0), (10.0, 45.0, -40.0), (60.0, 60.0, 0.0), (5.0, 10.0, 8.0)],
)
def test_constrained_look_clamps_the_look_angle(name, axis, amount, constraint, start):
    node = habitat_sim.SceneGraph().get_root_node().create_child()
    node.rotation = mn.Quaternion.rotation(mn.Deg(start), np.eye(3)[axis])
    spec = habitat_sim.agent.controls.ActuationSpec(amount, constraint)
    habitat_sim.registry.get_move_fn(name)(node, spec)
    sign = -1.0 if name in ("look_down", "look_right") else 1.0
    expected = min(max(start + sign * amount, -constraint), constraint)
    look = np.asarray(node.rotation.transform_vector(FRONT))
    if axis == 0:
        angle = math.degrees(math.atan2(look[1], -look[2]))
    else:
        angle = -math.degrees(math.atan2(look[0], -look[2]))
    assert angle == pytest.approx(expected, abs=1e-6)


def test_constrained_look_refuses_a_mixed_rotation():
    node = habitat_sim.SceneGraph().get_root_node().create_child()
    node.rotation = mn.Quaternion.rotation(mn.Deg(20.0), [1.0, 1.0, 0.0])
    with pytest.raises(RuntimeError, match="singular look"):
        habitat_sim.registry.get_move_fn("look_up")(node, habitat_sim.ActuationSpec(5.0, 10.0))


def test_user_defined_control_registered_by_decorator():
    @habitat_sim.registry.register_move_fn(body_action=True)
    class StrafeUpward(habitat_sim.agent.SceneNodeControl):
        def __call__(self, scene_node, actuation_spec):
            scene_node.translate_local([0.0, actuation_spec.amount, 0.0])

    assert habitat_sim.registry.get_move_fn("strafe_upward").body_action is True
    habitat_sim.registry.register_move_fn(StrafeUpward, name="hop", body_action=False)
    assert habitat_sim.registry.get_move_fn("hop").body_action is False
    agent = make_agent({"strafe_upward": 0.5})
    agent.act("strafe_upward")
    np.testing.assert_allclose(agent.state.position, [0.0, 0.5, 0.0], atol=1e-12)
    with pytest.raises(AssertionError):
        habitat_sim.registry.register_move_fn(StrafeUpward)  # body_action must be given
    with pytest.raises(AssertionError):
        habitat_sim.registry.register_move_fn(dict, body_action=True)  # not a control


def test_move_filter_reports_collisions_with_habitats_tolerance():
    agent = make_agent({"move_forward": 0.25})
    agent.controls.move_filter_fn = lambda start, end: start + 0.5 * (end - start)
    assert agent.act("move_forward") is True
    np.testing.assert_allclose(agent.state.position, [0.0, 0.0, -0.125], atol=1e-12)
    # a filter that only lifts the step (stairs) moves at least as far: no collision
    agent.controls.move_filter_fn = lambda start, end: end + np.array([0.0, 0.1, 0.0])
    assert agent.act("move_forward") is False


def test_set_state_round_trip_and_nan_refused_at_set_state():
    agent = make_agent({"move_forward": 0.25})
    state = agent.state
    agent.set_state(state, infer_sensor_states=True)
    check_delta(state, agent.state)
    check_delta(state.sensor_states["eye"], agent.state.sensor_states["eye"])
    state.position = np.array([float("nan")] * 3)  # stored, as Habitat's attrs class does
    before = agent.state
    with pytest.raises(ValueError, match="finite"):
        agent.set_state(state)
    check_delta(before, agent.state)  # unchanged
    with pytest.raises(ValueError):
        habitat_sim.AgentState([float("nan"), 0.0, 0.0])  # the constructor validates


def test_set_state_without_inferring_sensor_states_places_sensors_in_the_world():
    rng = np.random.default_rng(233)
    agent = make_agent({"move_forward": 0.25})
    for _ in range(20):
        state = agent.state
        state.position += rng.uniform(-1, 1, size=3)
        # Habitat's own lines: the quaternion type of utils.common composes with the state's
        state.rotation *= quat_from_angle_axis(rng.uniform(0, 2 * math.pi), np.array([0.0, 1, 0]))
        for pose in state.sensor_states.values():
            pose.position += rng.uniform(-1, 1, size=3)
            pose.rotation *= quat_from_angle_axis(
                rng.uniform(0, 2 * math.pi), np.array([1.0, 1.0, 1.0])
            )
        agent.set_state(state, infer_sensor_states=False)
        new_state = agent.state
        check_delta(state, new_state)
        check_delta(state.sensor_states["eye"], new_state.sensor_states["eye"])


def test_reset_sensors_false_keeps_a_looked_up_sensor():
    agent = make_agent({"look_up": 10.0})
    agent.act("look_up")
    looked = agent.state.sensor_states["eye"].rotation
    agent.set_state(habitat_sim.AgentState([1.0, 0.0, 0.0]), reset_sensors=False)
    assert rotation_angle_between(agent.state.sensor_states["eye"].rotation, looked) < 1e-9
    agent.set_state(habitat_sim.AgentState([1.0, 0.0, 0.0]))  # reset_sensors=True
    assert rotation_angle_between(agent.state.sensor_states["eye"].rotation, mn.Quaternion()) < 1e-9


def test_agent_defaults_sensors_by_uuid_and_is_initial():
    agent = habitat_sim.Agent(habitat_sim.SceneGraph().get_root_node().create_child())
    assert agent.initial_state is None and agent.sensors == {}
    assert set(agent.agent_config.action_space) == {"move_forward", "turn_left", "turn_right"}
    agent = make_agent({"move_forward": 0.25})
    assert list(agent.sensors) == ["eye"] and agent.sensors["eye"].object is not None
    state = habitat_sim.AgentState([0.0, 1.0, 0.0])
    agent.set_state(state, is_initial=True)
    assert agent.initial_state is state
    agent.state = habitat_sim.AgentState([2.0, 0.0, 0.0])  # the setter: set_state defaults
    np.testing.assert_allclose(agent.state.position, [2.0, 0.0, 0.0])
    assert agent.initial_state is state


def test_scene_graph_nodes():
    graph = habitat_sim.SceneGraph()
    root = graph.get_root_node()
    child = root.create_child()
    grandchild = child.create_child()
    assert child.parent is root and grandchild.get_root_node() is root
    child.translate([1.0, 0.0, 0.0])
    np.testing.assert_allclose(np.asarray(grandchild.absolute_translation), [1.0, 0.0, 0.0])
    grandchild.rotate_y_local(mn.Deg(90.0))
    grandchild.reset_transformation()
    assert rotation_angle_between(grandchild.rotation, mn.Quaternion()) == 0.0


def test_registry_alone_knows_the_default_controls():
    import subprocess
    import sys

    code = (
        "import engine.registry as r; print(r.get_move_fn('move_forward').body_action, "
        "r.get_move_fn('look_up').body_action)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["True", "False"]
