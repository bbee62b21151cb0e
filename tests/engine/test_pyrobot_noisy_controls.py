"""Habitat's noisy PyRobot controls: the measured noise means, no noise at multiplier 0, seeds.

Habitat's test_pyrobot_noisy_controls.py protocol: from the identity pose, compare each noisy
action with its perfect twin over many samples; the mean translation offset (along, across)
must match the model's linear mean times the multiplier within 5 cm. Here with fewer samples
(CI budget) and the same tolerance, plus the rotation mean and seeding by ``sim.seed``.
"""

from __future__ import annotations

import numpy as np
import pytest

import engine as habitat_sim
from engine.agent.controls.pyrobot_noisy_controls import pyrobot_noise_models, seed_noise
from engine.scene.graph import SceneGraph

SAMPLES = 120


def noisy_agent(robot: str, controller: str, multiplier: float):
    spec = habitat_sim.PyRobotNoisyActuationSpec
    space = {
        f"noisy_{name}": habitat_sim.ActionSpec(
            f"pyrobot_noisy_{name}",
            spec(amount=amount, robot=robot, controller=controller, noise_multiplier=multiplier),
        )
        for name, amount in (("move_forward", 1.0), ("turn_left", 90.0))
    }
    space["move_forward"] = habitat_sim.ActionSpec("move_forward", habitat_sim.ActuationSpec(1.0))
    space["turn_left"] = habitat_sim.ActionSpec("turn_left", habitat_sim.ActuationSpec(90.0))
    config = habitat_sim.AgentConfiguration()
    config.action_space = space
    return habitat_sim.Agent(SceneGraph().get_root_node().create_child(), config)


def offsets(agent, action: str) -> tuple[np.ndarray, np.ndarray]:
    """(SAMPLES, 2) translation offsets (forward, right) and (SAMPLES,) yaw offsets (rad)."""
    start = habitat_sim.AgentState()
    agent.state = start
    agent.act(action)
    base = agent.state
    moves, yaws = [], []
    for _ in range(SAMPLES):
        agent.state = start
        agent.act(f"noisy_{action}")
        noisy = agent.state
        d = np.asarray(noisy.position) - np.asarray(base.position)
        moves.append([-d[2], d[0]])
        yaws.append(2.0 * np.arctan2(noisy.rotation.y, noisy.rotation.w) - np.pi / 2)
    return np.array(moves), np.array(yaws)


@pytest.mark.parametrize("robot", ["LoCoBot", "LoCoBot-Lite"])
@pytest.mark.parametrize("controller", ["ILQR", "Proportional", "Movebase"])
def test_noisy_moves_have_the_measured_mean_offsets(robot, controller):
    seed_noise(0)
    agent = noisy_agent(robot, controller, 1.0)
    moves, _ = offsets(agent, "move_forward")
    model = pyrobot_noise_models[robot][controller].linear_motion
    assert np.linalg.norm(model.linear.mean - np.abs(moves.mean(axis=0))) < 5e-2
    _, yaws = offsets(agent, "turn_left")
    rotation_model = pyrobot_noise_models[robot][controller].rotational_motion
    assert abs(yaws.mean() - rotation_model.rotation.mean[0]) < 5e-2  # turns overshoot


def test_no_noise_at_multiplier_zero():
    agent = noisy_agent("LoCoBot", "ILQR", 0.0)
    moves, _ = offsets(agent, "move_forward")
    np.testing.assert_allclose(moves, 0.0, atol=1e-12)


@pytest.mark.parametrize("heading_degrees", [0.0, 60.0, 120.0, -150.0])
def test_a_turned_agent_moves_along_its_own_heading(heading_degrees):
    """The noisy offset is built from the node's axes in the parent frame: a turned agent goes
    where it faces, exactly without noise and on average with it (a rotated offset would go
    off at twice the heading)."""
    seed_noise(1)
    start = habitat_sim.AgentState()
    half = np.radians(heading_degrees) / 2.0
    start.rotation = np.quaternion(np.cos(half), 0.0, np.sin(half), 0.0)  # about +Y
    facing = np.array([-np.sin(2 * half), 0.0, -np.cos(2 * half)])  # R (0, 0, -1)
    for multiplier, samples, tolerance in ((0.0, 1, 1e-12), (1.0, SAMPLES, 0.03)):
        agent = noisy_agent("LoCoBot", "ILQR", multiplier)
        steps = []
        for _ in range(samples):
            agent.state = start
            agent.act("noisy_move_forward")
            steps.append(np.asarray(agent.state.position) - np.asarray(start.position))
        mean_step = np.mean(steps, axis=0)
        np.testing.assert_allclose(mean_step / np.linalg.norm(mean_step), facing, atol=tolerance)


def test_the_simulator_seed_fixes_the_noisy_trajectory(demo_data):
    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(demo_data / "scene_datasets/demo/apartment.glb")
    agent_cfg = habitat_sim.AgentConfiguration()
    agent_cfg.action_space["noisy_forward"] = habitat_sim.ActionSpec(
        "pyrobot_noisy_move_forward", habitat_sim.PyRobotNoisyActuationSpec(amount=0.25)
    )
    with habitat_sim.Simulator(habitat_sim.Configuration(cfg, [agent_cfg])) as sim:
        start = sim.pathfinder.get_random_navigable_point()

        def walk(seed: int) -> list[list[float]]:
            sim.seed(seed)
            sim.get_agent(0).state = habitat_sim.AgentState(start)
            return [
                sim.get_agent(0).act("noisy_forward") or sim.get_agent(0).state.position.tolist()
                for _ in range(5)
            ]

        assert walk(7) == walk(7)
        assert walk(7) != walk(8)


def test_unknown_robots_and_controllers_are_refused():
    with pytest.raises(ValueError, match="Roomba"):
        habitat_sim.PyRobotNoisyActuationSpec(amount=0.25, robot="Roomba")
    with pytest.raises(ValueError, match="PID"):
        habitat_sim.PyRobotNoisyActuationSpec(amount=0.25, controller="PID")
