"""Habitat's ``habitat_sim.nav``: the navmesh classes and the greedy geodesic follower.

``GreedyGeodesicFollower(pathfinder, agent, goal_radius=None, *, stop_key=None, ...)`` fits
the agent's ``move_forward`` / ``turn_left`` / ``turn_right`` actions to the geodesic shortest
path, as Habitat's C++ ``GreedyGeodesicFollowerImpl`` does (after Gupta et al.'s
map-plan-baseline):

* stop (return ``stop_key``, None by default) when the geodesic distance to the goal is below
  ``goal_radius`` (default 0.75 x the forward step);
* else try every primitive ``[turn] * n + [forward]`` for ``n`` turns left or right while
  ``n * turn < pi`` (with the agent's own controls and move filter, on scratch nodes) and
  score it::

      reward = (d_geo(before) - d_geo(after)) / step - 0.0125 n
               - 0.25 [collided] - 0.05 [obstacle closer than 0.2 m after the step]

  keep the best (ties: the fewer turns, left first); stop searching once a reward exceeds
  0.99 (a straight step that gains a full step);
* thrashing fix: after ``thrashing_threshold`` alternating left/right turns, commit to the
  whole best primitive instead of its first action.

Speed (issue 21: a 50-action path in under 50 ms): the geodesic distance comes from one
search from the goal per goal (``navmesh.geodesic_field``: the exact distance ``find_path``
reports, from a Dijkstra over the navmesh's visibility graph), not a path search per candidate,
and, for the default controls on the simulator's navmesh filter, the candidates of a pose are
scored in batches (``engine.nav.follower_probe.BatchProbe``: one start snap, one snap per new
position, one vectorized wall test). ``use_reference_poses = True`` selects the reference:
the agent's controls on scratch nodes, one candidate at a time through the PathFinder API, as
Habitat does; both choose the same actions (``tests/engine/test_greedy_follower.py``).
Habitat's ``demo_runner`` asks ``find_path(goal)`` every frame from the agent's new pose,
which often lies on the path found the frame before: the best primitive of a pose is a pure
function of the pose for one goal, navmesh and step rule, so it is remembered per exact pose
until the goal or the navmesh changes (``cache_primitives = False`` searches every pose
again; same actions, same test file).

``next_action_along(goal)`` returns one action key; ``find_path(goal)`` simulates the
primitives on a scratch node and returns every key, ending with ``stop_key``. No path (the
goal on another island, or more than 5000 actions) raises
:class:`engine.errors.GreedyFollowerError`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from enum import Enum
from typing import Any

import numpy as np

from engine import mn
from engine.agent import Agent
from engine.agent.controls import ActuationSpec
from engine.errors import GreedyFollowerError
from engine.nav.follower_poses import (
    ArrayPose,
    NodePose,
    PoseT,
    ScratchPose,
    default_controls_used,
)
from engine.nav.follower_probe import (
    CLOSE_TO_OBSTACLE_M,
    COLLISION_COST,
    BatchProbe,
    navmesh_sliding,
    reward_of,
)
from navmesh import HitRecord, MultiGoalShortestPath, NavMeshSettings, PathFinder, ShortestPath
from navmesh.geodesic_field import GeodesicField

__all__ = [
    "GreedyFollowerCodes",
    "GreedyGeodesicFollower",
    "HitRecord",
    "MultiGoalShortestPath",
    "NavMeshSettings",
    "PathFinder",
    "ShortestPath",
]

GOOD_ENOUGH_REWARD = 0.99  # stop searching: the step gained 99 % of a full step
MAX_ACTIONS = 5000  # find_path gives up after this many actions
MAX_CACHED_POSES = 100_000  # the primitive cache starts again beyond this many poses


class GreedyFollowerCodes(Enum):
    """The follower's internal action codes (Habitat's ``GreedyFollowerCodes``)."""

    ERROR = -2
    STOP = -1
    FORWARD = 0
    LEFT = 1
    RIGHT = 2


LEFT, RIGHT = GreedyFollowerCodes.LEFT, GreedyFollowerCodes.RIGHT
CONTROL_NAMES = {
    GreedyFollowerCodes.FORWARD: "move_forward",
    LEFT: "turn_left",
    RIGHT: "turn_right",
}


class GreedyGeodesicFollower:
    """Greedily fits the agent's actions to the geodesic shortest path (see the module)."""

    def __init__(
        self,
        pathfinder: PathFinder,
        agent: Agent,
        goal_radius: float | None = None,
        *,
        stop_key: Any = None,
        forward_key: Any = None,
        left_key: Any = None,
        right_key: Any = None,
        fix_thrashing: bool = True,
        thrashing_threshold: int = 16,
    ) -> None:
        self.pathfinder = pathfinder
        self.agent = agent
        self.last_goal: np.ndarray | None = None
        codes = GreedyFollowerCodes
        self.action_mapping: dict[GreedyFollowerCodes, Any] = {codes.STOP: stop_key}
        key, self.forward_spec = self._find_action("move_forward")
        self.action_mapping[codes.FORWARD] = key if forward_key is None else forward_key
        key, self.left_spec = self._find_action("turn_left")
        self.action_mapping[codes.LEFT] = key if left_key is None else left_key
        key, self.right_spec = self._find_action("turn_right")
        self.action_mapping[codes.RIGHT] = key if right_key is None else right_key
        self.goal_radius = (
            0.75 * float(self.forward_spec.amount) if goal_radius is None else float(goal_radius)
        )
        self.fix_thrashing = bool(fix_thrashing)
        self.thrashing_threshold = int(thrashing_threshold)
        self._turn_radians = math.radians(float(self.left_spec.amount))
        if self._turn_radians <= 0.0:
            raise ValueError(f"turn_left must turn by > 0 degrees, got {self.left_spec.amount}")
        self._actions: list[GreedyFollowerCodes] = []
        self._thrashing_actions: list[GreedyFollowerCodes] = []
        # one geodesic distance field per goal (a search from the goal), reused by every query
        self._field: GeodesicField | None = None
        self._field_goal: np.ndarray | None = None
        self._field_grid: object = None  # the navmesh the field was computed on
        #: the best primitive of each array pose met since the field was computed (a pure
        #: function of the pose for one goal and navmesh): demo programs ask find_path every
        #: frame from the agent's new pose, which often lies on the path found before
        self._primitives: dict[tuple[Any, ...], list[GreedyFollowerCodes]] = {}
        self._specs = {
            "move_forward": self.forward_spec,
            "turn_left": self.left_spec,
            "turn_right": self.right_spec,
        }
        #: try primitives through the agent's controls on scene nodes, scored one at a time
        #: (Habitat's way), instead of the array twin of the default controls scored in
        #: batches (same actions; see follower_poses and follower_probe)
        self.use_reference_poses = False
        #: remember the best primitive per array pose for the current goal; False: search
        #: every pose again (the reference; same actions, ``tests/engine/test_greedy_follower``)
        self.cache_primitives = True

    def _find_action(self, name: str) -> tuple[Any, ActuationSpec]:
        """The (key, actuation) of the one action of the agent's space that runs ``name``."""
        found = [
            (k, spec.actuation)
            for k, spec in self.agent.agent_config.action_space.items()
            if spec.name == name
        ]
        if len(found) != 1:
            raise ValueError(
                f"Could not find an action spec corresponding to {name!r} in the "
                f"agent's action space ({len(found)} found)"
            )
        key, actuation = found[0]
        if actuation is None:
            raise ValueError(f"the action spec of {name!r} has no actuation (no amount)")
        return key, actuation

    # -- primitives on scratch poses ----------------------------------------------------------
    def _scratch_pose(self, position: Any, rotation: Any) -> ScratchPose:
        """A pose to try actions on: the fast array twin for the default controls, else a
        scratch node moved by the agent's controls (``engine.nav.follower_poses``)."""
        if not self.use_reference_poses and default_controls_used(self._specs):
            xyzw = mn.to_quaternion(rotation).xyzw
            filter_fn = self.agent.controls.move_filter_fn
            return ArrayPose(filter_fn, self._specs, np.asarray(position, np.float64), xyzw)
        return NodePose(self.agent.controls, self._specs, position, rotation)

    def _geodesic(self, start: np.ndarray, goal: np.ndarray) -> float:
        """Geodesic distance from ``start`` to ``goal``, from the goal's distance field."""
        return self._field_for(goal).distance(start)

    def _field_for(self, goal: np.ndarray) -> GeodesicField:
        """The goal's geodesic field, computed again when the goal or the navmesh changed
        (the primitive cache, valid for one field, is then emptied)."""
        grid = self.pathfinder.nav_grid if self.pathfinder.is_loaded else None
        if (
            self._field is None
            or self._field_goal is None
            or self._field_grid is not grid
            or not np.array_equal(self._field_goal, goal)
        ):
            self._field, self._field_goal = self.pathfinder.geodesic_field(goal), goal.copy()
            self._field_grid = grid
            self._primitives.clear()
        return self._field

    def _reward(self, pose: ScratchPose, goal: np.ndarray, distance: float, turns: int) -> float:
        """Score the primitive ``turns`` turns (already applied to ``pose``) + one step."""
        probe = pose.copy()
        collided = probe.act("move_forward")
        after = probe.position
        gained = (distance - self._geodesic(after, goal)) / float(self.forward_spec.amount)
        # Habitat: distance_to_closest_obstacle(after, 1.1 * 0.2) < 0.2, the same answer
        near_wall = self.pathfinder.is_near_obstacle(after, CLOSE_TO_OBSTACLE_M)
        return reward_of(gained, turns, collided, near_wall)

    def _cached_best_primitive(
        self, pose: ScratchPose, goal: np.ndarray
    ) -> list[GreedyFollowerCodes]:
        """:meth:`_best_primitive`, remembered per array pose (its exact position and
        rotation bits, the step amounts, the goal radius and the sliding rule) while the goal
        and the navmesh stay the same (``cache_primitives``). Only for the navmesh step
        filter: another move filter may depend on more than the navmesh."""
        if not self.cache_primitives or not isinstance(pose, ArrayPose):
            return self._best_primitive(pose, goal)
        sliding = navmesh_sliding(pose.move_filter, self.pathfinder)
        if sliding is None:
            return self._best_primitive(pose, goal)
        self._field_for(goal)  # empties the cache when the goal or the navmesh changed
        amounts = tuple(float(spec.amount) for spec in self._specs.values())
        key = (pose.position.tobytes(), pose.xyzw.tobytes(), sliding, amounts, self.goal_radius)
        primitive = self._primitives.get(key)
        if primitive is None:
            if len(self._primitives) >= MAX_CACHED_POSES:
                self._primitives.clear()
            primitive = self._primitives[key] = self._best_primitive(pose, goal)
        return list(primitive)

    def _best_primitive(self, pose: ScratchPose, goal: np.ndarray) -> list[GreedyFollowerCodes]:
        """The best ``[turn] * n + [FORWARD]`` from this pose, [STOP], or [ERROR]."""
        distance = self._geodesic(pose.position, goal)
        if math.isinf(distance):
            return [GreedyFollowerCodes.ERROR]
        if distance < self.goal_radius:
            return [GreedyFollowerCodes.STOP]
        if isinstance(pose, ArrayPose) and (probe := self._batch_probe(pose)) is not None:
            return self._best_primitive_batched(probe, pose, distance)
        best_reward, best = -COLLISION_COST, []
        left, right = pose.copy(), pose.copy()
        turns, angle = 0, 0.0
        while angle < math.pi:
            # with no turn, left and right are the same primitive: score it once
            sides = ((left, LEFT),) if turns == 0 else ((left, LEFT), (right, RIGHT))
            for side, code in sides:
                reward = self._reward(side, goal, distance, turns)
                if reward > best_reward:
                    best_reward, best = reward, [code] * turns + [GreedyFollowerCodes.FORWARD]
            if best_reward > GOOD_ENOUGH_REWARD:
                break
            left.act("turn_left")
            right.act("turn_right")
            turns, angle = turns + 1, angle + self._turn_radians
        return best

    def _batch_probe(self, pose: ArrayPose) -> BatchProbe | None:
        """The fast scorer when it gives the reference's rewards: array poses moved by the
        simulator's navmesh step filter (``engine.nav.follower_probe``)."""
        sliding = navmesh_sliding(pose.move_filter, self.pathfinder)
        if sliding is None:
            return None
        return BatchProbe(self.pathfinder, sliding, float(self.forward_spec.amount))

    def _candidates(self, pose: PoseT) -> Iterator[list[tuple[PoseT, Any, int]]]:
        """Rounds of ``(turned pose, turn code, turns)``: round n holds the left and right
        primitives of n turns (round 0 the straight step), while ``n * turn < pi``; each
        round is turned only when asked for."""
        yield [(pose.copy(), LEFT, 0)]
        left, right = pose.copy(), pose.copy()
        turns, angle = 1, self._turn_radians
        while angle < math.pi:
            left.act("turn_left")
            right.act("turn_right")
            yield [(left.copy(), LEFT, turns), (right.copy(), RIGHT, turns)]
            turns, angle = turns + 1, angle + self._turn_radians

    def _best_primitive_batched(
        self, probe: BatchProbe, pose: ArrayPose, distance: float
    ) -> list[GreedyFollowerCodes]:
        """The reference loop's choice, its rewards computed in batches of rounds: the
        straight step, then the one-turn primitives, then all the others (each batch only
        when the rounds before it found no good-enough primitive, as the loop stops)."""
        assert self._field is not None  # set by the _geodesic call of _best_primitive
        rounds = self._candidates(pose)
        best_reward, best = -COLLISION_COST, []
        # batches of 1, 1 and all the remaining rounds, each turned only when reached
        for batch in (list(itertools.islice(rounds, size)) for size in (1, 1, None)):
            flat = [candidate for round_ in batch for candidate in round_]
            if not flat:
                break
            poses, turns = [c[0] for c in flat], [c[2] for c in flat]
            rewards = iter(probe.rewards(poses, turns, self._field, distance, best_reward))
            for round_ in batch:  # the reference loop over these rounds, same order and stop
                for _, code, n in round_:
                    reward = next(rewards)
                    if reward > best_reward:
                        best_reward, best = reward, [code] * n + [GreedyFollowerCodes.FORWARD]
                if best_reward > GOOD_ENOUGH_REWARD:
                    return best
        return best

    def _is_thrashing(self) -> bool:
        """The last ``thrashing_threshold`` actions alternate left and right."""
        recent = self._actions[-self.thrashing_threshold :]
        if len(self._actions) < self.thrashing_threshold:
            return False
        turns = {GreedyFollowerCodes.LEFT, GreedyFollowerCodes.RIGHT}
        if recent[-1] not in turns:
            return False
        return all(
            a in turns and b in turns and a != b for a, b in zip(recent, recent[1:], strict=False)
        )

    # -- Habitat's API -------------------------------------------------------------------------
    def next_action_along(self, goal_pos: Any) -> Any:
        """The action key to take now to follow the geodesic path to ``goal_pos``."""
        goal = np.asarray(goal_pos, dtype=np.float64)
        if self.last_goal is None or not np.allclose(goal, self.last_goal):
            self.reset()
            self.last_goal = goal
        state = self.agent.state
        if self.fix_thrashing and self._thrashing_actions:
            code = self._thrashing_actions.pop()
        else:
            pose = self._scratch_pose(state.position, state.rotation)
            primitive = self._cached_best_primitive(pose, goal)
            if not primitive:
                code = GreedyFollowerCodes.ERROR
            elif self.fix_thrashing and self._is_thrashing():
                self._thrashing_actions = primitive[::-1]
                code = self._thrashing_actions.pop()
            else:
                code = primitive[0]
        self._actions.append(code)
        if code is GreedyFollowerCodes.ERROR:
            raise GreedyFollowerError(f"no path from {state.position.tolist()} to {goal.tolist()}")
        return self.action_mapping[code]

    def find_path(self, goal_pos: Any) -> list[Any]:
        """Every action key from the agent's pose to ``goal_pos``, ending with ``stop_key``."""
        self.reset()
        goal = np.asarray(goal_pos, dtype=np.float64)
        state = self.agent.state
        pose = self._scratch_pose(state.position, state.rotation)
        actions: list[GreedyFollowerCodes] = []
        while len(actions) < MAX_ACTIONS:
            primitive = self._cached_best_primitive(pose, goal)
            if not primitive or primitive[-1] is GreedyFollowerCodes.ERROR:
                raise GreedyFollowerError(
                    f"no path from {state.position.tolist()} to {goal.tolist()}"
                )
            for code in primitive:
                if code is not GreedyFollowerCodes.STOP:
                    pose.act(CONTROL_NAMES[code])
                actions.append(code)
            if actions[-1] is GreedyFollowerCodes.STOP:
                return [self.action_mapping[code] for code in actions]
        raise GreedyFollowerError(f"no path to {goal.tolist()} within {MAX_ACTIONS} actions")

    def reset(self) -> None:
        """Forget the action history (thrashing detection) and the last goal."""
        self._actions.clear()
        self._thrashing_actions.clear()
        self.last_goal = None
