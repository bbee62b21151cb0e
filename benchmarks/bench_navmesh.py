"""Benchmark the navmesh: build time, find_path and try_step throughput.

Run on demand (not a test)::

    .venv/bin/python benchmarks/bench_navmesh.py          # full run
    .venv/bin/python benchmarks/bench_navmesh.py --quick  # fewer repeats

Scenes: Habitat's ``test_assets/scenes/stage_floor1.glb`` (Y up, scale 2: a 40 x 40 m
terrain), ``simple_room.glb`` (Z up) and, when ``engine.demo.datasets.demo_data_path()`` can
provide it, the generated demo ``apartment.glb``. Each stage is loaded through
``engine.scene.assets.load_meshes`` with its stage config's up / front / scale, merged, and built
with the default ``NavMeshSettings`` (0.05 m cells). Reported: median build time, grid size,
islands and area; ``find_path`` calls per second between random navigable points (the first
call, which also builds the Dijkstra graph, is timed apart); ``try_step`` and
``try_step_no_sliding`` calls per second for 0.25 m steps in random directions (the engine
calls one of them per agent step at up to 60 Hz). Compare ratios, not absolute times across
runs: the machine is shared.

The greedy follower (``--follower``): ``GreedyGeodesicFollower.find_path`` on the demo apartment
(30 degree turns, 0.25 m steps, goals over 2 m away, as Habitat's follower test), CPU time per
action and per 50-action path against the target of 50 ms, the best of ``--repeats`` runs of the
same episodes (the machine is shared: every run is printed). ``--baseline DIR`` runs the same
episodes with the code of another checkout (e.g. ``git worktree add /tmp/base <commit>``) in a
subprocess right after, and prints the speed-up.
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

import numpy as np

from engine.scene.assets import load_meshes, merge_meshes
from navmesh import NavMeshSettings, PathFinder, ShortestPath

HABITAT_SCENES = Path(__file__).resolve().parents[1] / "tests" / "habitat_data"
STEP_LENGTH = 0.25  # meters, the tutorial's forward step
FOLLOWER_TARGET_MS = 50.0  # a 50-action path, planned by find_path, CPU milliseconds
FOLLOWER_EPISODES = 12
FOLLOWER_REPEATS = 3  # runs of the episodes; the best one is reported


def stage_triangles(glb: Path) -> tuple[np.ndarray, np.ndarray]:
    """World-frame vertices/faces of a stage, honouring ``<stem>.stage_config.json``.

    A ``.glb`` without a stage config is Z-up (Habitat's default for bare stages).
    """
    config_path = glb.with_name(glb.name.split(".")[0] + ".stage_config.json")
    config = json.loads(config_path.read_text()) if config_path.is_file() else {}
    up = config.get("up", [0, 0, 1] if not config_path.is_file() else [0, 1, 0])
    front = config.get("front", [0, 1, 0] if not config_path.is_file() else [0, 0, -1])
    meshes = load_meshes(glb, up=up, front=front, scale=config.get("scale", [1, 1, 1]))
    merged = merge_meshes(meshes)
    return np.asarray(merged.vertices, np.float64), np.asarray(merged.faces, np.int64)


def bench_build(vertices, faces, repeats: int) -> tuple[float, PathFinder]:
    """Median build time (s) and the last PathFinder."""
    times, pathfinder = [], None
    for _ in range(repeats):
        pathfinder = PathFinder()
        start = time.perf_counter()
        pathfinder.build(vertices, faces, NavMeshSettings())
        times.append(time.perf_counter() - start)
    return statistics.median(times), pathfinder


def bench_paths(pathfinder: PathFinder, n_paths: int) -> dict:
    """find_path throughput between random points of the largest island."""
    pathfinder.seed(0)
    pairs = [
        (
            pathfinder.get_random_navigable_point(island_index=0),
            pathfinder.get_random_navigable_point(island_index=0),
        )
        for _ in range(n_paths + 1)
    ]
    start = time.perf_counter()
    pathfinder.find_path(ShortestPath(requested_start=pairs[0][0], requested_end=pairs[0][1]))
    first = time.perf_counter() - start
    lengths, start = [], time.perf_counter()
    for a, b in pairs[1:]:
        path = ShortestPath(requested_start=a, requested_end=b)
        pathfinder.find_path(path)
        lengths.append(path.geodesic_distance / max(np.linalg.norm(b - a), 1e-9))
    per_second = n_paths / (time.perf_counter() - start)
    return {"first_s": first, "per_s": per_second, "detour": float(np.median(lengths))}


def bench_steps(pathfinder: PathFinder, n_steps: int, sliding: bool) -> float:
    """try_step (sliding) or try_step_no_sliding calls per second, random 0.25 m steps."""
    pathfinder.seed(1)
    rng = np.random.default_rng(1)
    starts = [pathfinder.get_random_navigable_point(island_index=0) for _ in range(n_steps)]
    angles = rng.uniform(0.0, 2.0 * np.pi, n_steps)
    ends = [
        s + STEP_LENGTH * np.array([np.cos(a), 0.0, np.sin(a)])
        for s, a in zip(starts, angles, strict=True)
    ]
    step = pathfinder.try_step if sliding else pathfinder.try_step_no_sliding
    start = time.perf_counter()
    for s, e in zip(starts, ends, strict=True):
        step(s, e)
    return n_steps / (time.perf_counter() - start)


def scenes() -> list[tuple[str, Path]]:
    """(name, glb) of the scenes to measure; the demo apartment when it can be generated."""
    found = [
        ("stage_floor1 (40x40 m terrain)", HABITAT_SCENES / "test_assets/scenes/stage_floor1.glb"),
        ("simple_room", HABITAT_SCENES / "test_assets/scenes/simple_room.glb"),
    ]
    try:
        from engine.demo import demo_data_path

        apartment = demo_data_path() / "scene_datasets/demo/apartment.glb"
        if apartment.is_file():
            found.append(("demo apartment", apartment))
    except Exception as error:  # the demo dataset is optional here
        print(f"(demo apartment skipped: {error})")
    return found


def bench_follower(episodes: int, repeats: int) -> dict:
    """CPU seconds of ``find_path`` over ``episodes`` seeded episodes (the best of ``repeats``
    runs; the first also builds the navmesh's lazily computed tables), and their actions."""
    import engine as habitat_sim
    from engine.demo import demo_data_path

    cfg = habitat_sim.SimulatorConfiguration()
    cfg.scene_id = str(demo_data_path() / "scene_datasets/demo/apartment.glb")
    agent_cfg = habitat_sim.agent.AgentConfiguration()
    for turn in ("turn_left", "turn_right"):
        agent_cfg.action_space[turn].actuation.amount = 30.0
    with habitat_sim.Simulator(habitat_sim.Configuration(cfg, [agent_cfg])) as sim:
        pathfinder, agent = sim.pathfinder, sim.get_agent(0)
        pathfinder.seed(0)
        follower = habitat_sim.GreedyGeodesicFollower(
            pathfinder, agent, forward_key="move_forward", left_key="turn_left",
            right_key="turn_right",
        )  # fmt: skip
        pairs = []
        while len(pairs) < episodes:
            start, goal = (
                pathfinder.get_random_navigable_point(),
                pathfinder.get_random_navigable_point(),
            )
            path = ShortestPath(requested_start=start, requested_end=goal)
            if pathfinder.find_path(path) and path.geodesic_distance > 2.0:
                pairs.append((start, goal))
        runs = []
        for _ in range(repeats):
            actions, cpu = 0, 0.0
            for start, goal in pairs:
                agent.state = habitat_sim.AgentState(start)
                begin = time.process_time()
                actions += len(follower.find_path(goal))
                cpu += time.process_time() - begin
            runs.append(cpu)
    # the best run is the least disturbed by other processes (timeit's rule); all are printed
    return {"cpu_s": min(runs), "runs_s": runs, "actions": actions}


def print_follower(result: dict, baseline: dict | None) -> None:
    per_action_ms = 1000.0 * result["cpu_s"] / result["actions"]
    per_path = 50.0 * per_action_ms
    met = "met" if per_path < FOLLOWER_TARGET_MS else "MISSED"
    print(
        f"greedy follower find_path: {result['actions']} actions, {per_action_ms:.2f} ms CPU per "
        f"action (best of {len(result['runs_s'])} runs), {per_path:.1f} ms per 50-action path "
        f"(target < {FOLLOWER_TARGET_MS:.0f} ms: {met})"
    )
    print(f"  runs: {per_action_list(result)} ms CPU per action")
    if baseline is not None:
        base_ms = 1000.0 * baseline["cpu_s"] / baseline["actions"]
        print(
            f"  baseline: {base_ms:.2f} ms CPU per action (runs: {per_action_list(baseline)}); "
            f"speed-up {base_ms / per_action_ms:.1f}x"
        )


def per_action_list(result: dict) -> str:
    """The runs' CPU milliseconds per action, for the printout."""
    runs = result.get("runs_s", [result["cpu_s"]])  # an older checkout reports one run
    return ", ".join(f"{1000.0 * cpu / result['actions']:.2f}" for cpu in runs)


def run_baseline(directory: Path, episodes: int, repeats: int) -> dict:
    """The follower measurement with another checkout's code, in a subprocess."""
    env = dict(os.environ, PYTHONPATH=str(directory))
    command = [sys.executable, __file__, "--follower-json", "--episodes", str(episodes)]
    command += ["--repeats", str(repeats)]
    done = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--follower", action="store_true", help="only the greedy follower")
    parser.add_argument("--baseline", type=Path, help="checkout to compare the follower with")
    parser.add_argument("--episodes", type=int, default=FOLLOWER_EPISODES)
    parser.add_argument("--repeats", type=int, default=FOLLOWER_REPEATS, help="follower runs")
    parser.add_argument("--follower-json", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.follower_json:
        print(json.dumps(bench_follower(args.episodes, args.repeats)))
        return
    follower = bench_follower(args.episodes, args.repeats)
    baseline = run_baseline(args.baseline, args.episodes, args.repeats) if args.baseline else None
    print_follower(follower, baseline)
    if args.follower:
        return
    build_repeats, n_paths, n_steps = (1, 10, 300) if args.quick else (3, 50, 2000)
    print(
        f"{'scene':32s} {'tris':>7s} {'build s':>8s} {'grid LxZxX':>14s} {'isl':>4s} "
        f"{'area m2':>8s} {'path/s':>7s} {'1st s':>6s} {'detour':>6s} "
        f"{'step/s':>7s} {'noslide/s':>9s}"
    )
    for name, glb in scenes():
        vertices, faces = stage_triangles(glb)
        build_s, pf = bench_build(vertices, faces, build_repeats)
        paths = bench_paths(pf, n_paths)
        slide = bench_steps(pf, n_steps, sliding=True)
        no_slide = bench_steps(pf, n_steps, sliding=False)
        layers, nz, nx = pf.navmesh_data.shape
        print(
            f"{name:32s} {len(faces):7d} {build_s:8.2f} {f'{layers}x{nz}x{nx}':>14s} "
            f"{pf.num_islands:4d} {pf.navigable_area:8.1f} {paths['per_s']:7.1f} "
            f"{paths['first_s']:6.2f} {paths['detour']:6.3f} {slide:7.0f} {no_slide:9.0f}"
        )


if __name__ == "__main__":
    main()
