"""Step time of the Gymnasium environment ``rigidsim/PushObject-v0`` (on demand).

One ``env.step`` is 0.1 s of simulated time (13 fixed physics steps of 0.008 s) plus the
10-float observation and the reward. The benchmark resets the environment with a fixed
seed, takes the scripted pushing policy's actions (``scripted_push_action``) for a number
of steps, and reports CPU milliseconds per ``env.step`` (``time.process_time``: this
process's CPU, less sensitive to a loaded machine than wall time) and where the time goes
(the physics world's stage timers).

``--baseline PATH`` runs the same episodes, interleaved in the same run, with the rigidsim
checkout at ``PATH`` (a subprocess with ``PYTHONPATH=PATH``) and prints the ratio; the
target (issue 22) is a step at least 3x faster than the baseline's.

Usage::

    python benchmarks/bench_env.py                       # this checkout only
    python benchmarks/bench_env.py --baseline ../main    # + ratio against another checkout
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET_SPEEDUP = 3.0


def time_steps(n_steps: int, seed: int) -> dict:
    """CPU ms per ``env.step`` over ``n_steps`` scripted actions (reset not counted)."""
    import gymnasium as gym

    import engine.envs  # noqa: F401  (registers the ids)
    from engine.envs import scripted_push_action

    env = gym.make("rigidsim/PushObject-v0")
    observation, _ = env.reset(seed=seed)
    cpu = 0.0
    for _ in range(n_steps):
        action = scripted_push_action(observation)
        start = time.process_time()
        observation, _, terminated, truncated, _ = env.step(action)
        cpu += time.process_time() - start
        if terminated or truncated:
            observation, _ = env.reset(seed=seed)
    world = env.unwrapped._sim.get_physics_world()
    profile = {name: round(1000 * seconds / n_steps, 3) for name, seconds in world.profile.items()}
    env.close()
    return {"cpu_ms": 1000 * cpu / n_steps, "profile": profile}


def time_in(checkout: Path, n_steps: int, seed: int) -> dict:
    """:func:`time_steps` in a subprocess on the rigidsim checkout ``checkout``."""
    code = (
        "import json, sys; sys.path.insert(0, sys.argv[1]); import bench_env; "
        "print(json.dumps(bench_env.time_steps(int(sys.argv[2]), int(sys.argv[3]))))"
    )
    env = dict(os.environ, PYTHONPATH=str(checkout))
    out = subprocess.run(
        [sys.executable, "-c", code, str(ROOT / "benchmarks"), str(n_steps), str(seed)],
        env=env,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100, help="env steps per repeat")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--baseline", type=Path, help="another rigidsim checkout to compare")
    args = parser.parse_args()
    ours, theirs = [], []
    for repeat in range(args.repeats):  # interleaved: both see the same machine load
        ours.append(time_in(ROOT, args.steps, args.seed))
        if args.baseline:
            theirs.append(time_in(args.baseline, args.steps, args.seed))
        print(
            f"repeat {repeat}: {ours[-1]['cpu_ms']:.2f} ms per step"
            + (f", baseline {theirs[-1]['cpu_ms']:.2f} ms" if theirs else "")
        )
    median = statistics.median(r["cpu_ms"] for r in ours)
    print(f"\nPushObject-v0: {median:.2f} CPU ms per env.step (median of {args.repeats})")
    print(f"  physics stages, ms per env.step: {ours[0]['profile']}")
    if theirs:
        base = statistics.median(r["cpu_ms"] for r in theirs)
        speedup = base / median
        met = "met   " if speedup >= TARGET_SPEEDUP else "MISSED"
        print(f"  baseline {base:.2f} ms per env.step; speed-up {speedup:.2f}x")
        print(f"  [{met}] PushObject-v0 step >= {TARGET_SPEEDUP:g}x faster than the baseline")


if __name__ == "__main__":
    main()
