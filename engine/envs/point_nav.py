"""``rigidsim/PointNav-v0``: Habitat's point-goal navigation task as a Gymnasium environment.

The agent starts at a random navigable point of the demo apartment, facing a random
direction, and must reach a goal given only as a direction and distance (Habitat's
``PointGoalWithGPSCompassSensor``). Following Habitat-lab's PointNav task (Anderson et al.,
"On Evaluation of Embodied Navigation Agents", 2018; Savva et al., "Habitat", ICCV 2019):

- actions (Discrete(4), Habitat's order): 0 ``stop``, 1 ``move_forward`` (0.25 m, through
  the navmesh step filter), 2 ``turn_left``, 3 ``turn_right`` (10 degrees);
- observations (a Dict): ``rgb`` ``(H, W, 3)`` uint8 and ``depth`` ``(H, W, 1)`` float32 z-depth in
  meters clipped to [0, 10] from a camera 1.25 m above the floor, and ``pointgoal``
  ``[rho, phi]``: the goal in polar coordinates in the agent's frame, rho in meters and phi
  in radians, positive to the agent's left (a ``turn_left`` brings it towards 0)::

      d = R^-1 (goal - position)          (agent frame: forward is -z, right is +x)
      rho = |(d_x, d_z)|,  phi = atan2(-d_x, -d_z);

- the episode ends when the agent calls ``stop`` (terminated) or after 500 actions
  (truncated, by the registered TimeLimit); it succeeds when ``stop`` is called within
  0.2 m (geodesic) of the goal;
- reward (Habitat-lab's): ``-0.01`` per action, plus the decrease of the geodesic distance
  to the goal, plus 2.5 on success;
- ``info``: ``distance_to_goal`` (geodesic, m), ``success``, ``spl`` = success *
  shortest / max(shortest, travelled), ``collided`` (the navmesh shortened the move) and
  ``path_length`` (m travelled).

Episodes (start, goal) are drawn from the navmesh with the environment's seeded generator:
``reset(seed=s)`` always gives the same episode, and the simulator is deterministic, so the
same actions give the same observations bit for bit. Sensors are small by default (64 x 64)
so that many environments run fast.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

import engine as habitat_sim
from engine import mn
from engine.demo import demo_data_path
from engine.utils.common import quat_rotate_vector
from navmesh import ShortestPath

ACTIONS = ("stop", "move_forward", "turn_left", "turn_right")
SENSOR_HEIGHT = 1.25  # m above the agent's feet (Habitat-lab's PointNav agent)
MAX_DEPTH = 10.0  # m: depth beyond is clipped (Habitat's DEPTH_SENSOR max_depth)
SUCCESS_DISTANCE = 0.2  # m, geodesic
SLACK_REWARD = -0.01
SUCCESS_REWARD = 2.5
MIN_GEODESIC = 1.0  # m: shortest start-goal distance of an episode
MAX_EPISODE_TRIES = 200  # random (start, goal) draws before giving up


class PointNavEnv(gym.Env):
    """Point-goal navigation in the demo apartment (see the module docstring).

    Parameters
    ----------
    resolution : (int, int)
        ``[height, width]`` of the rgb and depth sensors.
    hfov : float
        Horizontal field of view, degrees.
    render_mode : None or "rgb_array"
        ``render()`` returns the last rgb observation.
    scene_id : str or None
        Stage to load (default: the demo apartment, with its navmesh).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(
        self,
        resolution: tuple[int, int] = (64, 64),
        hfov: float = 90.0,
        render_mode: str | None = None,
        scene_id: str | None = None,
    ) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        height, width = (int(v) for v in resolution)
        self.render_mode = render_mode
        self._sim = habitat_sim.Simulator(_configuration(scene_id, (height, width), hfov))
        if not self._sim.pathfinder.is_loaded:
            raise ValueError(f"PointNav needs a navmesh beside the scene {scene_id!r}")
        self.action_space = spaces.Discrete(len(ACTIONS))
        low, high = self._sim.pathfinder.get_bounds()
        max_rho = float(np.linalg.norm(np.asarray(high) - np.asarray(low)))  # scene diagonal
        self.observation_space = spaces.Dict(
            {
                "rgb": spaces.Box(0, 255, (height, width, 3), np.uint8),
                "depth": spaces.Box(0.0, MAX_DEPTH, (height, width, 1), np.float32),
                "pointgoal": spaces.Box(
                    np.array([0.0, -math.pi], np.float32),
                    np.array([max_rho, math.pi], np.float32),
                    dtype=np.float32,
                ),
            }
        )
        self._goal = np.zeros(3)
        self._shortest = self._distance = self._travelled = 0.0
        self._last_rgb: np.ndarray | None = None

    # --------------------------------------------------------------------------------------
    # Gymnasium API
    # --------------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        start, goal, yaw = self._sample_episode()
        rotation = mn.Quaternion.rotation(mn.Rad(yaw), [0.0, 1.0, 0.0])
        self._sim.initialize_agent(0, habitat_sim.AgentState(start, rotation))
        self._goal = goal
        self._shortest = self._distance = self.geodesic_distance(start)
        self._travelled = 0.0
        return self._observe(), self._info(success=False, collided=False)

    def step(self, action: int):
        """Take one discrete action (0 ``stop``, 1 ``move_forward``, 2 ``turn_left``, 3
        ``turn_right``).

        Returns Gymnasium's ``(observation, reward, terminated, truncated, info)``:
        ``terminated`` when the action is ``stop``; ``truncated`` is always False here (the
        registered TimeLimit truncates); the reward and ``info`` are those of the module
        docstring. Raises ``ValueError`` for an action outside the action space.
        """
        if not self.action_space.contains(action):
            raise ValueError(f"action must be 0..{len(ACTIONS) - 1}, got {action!r}")
        name = ACTIONS[int(action)]
        agent = self._sim.get_agent(0)
        before = agent.get_state().position
        collided = False if name == "stop" else bool(agent.act(name))
        self._travelled += float(np.linalg.norm(agent.get_state().position - before))
        previous, self._distance = self._distance, self.geodesic_distance()
        success = name == "stop" and self._distance < SUCCESS_DISTANCE
        reward = SLACK_REWARD + (previous - self._distance) + SUCCESS_REWARD * success
        observation = self._observe()
        return observation, float(reward), name == "stop", False, self._info(success, collided)

    def render(self) -> np.ndarray | None:
        if self.render_mode == "rgb_array":
            return self._last_rgb
        return None

    def close(self) -> None:
        self._sim.close()

    # --------------------------------------------------------------------------------------
    # Task
    # --------------------------------------------------------------------------------------
    @property
    def sim(self) -> habitat_sim.Simulator:
        """The environment's simulator (for a scripted agent or a look at the scene)."""
        return self._sim

    @property
    def goal(self) -> np.ndarray:
        """The goal position, world frame, m."""
        return self._goal.copy()

    def geodesic_distance(self, position: np.ndarray | None = None) -> float:
        """Shortest-path distance on the navmesh from ``position`` (default: the agent)."""
        path = ShortestPath()
        path.requested_start = (
            self._sim.get_agent(0).get_state().position
            if position is None
            else np.asarray(position)
        )
        path.requested_end = self._goal
        if not self._sim.pathfinder.find_path(path):
            return math.inf
        return float(path.geodesic_distance)

    def _sample_episode(self) -> tuple[np.ndarray, np.ndarray, float]:
        """A (start, goal, yaw) on the main island, goal >= MIN_GEODESIC away (geodesic)."""
        pathfinder = self._sim.pathfinder
        pathfinder.seed(int(self.np_random.integers(2**31 - 1)))
        for _ in range(MAX_EPISODE_TRIES):
            start = np.asarray(pathfinder.get_random_navigable_point(island_index=0))
            goal = np.asarray(pathfinder.get_random_navigable_point(island_index=0))
            self._goal = goal
            if MIN_GEODESIC <= self.geodesic_distance(start) < math.inf:
                return start, goal, float(self.np_random.uniform(-math.pi, math.pi))
        raise RuntimeError(
            f"no start and goal {MIN_GEODESIC} m apart in "
            f"{MAX_EPISODE_TRIES} draws: is the navmesh too small?"
        )

    def _pointgoal(self) -> np.ndarray:
        """``[rho, phi]`` of the goal in the agent's frame (see the module docstring)."""
        state = self._sim.get_agent(0).get_state()
        # d = R^-1 (goal - position): the goal in the agent's frame
        d = quat_rotate_vector(state.rotation.inverse(), self._goal - state.position)
        rho = math.hypot(d[0], d[2])
        phi = math.atan2(-d[0], -d[2])
        return np.array([rho, phi], dtype=np.float32)

    def _observe(self) -> dict[str, np.ndarray]:
        observation = self._sim.get_sensor_observations()
        rgb = np.ascontiguousarray(observation["rgb"][..., :3])
        depth = np.clip(observation["depth"], 0.0, MAX_DEPTH)[..., None].astype(np.float32)
        self._last_rgb = rgb
        return {"rgb": rgb, "depth": depth, "pointgoal": self._pointgoal()}

    def _info(self, success: bool, collided: bool) -> dict[str, Any]:
        spl = float(success) * self._shortest / max(self._shortest, self._travelled, 1e-9)
        return {
            "distance_to_goal": self._distance,
            "success": bool(success),
            "spl": spl,
            "collided": collided,
            "path_length": self._travelled,
        }


def _configuration(
    scene_id: str | None, resolution: tuple[int, int], hfov: float
) -> habitat_sim.Configuration:
    """The apartment (or ``scene_id``) and one agent with rgb and depth cameras."""
    sim_cfg = habitat_sim.SimulatorConfiguration()
    sim_cfg.scene_id = scene_id or str(demo_data_path() / "scene_datasets/demo/apartment.glb")
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    specs = []
    for uuid, sensor_type in (
        ("rgb", habitat_sim.SensorType.COLOR),
        ("depth", habitat_sim.SensorType.DEPTH),
    ):
        spec = habitat_sim.CameraSensorSpec()
        spec.uuid, spec.sensor_type = uuid, sensor_type
        spec.resolution, spec.hfov = list(resolution), float(hfov)
        spec.position = [0.0, SENSOR_HEIGHT, 0.0]
        specs.append(spec)
    agent_cfg.sensor_specifications = specs
    return habitat_sim.Configuration(sim_cfg, [agent_cfg])
