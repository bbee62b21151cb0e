"""Gymnasium environments on rigidsim (needs ``gymnasium``: ``pip install rigidsim[gym]``).

Importing this package registers:

- ``rigidsim/PointNav-v0`` (:class:`~engine.envs.point_nav.PointNavEnv`): Habitat's
  point-goal navigation in the demo apartment, discrete actions, rgb + depth + polar goal,
  500 actions at most;
- ``rigidsim/PushObject-v0`` (:class:`~engine.envs.push_object.PushObjectEnv`): the
  locobot pushes a cube onto a target patch, continuous velocity commands, dense reward,
  200 steps at most (:func:`~engine.envs.push_object.scripted_push_action` solves it).

    import gymnasium as gym
    import engine.envs  # noqa: F401  (registers the ids)

    env = gym.make("rigidsim/PointNav-v0")
    envs = gym.make_vec("rigidsim/PushObject-v0", num_envs=2, vectorization_mode="async")

Both are deterministic under ``reset(seed=...)``. ``gym.make("engine.envs:rigidsim/...")``
imports this package by itself (handy in subprocesses).

Read :mod:`~engine.envs.point_nav`, then :mod:`~engine.envs.push_object` and
:mod:`~engine.envs.greedy_follower`. May import: the whole ``engine`` (they are programs
on top of it), ``navmesh`` and ``gymnasium``; nothing of the engine imports them.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError as error:  # pragma: no cover - depends on the installation
    raise ImportError("engine.envs needs gymnasium: pip install 'rigidsim[gym]'") from error

from engine.envs.point_nav import ACTIONS, PointNavEnv
from engine.envs.push_object import PushObjectEnv, scripted_push_action

POINT_NAV_ID = "rigidsim/PointNav-v0"
PUSH_OBJECT_ID = "rigidsim/PushObject-v0"

__all__ = [
    "ACTIONS",
    "POINT_NAV_ID",
    "PUSH_OBJECT_ID",
    "PointNavEnv",
    "PushObjectEnv",
    "scripted_push_action",
]


def _register() -> None:
    """Register the ids once (re-importing this package is harmless)."""
    registered = gymnasium.envs.registry
    if POINT_NAV_ID not in registered:
        gymnasium.register(
            POINT_NAV_ID, entry_point="engine.envs.point_nav:PointNavEnv", max_episode_steps=500
        )
    if PUSH_OBJECT_ID not in registered:
        gymnasium.register(
            PUSH_OBJECT_ID,
            entry_point="engine.envs.push_object:PushObjectEnv",
            max_episode_steps=200,
        )


_register()
