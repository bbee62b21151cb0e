"""habitat-lab on rigidsim: the checks ``scripts/habitat_lab_check.sh`` runs in its own venv.

Run in the environment that script builds (habitat-lab 0.3.320260507 with its pins, numpy
1.26.4; rigidsim; the ``rigidsim-habitat-alias`` start-up hook). Each check prints one line
with its time; any failure stops the run with a non-zero exit. The checks:

1. ``alias``: the start-up hook is active (no code here installs the alias) and maps
   ``habitat_sim`` / ``magnum`` to rigidsim; NumPy is habitat-lab's pin;
2. ``import habitat`` and the modules that touch rigidsim's placeholders;
3. ``pointnav``: ``examples/habitat_lab_pointnav.py``: episodes from habitat-lab's
   ``generate_pointnav_episode`` on the demo apartment, ``habitat.Env`` with the PointNav
   test config and the oracle ``ShortestPathFollower``: success 1.0 and SPL >= 0.9 on every
   episode;
4. ``metrics``: the ``top_down_map`` and ``collisions`` measures on those episodes;
5. ``gym``: ``habitat.gym.make_gym_from_config``: reset and step with the ``rgb``,
   ``depth`` and ``pointgoal_with_gps_compass`` observations;
6. ``vector_env``: ``habitat.VectorEnv`` with two worker processes (``forkserver``: fresh
   interpreters, aliased by the start-up hook alone);
7. ``imagenav``: the ImageNav test config on the same episodes (an ``imagegoal`` image).

Usage: ``python scripts/habitat_lab_check.py [--episodes N] [--work DIR]``.
"""

from __future__ import annotations

import argparse
import functools
import importlib.util
import logging
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

REPO_ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = REPO_ROOT / "examples" / "habitat_lab_pointnav.py"
NUMPY_PIN = "1.26.4"  # habitat-lab 0.3.320260507's numpy
MIN_SPL = 0.9
HABITAT_LAB_MODULES = (  # habitat-lab modules that touch rigidsim's placeholders at import
    "habitat.datasets.rearrange.samplers.receptacle",
    "habitat.sims.habitat_simulator.debug_visualizer",
    "habitat.tasks.rearrange.rearrange_sim",
    "habitat.core.batch_rendering.env_batch_renderer",
)


def check_alias() -> str:
    """The .pth hook, not this script, aliases the names; NumPy is habitat-lab's."""
    hooks = [type(finder).__name__ for finder in sys.meta_path]
    assert "_DeferredAlias" in hooks, f"the rigidsim-habitat-alias hook is not active: {hooks}"
    import habitat_sim
    import magnum

    import engine

    assert habitat_sim is engine and magnum is engine.mn
    assert np.__version__ == NUMPY_PIN, f"numpy {np.__version__}, habitat-lab pins {NUMPY_PIN}"
    return f"habitat_sim -> engine, magnum -> engine.mn; numpy {np.__version__}"


def check_import_habitat() -> str:
    import habitat

    for module in HABITAT_LAB_MODULES:
        importlib.import_module(module)
    return f"habitat-lab {habitat.__version__} and {len(HABITAT_LAB_MODULES)} placeholder users"


@functools.cache
def load_example() -> Any:
    """The example module (loaded after the alias check: it installs the alias itself)."""
    spec = importlib.util.spec_from_file_location("habitat_lab_pointnav", EXAMPLE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def check_pointnav(example: Any, work: Path, episodes: int) -> str:
    results = example.run_pointnav(work, episodes)
    assert len(results) == episodes, results
    for row in results:
        assert row["success"] == 1.0 and row["spl"] >= MIN_SPL, f"oracle episode failed: {row}"
    spl = ", ".join(f"{row['spl']:.3f}" for row in results)
    per_step = np.mean([row["ms_per_step"] for row in results])
    return f"{episodes} episodes, success 1.0, SPL {spl}; {per_step:.1f} ms/step"


def check_metrics(example: Any, work: Path) -> str:
    import habitat
    from habitat.config import read_write
    from habitat.config.default_structured_configs import (
        CollisionsMeasurementConfig,
        TopDownMapMeasurementConfig,
    )

    config = example.pointnav_config(work / "pointnav_demo")
    with read_write(config):
        config.habitat.task.measurements.update(
            {
                "top_down_map": TopDownMapMeasurementConfig(),
                "collisions": CollisionsMeasurementConfig(),
            }
        )
    with habitat.Env(config=config) as env:
        env.reset()
        for _ in range(5):
            env.step(1)  # move_forward
        metrics = env.get_metrics()
    top_down = metrics["top_down_map"]["map"]
    assert isinstance(top_down, np.ndarray) and top_down.ndim == 2 and top_down.any()
    assert metrics["collisions"]["count"] >= 0
    return f"top_down_map {top_down.shape}, collisions {metrics['collisions']['count']}"


def check_gym(example: Any, work: Path) -> str:
    from habitat.gym import make_gym_from_config

    env = make_gym_from_config(example.pointnav_config(work / "pointnav_demo"))
    try:
        observation = env.reset()
        for key in ("rgb", "depth", "pointgoal_with_gps_compass"):
            assert key in observation, sorted(observation)
        assert observation["rgb"].shape == (256, 256, 3)
        observation, reward, done, info = env.step(env.action_space.sample())
        assert np.isfinite(reward) and "distance_to_goal" in info
    finally:
        env.close()
    return f"observations {sorted(observation)}, reward {reward:.3f}"


def make_env(config: Any) -> Any:
    """VectorEnv's environment factory (top level, so worker processes can import it): a
    habitat-lab gym environment, as habitat-baselines builds them."""
    from habitat.gym import make_gym_from_config

    return make_gym_from_config(config)


def check_vector_env(example: Any, work: Path) -> str:
    import habitat

    config = example.pointnav_config(work / "pointnav_demo")
    envs = habitat.VectorEnv(make_env_fn=make_env, env_fn_args=[(config,), (config,)])
    try:
        observations = envs.reset()
        assert envs.num_envs == 2 and len(observations) == 2
        outputs = envs.step([1, 2])  # move_forward in one, turn_left in the other
        assert len(outputs) == 2
        for observation, reward, _, info in outputs:
            assert "rgb" in observation and np.isfinite(reward) and "spl" in info
    finally:
        envs.close()
    return "2 worker processes reset and stepped"


def check_imagenav(example: Any, work: Path) -> str:
    import habitat

    config = example.pointnav_config(
        work / "pointnav_demo", "benchmark/nav/imagenav/imagenav_test.yaml"
    )
    with habitat.Env(config=config) as env:
        observation = env.reset()
        goal = observation["imagegoal"]
        assert goal.shape == (256, 256, 3) and goal.std() > 0, goal.shape
        env.step(1)
    return f"imagegoal {goal.shape}"


def run(name: str, check: Callable[[], str]) -> float:
    start = time.perf_counter()
    detail = check()
    seconds = time.perf_counter() - start
    print(f"habitat-lab check {name}: ok in {seconds:.1f} s ({detail})", flush=True)
    return seconds


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--work", type=Path, help="folder for the episode dataset (temp)")
    parser.add_argument(
        "--only", nargs="+", help="run these checks only (the later ones need --work of a run)"
    )
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)
    with tempfile.TemporaryDirectory() as temporary:
        work = args.work or Path(temporary)
        checks: dict[str, Callable[[], str]] = {
            "alias": check_alias,
            "import_habitat": check_import_habitat,
            "pointnav": lambda: check_pointnav(load_example(), work, args.episodes),
            "metrics": lambda: check_metrics(load_example(), work),
            "gym": lambda: check_gym(load_example(), work),
            "vector_env": lambda: check_vector_env(load_example(), work),
            "imagenav": lambda: check_imagenav(load_example(), work),
        }
        names = args.only or list(checks)
        total = sum(run(name, checks[name]) for name in names)
    print(f"habitat-lab check: {len(names)} checks ok in {total:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
