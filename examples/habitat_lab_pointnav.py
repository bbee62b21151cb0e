"""PointNav with habitat-lab on rigidsim: generate episodes, evaluate an oracle agent.

habitat-lab (Meta's task library) runs unchanged on rigidsim once the import alias maps
``habitat_sim`` and ``magnum`` to rigidsim (``docs/habitat_lab.md``). From a fresh clone::

    pip install habitat-lab==0.3.320260507 . ./scripts/habitat_alias
    python examples/habitat_lab_pointnav.py --episodes 3

What it does, all with habitat-lab's own code:

1. builds rigidsim's demo apartment (``engine.demo.demo_data_path()``);
2. loads habitat-lab's PointNav test config (``pointnav_habitat_test.yaml``: RGB and depth
   256x256, ``pointgoal_with_gps_compass``, the metrics ``distance_to_goal``, ``success``,
   ``spl``) pointed at the apartment, and generates episodes with habitat-lab's
   ``generate_pointnav_episode``, saved as a ``PointNav-v1`` dataset;
3. runs ``habitat.Env`` over them with an oracle agent, habitat-lab's
   ``ShortestPathFollower``, and prints each episode's metrics.

Without the alias distribution it installs the alias itself
(``engine.habitat_compat.alias.install()``), so it also runs from a checkout with
``PYTHONPATH`` set. Run time on a 2-core laptop: about 25 ms a step.
"""

from __future__ import annotations

import argparse
import gzip
import logging
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from engine.demo import demo_data_path
from engine.habitat_compat import alias

alias.install()  # a no-op when the rigidsim-habitat-alias distribution installed it already

import habitat  # noqa: E402 - needs the alias
from habitat.config import read_write  # noqa: E402
from habitat.datasets.pointnav.pointnav_generator import generate_pointnav_episode  # noqa: E402
from habitat.tasks.nav.shortest_path_follower import ShortestPathFollower  # noqa: E402

POINTNAV_CONFIG = "benchmark/nav/pointnav/pointnav_habitat_test.yaml"
SCENE = "demo/apartment.glb"  # relative to the demo data's scene_datasets folder
SPLIT = "train"


def pointnav_config(episodes_dir: Path, config_path: str = POINTNAV_CONFIG) -> Any:
    """habitat-lab's config ``config_path`` reading episodes from ``episodes_dir`` and scenes
    from the demo data (built on first use)."""
    scenes_dir = demo_data_path() / "scene_datasets"
    return habitat.get_config(
        config_path,
        overrides=[
            f"habitat.dataset.data_path='{episodes_dir}/{{split}}/{{split}}.json.gz'",
            f"habitat.dataset.scenes_dir='{scenes_dir}'",
            f"habitat.dataset.split={SPLIT}",
        ],
    )


def generate_episodes(config: Any, count: int, seed: int = 0) -> Path:
    """Generate ``count`` PointNav episodes on the demo apartment with habitat-lab's generator
    and write them where ``config`` reads its dataset; returns that file."""
    scene_path = Path(config.habitat.dataset.scenes_dir) / SCENE
    sim_config = config.habitat.simulator.copy()
    with read_write(sim_config):
        sim_config.scene = str(scene_path)
    np.random.seed(seed)  # the generator draws start headings from numpy's global generator
    with habitat.sims.make_sim(sim_config.type, config=sim_config) as sim:
        sim.seed(seed)
        episodes = list(generate_pointnav_episode(sim, num_episodes=count))
    for episode in episodes:
        episode.scene_id = SCENE  # relative: the dataset joins it to scenes_dir
        episode.episode_id = str(episode.episode_id)
    dataset = habitat.make_dataset("PointNav-v1")
    dataset.episodes = episodes
    out = Path(config.habitat.dataset.data_path.format(split=SPLIT))
    out.parent.mkdir(parents=True, exist_ok=True)
    with gzip.open(out, "wt") as file:
        file.write(dataset.to_json())
    return out


def evaluate_oracle(config: Any) -> list[dict[str, float]]:
    """Run every episode of ``config``'s dataset with habitat-lab's ``ShortestPathFollower``
    (the oracle: the greedy geodesic follower); returns each episode's metrics and steps."""
    results = []
    with habitat.Env(config=config) as env:
        goal_radius = config.habitat.task.measurements.success.success_distance
        follower = ShortestPathFollower(env.sim, goal_radius, return_one_hot=False)
        for _ in range(len(env.episodes)):
            env.reset()
            goal = env.current_episode.goals[0].position
            start = time.perf_counter()
            steps = 0
            while not env.episode_over:
                action = follower.get_next_action(goal)
                env.step(action if action is not None else 0)  # None: the follower gave up
                steps += 1
            metrics = env.get_metrics()
            results.append(
                {
                    "episode": float(env.current_episode.episode_id),
                    "steps": float(steps),
                    "ms_per_step": 1000.0 * (time.perf_counter() - start) / max(steps, 1),
                    "distance_to_goal": float(metrics["distance_to_goal"]),
                    "success": float(metrics["success"]),
                    "spl": float(metrics["spl"]),
                }
            )
    return results


def run_pointnav(work: Path, episodes: int = 3, seed: int = 0) -> list[dict[str, float]]:
    """Steps 1 to 3 of the module docstring, the dataset written under ``work``."""
    config = pointnav_config(work / "pointnav_demo")
    dataset_file = generate_episodes(config, episodes, seed)
    print(f"{episodes} PointNav episodes on the demo apartment -> {dataset_file}")
    results = evaluate_oracle(config)
    for row in results:
        print(
            f"episode {row['episode']:.0f}: {row['steps']:.0f} steps "
            f"({row['ms_per_step']:.1f} ms/step), distance_to_goal "
            f"{row['distance_to_goal']:.3f} m, success {row['success']:.0f}, "
            f"SPL {row['spl']:.3f}"
        )
    print(
        f"mean success {np.mean([r['success'] for r in results]):.3f}, "
        f"mean SPL {np.mean([r['spl'] for r in results]):.3f}"
    )
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=3, help="episodes to generate")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--work", type=Path, help="folder for the episode dataset (temp)")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    if args.work is not None:
        run_pointnav(args.work, args.episodes, args.seed)
    else:
        with tempfile.TemporaryDirectory() as temporary:
            run_pointnav(Path(temporary), args.episodes, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
