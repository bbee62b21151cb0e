"""Issue acceptance: a greedy follower walks the demo apartment's navmesh to random goals.

The follower is the simplest controller a Habitat user writes: ask the PathFinder for the
shortest path, turn (30 degree steps) towards its next corner until it lies within half a
turn of the heading, then step 0.25 m forward through ``sim.step_filter``. Shortest paths
hug the navmesh boundary, so without sliding a step can be blocked outright; then the
follower is greedy on geodesic distance, as Habitat's greedy follower is: it probes the
headings one and two turns away with ``sim.step_filter`` and commits to the turns and step
that bring it closest to the goal. Goals are random
navigable points more than 2 m (geodesic) away on the main island. The bars come from the
navigation issue: at least 95 % of 100 episodes reach the goal with sliding, 90 % without.
"""

import math

import numpy as np
import pytest

import engine as habitat_sim
from engine import mn
from engine.utils.common import quat_to_magnum
from navmesh import ShortestPath

TURN_DEGREES = 30.0
STEP_METERS = 0.25
SUCCESS_RADIUS = 0.25  # m: within one step of the goal
MAX_ACTIONS = 300


def make_sim(demo_data, allow_sliding: bool):
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = str(demo_data / "scene_datasets/demo/apartment.glb")
    sim_cfg.allow_sliding = allow_sliding
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    agent_cfg.action_space["move_forward"].actuation.amount = STEP_METERS
    agent_cfg.action_space["turn_left"].actuation.amount = TURN_DEGREES
    agent_cfg.action_space["turn_right"].actuation.amount = TURN_DEGREES
    return habitat_sim.Simulator(habitat_sim.Configuration(sim_cfg, [agent_cfg]))


def geodesic(pathfinder, start, end) -> tuple[float, np.ndarray]:
    path = ShortestPath()
    path.requested_start, path.requested_end = start, end
    if not pathfinder.find_path(path):
        return math.inf, np.zeros((0, 3))
    return path.geodesic_distance, np.asarray(path.points)


def next_action(agent, corner: np.ndarray) -> str:
    """Turn towards ``corner`` unless it is within half a turn of the heading, else move."""
    state = agent.get_state()
    forward = quat_to_magnum(state.rotation).transform_vector([0.0, 0.0, -1.0])
    to_corner = corner - state.position
    # signed angle about +Y from forward to the corner: atan2(cross.y, dot) in the xz-plane
    cross_y = forward.z * to_corner[0] - forward.x * to_corner[2]
    dot = forward.x * to_corner[0] + forward.z * to_corner[2]
    angle = math.degrees(math.atan2(cross_y, dot))
    if abs(angle) <= TURN_DEGREES / 2:
        return "move_forward"
    return "turn_left" if angle > 0 else "turn_right"


def unblocking_plan(sim, agent, goal) -> list[str]:
    """After a blocked step: the turns (then a step) whose filtered step ends nearest the goal."""
    state = agent.get_state()
    best_distance, best_plan = math.inf, ["turn_left"]
    for turns in (-2, -1, 1, 2):
        turn = mn.Quaternion.rotation(mn.Deg(turns * TURN_DEGREES), [0, 1, 0])
        heading = quat_to_magnum(state.rotation) * turn
        step = np.asarray(heading.transform_vector([0.0, 0.0, -STEP_METERS]))
        landed = np.asarray(sim.step_filter(state.position, state.position + step))
        if np.linalg.norm(landed - state.position) < 0.01:
            continue  # that heading is blocked too
        distance = geodesic(sim.pathfinder, landed, goal)[0]
        if distance < best_distance:
            name = "turn_left" if turns > 0 else "turn_right"
            best_distance, best_plan = distance, [name] * abs(turns) + ["move_forward"]
    return best_plan


def run_episode(sim, start, goal, yaw) -> bool:
    agent = sim.initialize_agent(
        0, habitat_sim.AgentState(start, mn.Quaternion.rotation(mn.Rad(yaw), [0, 1, 0])))
    plan: list[str] = []
    for _ in range(MAX_ACTIONS):
        distance, points = geodesic(sim.pathfinder, agent.get_state().position, goal)
        if distance < SUCCESS_RADIUS:
            return True
        if len(points) < 2:
            return False
        action = plan.pop(0) if plan else next_action(agent, points[1])
        if agent.act(action) and action == "move_forward" and not plan:
            plan = unblocking_plan(sim, agent, goal)
    return False


def episodes(sim, count: int, seed: int):
    """``count`` (start, goal, yaw) triples on the main island, goals > 2 m away."""
    rng = np.random.default_rng(seed)
    sim.pathfinder.seed(seed)
    found = []
    while len(found) < count:
        start = sim.pathfinder.get_random_navigable_point(island_index=0)
        goal = sim.pathfinder.get_random_navigable_point(island_index=0)
        if geodesic(sim.pathfinder, start, goal)[0] > 2.0:
            found.append((start, goal, rng.uniform(-math.pi, math.pi)))
    return found


@pytest.mark.parametrize("allow_sliding, bar", [(True, 0.95), (False, 0.90)])
def test_greedy_follower_reaches_random_goals(demo_data, allow_sliding, bar):
    with make_sim(demo_data, allow_sliding) as sim:
        assert sim.pathfinder.is_loaded  # apartment.navmesh ships with the dataset
        runs = episodes(sim, 100, seed=7)
        successes = sum(run_episode(sim, *run) for run in runs)
    assert successes / len(runs) >= bar, f"{successes} of {len(runs)} episodes reached the goal"
