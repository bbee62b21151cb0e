"""Gymnasium environments ``rigidsim/PointNav-v0`` and ``rigidsim/PushObject-v0``.

Both must pass Gymnasium's environment checker, be deterministic under ``reset(seed=...)``
and run in an asynchronous vector env (worker processes). Task semantics follow Habitat's
PointNav (polar goal, success within 0.2 m, SPL) and the push task's documented reward.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import engine.envs  # noqa: F401  (registers the ids)
from engine.envs import (
    POINT_NAV_ID,
    PUSH_OBJECT_ID,
    PointNavEnv,
    PushObjectEnv,
    scripted_push_action,
)
from engine.envs.greedy_follower import TURN_LEFT, greedy_action, run_greedy_episode
from engine.envs.push_object import CONTROL_DT, MAX_LINEAR_SPEED


@pytest.fixture(scope="module")
def point_nav():
    env = PointNavEnv()
    yield env
    env.close()


@pytest.mark.parametrize("env_id", [POINT_NAV_ID, PUSH_OBJECT_ID])
def test_environment_checker_passes(env_id):
    env = gym.make(env_id)
    try:
        check_env(env.unwrapped, skip_render_check=True)
    finally:
        env.close()


def rollout(env, seed: int, actions) -> list:
    observation, _ = env.reset(seed=seed)
    trace = [observation]
    for action in actions:
        observation, reward, terminated, _, _ = env.step(action)
        trace.append((observation, reward))
        if terminated:
            break
    return trace


def flatten(trace) -> list[np.ndarray]:
    arrays = []
    for item in trace:
        for part in item if isinstance(item, tuple) else (item,):
            values = part.values() if isinstance(part, dict) else [part]
            arrays.extend(np.asarray(v) for v in values)
    return arrays


@pytest.mark.parametrize("make", [PointNavEnv, PushObjectEnv], ids=["PointNav", "PushObject"])
def test_same_seed_same_episode_bit_for_bit(make):
    env = make()
    try:
        actions = [env.action_space.sample() for _ in range(6)]
        first, again = rollout(env, 5, actions), rollout(env, 5, actions)
        other = rollout(env, 6, actions)
    finally:
        env.close()
    assert all(np.array_equal(a, b) for a, b in zip(flatten(first), flatten(again), strict=True))
    assert not np.array_equal(flatten(first)[-1], flatten(other)[-1]) or not np.array_equal(
        flatten(first)[0], flatten(other)[0]
    )


def test_pointgoal_is_the_goal_in_polar_coordinates(point_nav):
    observation, info = point_nav.reset(seed=2)
    state = point_nav.sim.get_agent(0).get_state()
    offset = point_nav.goal - state.position
    rho, phi = observation["pointgoal"]
    assert rho == pytest.approx(math.hypot(offset[0], offset[2]), rel=1e-5)
    assert info["distance_to_goal"] >= rho - 1e-5  # the geodesic is never shorter
    # a 10 degree turn to the left moves the goal 10 degrees to the right (phi - 10 deg)
    observation, reward, terminated, _, info = point_nav.step(TURN_LEFT)
    new_rho, new_phi = observation["pointgoal"]
    assert new_rho == pytest.approx(rho, rel=1e-5)
    turned = (new_phi - phi + math.pi) % (2 * math.pi) - math.pi
    assert turned == pytest.approx(-math.radians(10.0), abs=1e-5)
    assert reward == pytest.approx(-0.01) and not terminated  # only the slack


def test_depth_and_rgb_are_the_cameras_view(point_nav):
    observation, _ = point_nav.reset(seed=4)
    depth, rgb = observation["depth"], observation["rgb"]
    assert depth.shape == (64, 64, 1) and rgb.shape == (64, 64, 3)
    # indoors: every pixel sees a surface within the apartment (depth > 0, finite, <= 10 m)
    assert np.all(depth > 0.0) and np.all(depth <= 10.0)
    assert rgb.std() > 5  # a textured room, not a blank frame


def test_greedy_follower_succeeds_with_spl_near_one(point_nav):
    result = run_greedy_episode(point_nav, seed=3)
    assert result["success"] and result["distance_to_goal"] < 0.2
    # the follower walks the shortest path in 0.25 m steps and 10 degree turns
    assert 0.8 < result["spl"] <= 1.0
    assert greedy_action(point_nav) in range(4)


def test_stop_away_from_the_goal_fails(point_nav):
    _, info = point_nav.reset(seed=8)
    assert info["distance_to_goal"] >= 1.0  # episodes start at least 1 m away
    _, reward, terminated, _, info = point_nav.step(0)
    assert terminated and not info["success"] and info["spl"] == 0.0
    assert reward == pytest.approx(-0.01)


def test_pushing_straight_moves_the_cube_along_the_heading():
    env = PushObjectEnv()
    try:
        observation, info = env.reset(seed=1)
        heading = observation[2:4]  # cos yaw, sin yaw; forward = (-sin yaw, -cos yaw)
        forward = np.array([-heading[1], -heading[0]])
        cube_start = observation[4:6].copy()
        total = 0.0
        for _ in range(20):
            observation, reward, terminated, _, info = env.step(np.array([1.0, 0.0]))
            total += reward
            if terminated:
                break
        world_time = env.sim.get_world_time()
    finally:
        env.close()
    robot = observation[0:2]
    # the dynamic robot is set to 0.5 m/s before every 8 ms physics step; within a step
    # damping (0.2: factor 0.8^h) and floor friction (mu = 0.5 x 0.5, loses mu g h) slow it,
    # and while it pushes, the cube's friction on the floor (0.5 kg of the robot's 4 kg)
    # costs mu g h / 8 more: about 0.4775 m/s along its heading, from the origin
    h = 0.008
    speed = MAX_LINEAR_SPEED * 0.8**h - 0.25 * 9.8 * h * (1 + 0.5 / 4.0)
    assert world_time == pytest.approx(CONTROL_DT * 20, abs=h / 2) or terminated
    assert np.linalg.norm(robot) == pytest.approx(speed * world_time, rel=0.03)
    moved = observation[4:6] - cube_start
    assert np.linalg.norm(moved) > 0.2  # it was reached and pushed
    assert moved @ forward / np.linalg.norm(moved) > 0.9  # along the heading (25 degrees)


def test_the_scripted_pusher_puts_the_cube_on_the_target():
    env = PushObjectEnv()
    try:
        observation, info = env.reset(seed=5)
        assert info["cube_target"] > 0.4 and not info["success"]
        total = 0.0
        for _ in range(100):
            observation, reward, terminated, _, info = env.step(scripted_push_action(observation))
            total += reward
            if terminated:
                break
    finally:
        env.close()
    assert info["success"] and info["cube_target"] < 0.15
    # the cube rests on the floor (top face y = 0): its center 0.1 m up, within 5 mm
    assert info["cube_position"][1] == pytest.approx(0.1, abs=0.005)
    assert total > 10.0  # the success bonus plus the progress terms


@pytest.mark.parametrize("env_id", [POINT_NAV_ID, PUSH_OBJECT_ID])
def test_async_vector_env_of_two(env_id):
    envs = gym.make_vec(env_id, num_envs=2, vectorization_mode="async")
    try:
        observations, _ = envs.reset(seed=[3, 4])
        first = observations["pointgoal"] if isinstance(observations, dict) else observations
        assert first.shape[0] == 2 and not np.array_equal(first[0], first[1])
        envs.action_space.seed(0)
        for _ in range(3):
            observations, rewards, terminated, truncated, _ = envs.step(envs.action_space.sample())
            assert rewards.shape == (2,) and np.all(np.isfinite(rewards))
        # the same seeds in this process give the same first observation as the workers
        single = gym.make(env_id)
        alone, _ = single.reset(seed=4)
        single.close()
        alone = alone["pointgoal"] if isinstance(alone, dict) else alone
        np.testing.assert_array_equal(alone, first[1])
    finally:
        envs.close()
