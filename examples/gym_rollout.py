"""A Gymnasium rollout: two PointNav environments stepped together in worker processes.

``import engine.envs`` registers ``rigidsim/PointNav-v0`` and ``rigidsim/PushObject-v0``;
``gymnasium.make_vec(..., vectorization_mode="async")`` runs each copy in its own process
and resets an episode that ends by itself. Random actions here: put your policy in their
place. Needs the ``gym`` extra (``pip install 'rigidsim[gym]'``).

    python examples/gym_rollout.py                         # PointNav, 2 envs, 50 steps
    python examples/gym_rollout.py --env rigidsim/PushObject-v0 --steps 100
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import engine.envs  # noqa: F401 - registers the rigidsim environments


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="rigidsim/PointNav-v0")
    parser.add_argument("--num-envs", type=int, default=2)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--fast", action="store_true", help="5 steps (the test suite's mode)")
    args = parser.parse_args()
    steps = 5 if args.fast else args.steps

    envs = gym.make_vec(args.env, num_envs=args.num_envs, vectorization_mode="async")
    try:
        envs.action_space.seed(0)
        observations, _ = envs.reset(seed=list(range(args.num_envs)))
        returns = np.zeros(args.num_envs)
        episode_ends = 0
        for _ in range(steps):
            actions = envs.action_space.sample()  # your policy here
            observations, rewards, terminated, truncated, _ = envs.step(actions)
            returns += rewards
            episode_ends += int(np.sum(terminated | truncated))
        print(
            f"{args.env}: {steps} steps x {args.num_envs} envs, "
            f"return per env {np.round(returns, 3)}, {episode_ends} episode ends"
        )
        if isinstance(observations, dict):
            shapes = {key: value.shape for key, value in observations.items()}
            print(f"observations: {shapes}")
    finally:
        envs.close()


if __name__ == "__main__":
    main()
