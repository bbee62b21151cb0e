"""Benchmark ``engine.batch.run_batch``: episodes per second by backend and worker count.

Two kinds of episode:

* ``physics``: 5 boxes of 0.2 m dropped in a loose column on a floor slab and simulated
  for ``--sim-seconds`` (about 1 s of wall time per episode by default, the size the
  issue's target speaks of: at least 1.8x with 2 workers on 2 cores);
* ``empty``: returns at once, so the whole time is the backend's own cost per episode
  (shipping the task and the result, bookkeeping).

For each kind: a plain ``for`` loop calling the episode function (the baseline), then
``run_batch`` with ``serial``, ``process`` (1, 2 and all workers) and ``ray`` (1, 2 and all
workers). Printed: wall seconds, episodes per second, speed-up against the plain loop and
the per-episode overhead ``(wall - loop wall) / episodes`` of the one-worker runs. Process
pools and the Ray cluster are started inside each timed run except Ray's own start-up (one
``ray.init`` before the Ray runs, timed separately), as a user who keeps a cluster running
sees it. Ratios from one run are the figures to compare: the machine is shared.

Usage::

    python benchmarks/bench_batch.py                 # 8 physics episodes per run
    python benchmarks/bench_batch.py --quick         # 4 episodes, no Ray
    python benchmarks/bench_batch.py --episodes 16 --sim-seconds 2
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import engine as habitat_sim
from engine.batch import run_batch

MotionType = habitat_sim.physics.MotionType


def physics_episode(params: dict, seed: int) -> dict:
    """Five boxes dropped on a floor with seeded jitter; returns their final heights."""
    rng = np.random.default_rng(seed)
    sim = habitat_sim.Simulator(habitat_sim.Configuration())
    templates, objects = sim.get_object_template_manager(), sim.get_rigid_object_manager()
    unit_cube = templates.get_template_handles("cubeSolid")[0]
    floor_template = templates.get_template_by_handle(unit_cube).copy()
    floor_template.scale = [3.0, 0.1, 3.0]
    floor = objects.add_object_by_template_id(templates.register_template(floor_template, "fl"))
    floor.translation = [0.0, -0.1, 0.0]
    floor.motion_type = MotionType.STATIC
    box_template = templates.get_template_by_handle(unit_cube).copy()
    box_template.scale = [0.1, 0.1, 0.1]
    box_id = templates.register_template(box_template, "box")
    boxes = []
    for level in range(5):
        box = objects.add_object_by_template_id(box_id)
        box.translation = [rng.uniform(-0.05, 0.05), 0.15 + 0.3 * level, rng.uniform(-0.05, 0.05)]
        boxes.append(box)
    for _ in range(round(params["sim_seconds"] * 60)):
        sim.step_physics(1.0 / 60.0)
    heights = [float(box.translation[1]) for box in boxes]
    sim.close()
    return {"heights": heights}


def empty_episode(params: dict, seed: int) -> dict:
    """No work: measures what a backend costs per episode."""
    return {"seed": seed}


def time_loop(episode_fn, params: list[dict]) -> float:
    """Wall seconds of a plain loop over the episodes (the baseline)."""
    start = time.perf_counter()
    for index, entry in enumerate(params):
        episode_fn(entry, index)
    return time.perf_counter() - start


def time_batch(episode_fn, params: list[dict], backend: str, workers: int | None) -> float:
    start = time.perf_counter()
    results = run_batch(episode_fn, params, backend=backend, workers=workers, progress=False)
    elapsed = time.perf_counter() - start
    failed = [r for r in results if not r.ok]
    if failed:
        raise RuntimeError(f"{backend} x {workers}: {failed[0].error}\n{failed[0].traceback}")
    return elapsed


def runs(use_ray: bool) -> list[tuple[str, int | None]]:
    """(backend, workers) pairs: 1, 2 and all workers (all = os.cpu_count())."""
    counts = sorted({1, 2, os.cpu_count() or 1})
    pairs = [("serial", 1)] + [("process", n) for n in counts]
    if use_ray:
        pairs += [("ray", n) for n in counts]
    return pairs


def bench(kind: str, episode_fn, params: list[dict], use_ray: bool) -> None:
    loop = time_loop(episode_fn, params)
    n = len(params)
    print(
        f"\n{kind} episodes: {n} per run; plain loop {loop:.2f} s wall "
        f"({n / loop:.2f} episodes/s, {1000 * loop / n:.1f} ms each)"
    )
    print(
        f"{'backend':<8} {'workers':>7} {'wall s':>8} {'ep/s':>8} {'vs loop':>8} "
        f"{'overhead ms/ep':>15}"
    )
    for backend, workers in runs(use_ray):
        wall = time_batch(episode_fn, params, backend, workers)
        overhead = f"{1000 * (wall - loop) / n:15.1f}" if workers == 1 else ""
        print(
            f"{backend:<8} {workers:>7} {wall:8.2f} {n / wall:8.2f} {loop / wall:7.2f}x {overhead}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--episodes", type=int, default=8, help="physics episodes per run")
    parser.add_argument(
        "--sim-seconds", type=float, default=2.0, help="simulated seconds per physics episode"
    )
    parser.add_argument("--quick", action="store_true", help="4 episodes, no Ray")
    parser.add_argument("--no-ray", action="store_true", help="skip the Ray backend")
    args = parser.parse_args()
    episodes = 4 if args.quick else args.episodes
    use_ray = not (args.quick or args.no_ray)
    print(
        f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.1f} at the start "
        "(other work on the machine slows every figure)"
    )
    if use_ray:
        start = time.perf_counter()
        _start_local_ray()
        print(f"ray.init (local cluster, loopback): {time.perf_counter() - start:.1f} s")
    try:
        bench("physics", physics_episode, [{"sim_seconds": args.sim_seconds}] * episodes, use_ray)
        bench("empty", empty_episode, [{}] * (10 * episodes), use_ray)
    finally:
        if use_ray:
            import ray

            ray.shutdown()


def _start_local_ray() -> None:
    """A local Ray instance on loopback only, kept for all Ray runs of the benchmark."""
    os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"  # before Ray is imported
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    import ray

    ray.init(num_cpus=os.cpu_count(), include_dashboard=False, log_to_driver=False)


if __name__ == "__main__":
    main()
