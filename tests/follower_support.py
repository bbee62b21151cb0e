"""The agent of Habitat's noisy greedy-follower episodes, shared by the follower tests.

Habitat-sim's ``tests/test_greedy_follower.py`` plans with perfect actions (renamed ``_*``)
and moves with PyRobot's noisy LoCoBot actions under the plain names, ``try_step`` filtering
every move; turns are 30 degrees and steps 0.25 m.
"""

from __future__ import annotations

import engine as habitat_sim

TURN_DEGREES = 30.0


def noisy_agent(pathfinder):
    """Habitat's noisy agent: perfect actions renamed ``_*`` for the follower's planning,
    PyRobot noisy actions under the plain names, ``try_step`` as the move filter."""
    agent = habitat_sim.Agent(habitat_sim.SceneGraph().get_root_node().create_child())
    agent.controls.move_filter_fn = pathfinder.try_step
    space = agent.agent_config.action_space
    space["turn_left"].actuation.amount = space["turn_right"].actuation.amount = TURN_DEGREES
    noisy = habitat_sim.PyRobotNoisyActuationSpec
    agent.agent_config.action_space = {"_" + key: spec for key, spec in space.items()}
    agent.agent_config.action_space.update(
        move_forward=habitat_sim.ActionSpec("pyrobot_noisy_move_forward", noisy(amount=0.25)),
        turn_left=habitat_sim.ActionSpec("pyrobot_noisy_turn_left", noisy(amount=TURN_DEGREES)),
        turn_right=habitat_sim.ActionSpec("pyrobot_noisy_turn_right", noisy(amount=TURN_DEGREES)),
    )
    return agent
