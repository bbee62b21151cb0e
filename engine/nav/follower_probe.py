"""The greedy follower's candidate steps scored in one batch: the fast twin of its ``_reward``.

The follower (``engine.nav``) scores every primitive ``[turn] * n + [forward]`` by the step
that ends it::

    reward = (d_geo(before) - d_geo(after)) / step - 0.0125 n
             - 0.25 [collided] - 0.05 [obstacle closer than 0.2 m after the step]

Its reference ``_reward`` asks for each candidate, one at a time, what Habitat asks: the
agent's move filter (``Simulator.step_filter``: ``PathFinder.try_step``), the goal's
geodesic field at the new position and ``PathFinder.is_near_obstacle``, each snapping the
points it is given. :class:`BatchProbe` gives the same numbers for all candidates of one
pose at once when the move filter is the simulator's navmesh step filter (the default):

* the pose's position is snapped once for all candidate steps
  (``navmesh.step_filter.step_from``) and the filters' Magnum-vector wrappers are skipped;
* each new position is snapped once and that node serves both the field
  (``GeodesicField.distance_at``) and the wall test;
* the wall tests of all candidates are one vectorized pass (``navmesh.proximity.walls_within``).

The arithmetic of a step (target, filter, collision) is the one of
:class:`engine.nav.follower_poses.ArrayPose`, so rewards agree bit for bit;
``tests/engine/test_greedy_follower.py`` checks both paths choose the same actions.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from engine.nav.follower_poses import ArrayPose, filtered_move
from engine.nav.pathfinder import PathFinder as EnginePathFinder
from navmesh import PathFinder
from navmesh.geodesic_field import GeodesicField
from navmesh.proximity import walls_within
from navmesh.step_filter import step_from

CLOSE_TO_OBSTACLE_M = 0.2  # a step ending closer than this to a wall costs 0.05
COLLISION_COST = 0.25  # a blocked step costs this (the floor of acceptable rewards)
TURN_COST = 0.0125  # per turn of the primitive: prefer short primitives
NEAR_WALL_COST = 0.05


def reward_of(gained: float, turns: int, collided: bool, near_wall: bool) -> float:
    """The follower's reward of one primitive (see the module), one formula for both paths."""
    return (
        gained
        - TURN_COST * turns
        - (COLLISION_COST if collided else 0.0)
        - (NEAR_WALL_COST if near_wall else 0.0)
    )


def navmesh_sliding(move_filter: Any, pathfinder: PathFinder) -> bool | None:
    """``allow_sliding`` when ``move_filter`` is the navmesh step filter on this loaded
    ``pathfinder``, else None (another filter: the follower scores through it).

    Two filters qualify: a simulator's ``step_filter`` with this pathfinder (``allow_sliding``
    is read now, as the simulator does) and the pathfinder's own ``try_step`` /
    ``try_step_no_sliding`` (Habitat's follower test sets those). Overridden methods do not:
    the function behind the bound method must be rigidsim's own.
    """
    owner = getattr(move_filter, "__self__", None)
    function = getattr(move_filter, "__func__", None)
    if owner is None or function is None or not pathfinder.is_loaded:
        return None
    if owner is pathfinder:
        return _PATHFINDER_STEPS.get(function)
    # a Simulator, named rather than imported: engine.simulator.simulator imports the follower
    own_step_filter = (function.__module__, function.__qualname__) == (
        "engine.simulator.simulator",
        "Simulator.step_filter",
    )
    if own_step_filter and getattr(owner, "pathfinder", None) is pathfinder:
        return bool(owner.config.sim_cfg.allow_sliding)
    return None


#: the pathfinders' step methods and whether they slide (equal results: the engine's
#: subclass only wraps the point in an mn.Vector3)
_PATHFINDER_STEPS = {
    PathFinder.try_step: True,
    PathFinder.try_step_no_sliding: False,
    EnginePathFinder.try_step: True,
    EnginePathFinder.try_step_no_sliding: False,
}


class BatchProbe:
    """Rewards of ``[turn] * n + [forward]`` candidates from one pose, all at once."""

    def __init__(self, pathfinder: PathFinder, allow_sliding: bool, forward_amount: float):
        self.grid = pathfinder.nav_grid
        self.allow_sliding = allow_sliding
        self.forward_amount = float(forward_amount)
        # (position, node, snapped) of the last start: the batches of one pose share it
        self._start: tuple[np.ndarray, int, np.ndarray | None] | None = None

    def rewards(
        self,
        poses: Sequence[ArrayPose],
        turns: Sequence[int],
        field: GeodesicField,
        distance: float,
        best_so_far: float,
    ) -> list[float]:
        """Rewards of the candidates ``poses[k]`` (already turned ``turns[k]`` times, all where
        the agent stands; ``distance`` is the geodesic distance from there), in the order the
        follower compares them with the best reward found before them (``best_so_far`` at the
        first).

        The wall test (the 0.05 penalty) runs only for candidates that could still beat the
        best before them: a candidate whose reward without the penalty is no more than
        ``max(best_so_far, reward of an earlier one - 0.05)`` cannot, and gets that upper
        bound instead of its reward; the best candidate and every comparison it wins are
        exact. Likewise the geodesic distance after a step is searched only below the value
        that would let the candidate beat that bound (``GeodesicField.distance_at``'s
        ``at_most``); above it a lower bound of the distance gives an upper bound of the
        reward, no more than the bound.
        """
        grid = self.grid
        start = poses[0].position
        if self._start is None or not np.array_equal(self._start[0], start):
            self._start = (start, *grid.nearest_node(start))
        _, start_node, start_pt = self._start
        upper, nodes, points = [], [], []
        bound = best_so_far  # the follower's best reward is at least this before candidate k
        for pose, n in zip(poses, turns, strict=True):
            end = pose.forward_target(self.forward_amount)
            filtered = step_from(grid, start, start_node, start_pt, end, self.allow_sliding)
            after, blocked = filtered_move(start, end, filtered)
            node, snapped = grid.nearest_node(after)
            # the candidate can win only if its distance is below this (reward > bound)
            costs = reward_of(0.0, n, blocked, False)
            at_most = distance - self.forward_amount * (bound - costs)
            gain = (distance - field.distance_at(node, snapped, at_most)) / self.forward_amount
            upper.append(reward_of(gain, n, blocked, False))
            bound = max(bound, upper[-1] - NEAR_WALL_COST)  # the reward of k is at least this
            nodes.append(node)
            points.append(after if snapped is None else snapped)
        tested = self._worth_testing(upper, nodes, best_so_far)
        rewards = list(upper)
        if not tested:
            return rewards
        near = walls_within(
            grid, np.asarray(nodes)[tested], np.asarray(points)[tested], CLOSE_TO_OBSTACLE_M
        )
        for k, wall in zip(tested, near.tolist(), strict=True):
            rewards[k] = upper[k] - (NEAR_WALL_COST if wall else 0.0)  # reward_of's last term
        return rewards

    @staticmethod
    def _worth_testing(upper: list[float], nodes: list[int], best_so_far: float) -> list[int]:
        """Indices of the on-mesh candidates that may beat every candidate before them (off
        the mesh no wall is near, as ``is_near_obstacle`` says)."""
        tested, bound = [], best_so_far
        for k, (high, node) in enumerate(zip(upper, nodes, strict=True)):
            if high > bound and node >= 0:
                tested.append(k)
            bound = max(bound, high - NEAR_WALL_COST)  # the reward of k is at least this
        return tested
