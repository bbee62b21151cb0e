"""``rigidsim/PushObject-v0``: the locobot pushes a cube onto a target patch on the floor.

A continuous-control task on rigidsim's physics. The world is a 6 x 6 m floor slab (a
STATIC box, top face at y = 0), a 20 cm cube of 0.5 kg and the locobot (4 kg), both
DYNAMIC. The robot is driven by its ``VelocityControl``: the command sets its local linear
velocity along -Z (forward) and its angular velocity about +Y; contacts push the cube, and
the cube pushes back (the robot slows while it pushes).

The command is applied at the physics rate. Habitat's dynamic velocity control sets the
velocity once per ``step_physics`` call, after which gravity and contacts act: a body
sliding on the floor loses ``mu g`` of speed per second (pair friction ``mu`` = 0.5 x 0.5
here), so one call of 0.1 s would let the robot coast down from 0.5 to 0.26 m/s and average
about 0.36 m/s. The environment therefore runs each action as fixed steps of
``get_physics_time_step()`` (0.008 s) and the command is set again before each one: the
robot loses only ``mu g h`` = 0.02 m/s to friction per step and drives at about 0.48 m/s
(``tests/physics/test_velocity_control_friction.py`` checks both cases against Coulomb's
law).

- action (Box [-1, 1]^2): ``[forward, turn]``, scaled to ``forward * 0.5 m/s`` and
  ``turn * 1.5 rad/s``; held for 0.1 s of simulated time (one control step);
- observation (Box, 10 float32, world frame, m): robot ``x, z``, robot heading
  ``cos yaw, sin yaw`` (yaw about +Y, 0 when facing -Z), cube ``x, z``, target ``x, z``,
  and cube-to-target ``dx, dz``;
- dense reward per step, with d_ct the cube-target and d_rc the robot-cube distance:

      r = 10 (d_ct_before - d_ct) + (d_rc_before - d_rc) - 0.01 + 10 [success]

  (progress of the cube to the target, of the robot to the cube, a time cost, a bonus);
- terminated when the cube's center is within 0.15 m of the target (success) or the cube
  left the floor; the registered TimeLimit truncates after 200 steps (20 s).

``reset(seed=s)`` builds a fresh simulator and draws the layout from the environment's
seeded generator: the robot at the origin with a random heading, the cube 0.5-0.8 m in
front of it, the target 0.4-0.8 m beyond the cube within 45 degrees of the same line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

import engine as habitat_sim
from engine import mn
from engine.demo import demo_data_path
from engine.physics import ManagedRigidObject

MotionType = habitat_sim.physics.MotionType

CONTROL_DT = 0.1  # s of simulated time per action
MAX_LINEAR_SPEED = 0.5  # m/s
MAX_ANGULAR_SPEED = 1.5  # rad/s
FLOOR_HALF_SIZE = 3.0  # m: the floor is 6 x 6 m
CUBE_HALF_SIZE = 0.1  # m
CUBE_MASS = 0.5  # kg
TARGET_RADIUS = 0.15  # m
OBSERVATION_BOUND = 10.0  # m: observations are clipped to +-this
PROGRESS_WEIGHT, APPROACH_WEIGHT, TIME_COST, SUCCESS_BONUS = 10.0, 1.0, 0.01, 10.0


class PushObjectEnv(gym.Env):
    """The locobot pushes a cube onto a target patch (see the module docstring).

    Parameters
    ----------
    render_mode : None or "rgb_array"
        With "rgb_array", a camera behind and above the robot renders ``resolution`` frames.
    resolution : (int, int)
        ``[height, width]`` of the rendered frames.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(
        self, render_mode: str | None = None, resolution: tuple[int, int] = (96, 128)
    ) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self._resolution = tuple(int(v) for v in resolution)
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.observation_space = spaces.Box(
            -OBSERVATION_BOUND, OBSERVATION_BOUND, (10,), np.float32
        )
        self._sim: habitat_sim.Simulator | None = None
        self._robot: ManagedRigidObject  # the locobot, set by reset()
        self._cube: ManagedRigidObject  # the cube to push, set by reset()
        self._target = np.zeros(3)
        self._control_time = 0.0  # simulated seconds of the actions taken since reset

    # --------------------------------------------------------------------------------------
    # Gymnasium API
    # --------------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        if self._sim is not None:
            self._sim.close()
        self._sim, self._robot, self._cube = _build_world(self.render_mode, self._resolution)
        self._place(*self._sample_layout())
        self._control_time = self._sim.get_world_time()
        return self._observe(), self._info()

    def step(self, action: np.ndarray):
        """Drive the robot with ``action`` for one control step (0.1 s of simulated time).

        ``action`` is ``[forward, turn]``, clipped to [-1, 1]; the command is set again
        before every physics step of the control step. Returns Gymnasium's
        ``(observation, reward, terminated, truncated, info)``: the reward and the end
        conditions are those of the module docstring; ``truncated`` is always False here
        (the registered TimeLimit truncates). Raises ``RuntimeError`` before ``reset`` and
        ``ValueError`` for an action that is not 2 finite numbers.
        """
        if self._sim is None:
            raise RuntimeError("call reset() before step()")
        action = np.asarray(action, dtype=np.float64).reshape(-1)
        if action.shape != (2,) or not np.all(np.isfinite(action)):
            raise ValueError(f"action must be 2 finite numbers in [-1, 1], got {action!r}")
        forward, turn = np.clip(action, -1.0, 1.0)
        before = self._distances()
        control = self._robot.velocity_control
        control.linear_velocity = [0.0, 0.0, -forward * MAX_LINEAR_SPEED]
        control.angular_velocity = [0.0, turn * MAX_ANGULAR_SPEED, 0.0]
        self._advance_to(self._control_time + CONTROL_DT)
        after = self._distances()
        success = after["cube_target"] < TARGET_RADIUS
        fell = float(self._cube.translation[1]) < -CUBE_HALF_SIZE
        reward = (
            PROGRESS_WEIGHT * (before["cube_target"] - after["cube_target"])
            + APPROACH_WEIGHT * (before["robot_cube"] - after["robot_cube"])
            - TIME_COST
            + SUCCESS_BONUS * success
        )
        return self._observe(), float(reward), bool(success or fell), False, self._info()

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array" or self._sim is None:
            return None
        return np.ascontiguousarray(self._sim.get_sensor_observations()["camera"][..., :3])

    def close(self) -> None:
        if self._sim is not None:
            self._sim.close()
            self._sim = None

    # --------------------------------------------------------------------------------------
    # Task
    # --------------------------------------------------------------------------------------
    @property
    def sim(self) -> habitat_sim.Simulator | None:
        return self._sim

    def _advance_to(self, control_time: float) -> None:
        """Simulate up to ``control_time`` (s since reset) in fixed physics steps, one
        ``step_physics`` call each, so that the velocity control sets the command before
        every step (a controller at the physics rate). The world time ends within half a
        step of ``control_time`` (0.1 s per action is 12 or 13 steps of 0.008 s)."""
        sim = self._sim
        if sim is None:
            raise RuntimeError("PushObject: call reset() before step()")
        step = sim.get_physics_time_step()
        while sim.get_world_time() < control_time - 0.5 * step:
            sim.step_physics(step)
        self._control_time = control_time

    def _sample_layout(self) -> tuple[float, np.ndarray, np.ndarray]:
        """Robot heading, cube and target positions (floor plane, y of their centers)."""
        rng = self.np_random
        yaw = float(rng.uniform(-math.pi, math.pi))
        heading = np.array([-math.sin(yaw), 0.0, -math.cos(yaw)])  # R_y(yaw) applied to -Z
        cube = heading * rng.uniform(0.5, 0.8)
        turn = rng.uniform(-math.pi / 4, math.pi / 4)
        c, s = math.cos(turn), math.sin(turn)
        # the heading turned by `turn` about +Y: x' = c x + s z, z' = -s x + c z
        beyond = np.array([c * heading[0] + s * heading[2], 0.0, -s * heading[0] + c * heading[2]])
        target = cube + beyond * rng.uniform(0.4, 0.8)
        return yaw, cube + [0.0, CUBE_HALF_SIZE, 0.0], target

    def _place(self, yaw: float, cube: np.ndarray, target: np.ndarray) -> None:
        self._robot.translation = [0.0, 0.0, 0.0]
        self._robot.rotation = mn.Quaternion.rotation(mn.Rad(yaw), [0.0, 1.0, 0.0])
        self._cube.translation = cube
        self._target = np.asarray(target, dtype=np.float64)

    def _distances(self) -> dict[str, float]:
        robot = np.asarray(self._robot.translation)[[0, 2]]
        cube = np.asarray(self._cube.translation)[[0, 2]]
        return {
            "cube_target": float(np.linalg.norm(cube - self._target[[0, 2]])),
            "robot_cube": float(np.linalg.norm(cube - robot)),
        }

    def _observe(self) -> np.ndarray:
        robot = np.asarray(self._robot.translation)
        # heading: the robot's local -Z in the world, yaw = atan2(-f_x, -f_z)
        forward = np.asarray(self._robot.rotation.transform_vector([0.0, 0.0, -1.0]))
        yaw = math.atan2(-forward[0], -forward[2])
        cube = np.asarray(self._cube.translation)
        values = [
            robot[0],
            robot[2],
            math.cos(yaw),
            math.sin(yaw),
            cube[0],
            cube[2],
            self._target[0],
            self._target[2],
            self._target[0] - cube[0],
            self._target[2] - cube[2],
        ]
        return np.clip(np.array(values, dtype=np.float32), -OBSERVATION_BOUND, OBSERVATION_BOUND)

    def _info(self) -> dict[str, Any]:
        distances = self._distances()
        return {
            **distances,
            "success": distances["cube_target"] < TARGET_RADIUS,
            "cube_position": np.asarray(self._cube.translation, dtype=np.float64),
        }


def _build_world(render_mode: str | None, resolution: Sequence[int]):
    """A fresh simulator with the floor slab, the cube and the locobot (both dynamic)."""
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    if render_mode == "rgb_array":
        spec = habitat_sim.CameraSensorSpec()
        spec.uuid, spec.resolution = "camera", list(resolution)
        spec.position, spec.orientation = [0.0, 1.2, 0.8], [-0.7, 0.0, 0.0]
        agent_cfg.sensor_specifications = [spec]
    else:
        agent_cfg.sensor_specifications = []
    sim = habitat_sim.Simulator(
        habitat_sim.Configuration(habitat_sim.SimulatorConfiguration(), [agent_cfg])
    )
    templates, objects = sim.get_object_template_manager(), sim.get_rigid_object_manager()
    cube_handle = templates.get_template_handles("cubeSolid")[0]  # the unit cube, [-1, 1]^3
    floor = _add_box(
        templates,
        objects,
        cube_handle,
        "push_floor",
        [FLOOR_HALF_SIZE, 0.1, FLOOR_HALF_SIZE],
        100.0,
    )
    floor.translation = [0.0, -0.1, 0.0]  # top face at y = 0
    floor.motion_type = MotionType.STATIC  # after placing it: STATIC bodies do not move
    cube = _add_box(templates, objects, cube_handle, "push_cube", [CUBE_HALF_SIZE] * 3, CUBE_MASS)
    locobot_id = templates.load_configs(str(demo_data_path() / "objects/locobot_merged"))[0]
    robot = objects.add_object_by_template_id(locobot_id, sim.agents[0].scene_node)
    robot.motion_type = MotionType.DYNAMIC
    control = robot.velocity_control
    control.controlling_lin_vel = control.controlling_ang_vel = True
    control.lin_vel_is_local = control.ang_vel_is_local = True
    return sim, robot, cube


def _add_box(templates, objects, cube_handle: str, handle: str, half_size, mass: float):
    """Register a scaled copy of the unit cube template and add one object of it."""
    template = templates.get_template_by_handle(cube_handle).copy()
    template.scale, template.mass = list(half_size), float(mass)
    return objects.add_object_by_template_id(templates.register_template(template, handle))


# ------------------------------------------------------------------------------------------
# A scripted baseline: get behind the cube, then push it towards the target
# ------------------------------------------------------------------------------------------
BEHIND_DISTANCE = 0.35  # m behind the cube's center: robot radius 0.18 + cube half size 0.1 + gap


def scripted_push_action(observation: np.ndarray) -> np.ndarray:
    """A hand-written controller for PushObject (a baseline for learned policies).

    With ``u`` the unit vector from the cube to the target, the robot first drives to the
    point ``cube - 0.35 u`` behind the cube, then towards the target, pushing the cube ahead.
    Steering is proportional to the signed angle to the current goal (positive = left,
    ``atan2(f_z g_x - f_x g_z, f . g)`` for forward ``f`` and goal offset ``g`` in the
    x-z plane); the forward command fades as ``cos^3`` of that angle so it turns first.
    """
    robot, cube, target = observation[0:2], observation[4:6], observation[6:8]
    forward = np.array([-observation[3], -observation[2]])  # (x, z) of local -Z at yaw
    push = (target - cube) / max(float(np.linalg.norm(target - cube)), 1e-9)
    behind = cube - BEHIND_DISTANCE * push
    offset = robot - cube
    lateral = abs(push[0] * offset[1] - push[1] * offset[0])  # distance off the push line
    in_position = np.linalg.norm(behind - robot) < 0.08 or (
        offset @ push < -0.25 and lateral < 0.05
    )
    goal = (target if in_position else behind) - robot
    angle = math.atan2(forward[1] * goal[0] - forward[0] * goal[1], forward @ goal)
    turn = np.clip(2.0 * angle, -1.0, 1.0)
    speed = min(2.0 * float(np.linalg.norm(goal)), 1.0) * max(0.0, math.cos(angle)) ** 3
    return np.array([speed, turn], dtype=np.float32)
