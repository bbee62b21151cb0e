"""A scripted PointNav agent: follow the navmesh's shortest path, stop at the goal.

Habitat's ``ShortestPathFollower`` in its simplest form (the oracle behind PointNav's SPL
upper bound): ask the PathFinder for the shortest path from the agent to the goal, turn
towards its next corner until that corner lies within half a turn of the heading, then step
forward; call ``stop`` once the geodesic distance is under the success radius. The signed
angle to the corner, about +Y, in the floor plane is

    angle = atan2(f_z c_x - f_x c_z, f_x c_x + f_z c_z)

with ``f`` the agent's forward (-Z) and ``c`` the vector to the corner; positive is to the
left, where ``turn_left`` goes.
"""

from __future__ import annotations

import math

import numpy as np

from engine.envs.point_nav import ACTIONS, SUCCESS_DISTANCE, PointNavEnv
from engine.utils.common import quat_rotate_vector
from navmesh import ShortestPath

STOP, MOVE_FORWARD, TURN_LEFT, TURN_RIGHT = range(len(ACTIONS))


def greedy_action(env: PointNavEnv, turn_degrees: float = 10.0) -> int:
    """The follower's next action in ``env`` (an unwrapped :class:`PointNavEnv`)."""
    state = env.sim.get_agent(0).get_state()
    path = ShortestPath()
    path.requested_start, path.requested_end = state.position, env.goal
    if not env.sim.pathfinder.find_path(path) or path.geodesic_distance < SUCCESS_DISTANCE:
        return STOP
    points = np.asarray(path.points)
    if len(points) < 2:
        return STOP
    forward = quat_rotate_vector(state.rotation, [0.0, 0.0, -1.0])
    to_corner = points[1] - np.asarray(state.position)
    # signed angle from forward to the corner about +Y (module docstring)
    cross_y = forward[2] * to_corner[0] - forward[0] * to_corner[2]
    dot = forward[0] * to_corner[0] + forward[2] * to_corner[2]
    angle = math.degrees(math.atan2(cross_y, dot))
    if abs(angle) <= turn_degrees / 2:
        return MOVE_FORWARD
    return TURN_LEFT if angle > 0 else TURN_RIGHT


def run_greedy_episode(env: PointNavEnv, seed: int, max_actions: int = 500) -> dict:
    """One PointNav episode driven by :func:`greedy_action`; returns the final info
    (``success``, ``spl``, ``distance_to_goal``...) and the number of actions."""
    env.reset(seed=seed)
    info: dict = {}
    actions = 0
    while actions < max_actions:
        _, _, terminated, _, info = env.step(greedy_action(env))
        actions += 1
        if terminated:
            break
    return {**info, "actions": actions}
