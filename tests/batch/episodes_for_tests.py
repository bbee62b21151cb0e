"""Tiny episode functions shared by the batch tests (each runs in milliseconds).

They live in a file pytest loads by path, so the batch runner ships them to worker
processes by value (cloudpickle), the same path a notebook's functions take.
"""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import numpy as np

import engine as habitat_sim


def toss_cube(params: dict, seed: int, episode_dir: str | None = None) -> dict:
    """A cube tossed in an empty world with a seeded random velocity, 0.1 s of physics.

    Free flight under gravity without damping: symplectic Euler gives after n steps of h
    ``p_n = n h v0 + g h^2 n (n + 1) / 2``; it depends only on ``seed`` and ``params``.
    """
    if params.get("fail"):
        raise ValueError(f"episode asked to fail: {params}")
    if params.get("kill"):
        os.kill(os.getpid(), signal.SIGKILL)  # the worker process dies mid-episode
    marker = params.get("kill_once")
    if marker and not Path(marker).exists():
        Path(marker).write_text(str(os.getpid()))
        os.kill(os.getpid(), signal.SIGKILL)  # dies the first time only
    time.sleep(params.get("sleep", 0.0))
    sim = habitat_sim.Simulator(habitat_sim.Configuration())
    handle = sim.get_object_template_manager().get_template_handles("cubeSolid")[0]
    cube = sim.get_rigid_object_manager().add_object_by_template_handle(handle)
    rng = np.random.default_rng(seed)
    velocity = rng.normal(size=3) * params.get("speed", 1.0)
    cube.linear_damping = 0.0
    cube.linear_velocity = velocity
    sim.step_physics(0.1)
    if episode_dir is not None:
        np.save(Path(episode_dir) / "velocity.npy", velocity)
    return {
        "position": [float(c) for c in cube.translation],
        "velocity": velocity.tolist(),
        "world_time": sim.get_world_time(),
        "time_step": sim.get_physics_time_step(),
        "pid": os.getpid(),
    }


def seed_echo(params: dict, seed: int) -> dict:
    """No simulation: the parameters and the seed back (batches of very short episodes)."""
    return {"i": params["i"], "seed": seed}


def ray_node_id(params: dict, seed: int) -> dict:
    """Which Ray node ran the episode (it sleeps so that both nodes get work)."""
    import ray

    time.sleep(params["sleep"])
    return {"node": ray.get_runtime_context().get_node_id(), "seed": seed}
