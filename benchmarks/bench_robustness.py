"""Issue 10 figures: object lifecycle (memory, step time) and crowds created at one point.

1. Lifecycle: ten rounds of adding 1000 boxes, one step, removing them all. After each
   round: the process's resident memory, the body slots in use, and the median time of a
   step with one object in the world. Target: memory within 10 MB of the first round and
   the one-object step within 10 % of the first round's.
2. Crowds: 100 boxes and 100 spheres (20 cm) created at one point 1 m above a floor, 3 s:
   when they are apart (no overlap deeper than 2 cm), their fastest speed and lowest center.

Usage::

    python benchmarks/bench_robustness.py          # both parts
    python benchmarks/bench_robustness.py --quick  # 3 rounds of 300, crowds of 30
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "physics"))

from helpers import add, make_world, register_primitive  # noqa: E402

FRAME = 1.0 / 60.0


def resident_mb() -> float:
    """MB of resident memory now (Linux /proc), else the peak from getrusage."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
        return pages * resource.getpagesize() / 2**20
    except OSError:
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def one_object_step_ms(world, templates, handle, repeats: int = 100) -> float:
    """Median CPU ms (``process_time``: other processes on a shared machine do not count)
    of ``step_physics(1/60)`` with one box resting on the floor."""
    obj = add(world, templates, handle, [0.0, 0.1, 0.0])
    for _ in range(5):
        world.step_physics(FRAME)
    times = []
    for _ in range(repeats):
        obj.awake = True  # keep it simulated (a sleeping body costs nothing)
        start = time.process_time()
        world.step_physics(FRAME)
        times.append(time.process_time() - start)
    world.rigid_object_manager.remove_object_by_id(obj.object_id)
    return 1000.0 * float(np.median(times))


def lifecycle(rounds: int, n_objects: int) -> None:
    world, templates = make_world()
    handle = register_primitive(templates, half=(0.1, 0.1, 0.1))
    rom = world.rigid_object_manager
    print(f"lifecycle: {rounds} rounds of adding and removing {n_objects} boxes")
    print(
        f"{'round':>5} {'memory MB':>10} {'d MB':>6} {'slots':>6} {'1-object step ms':>17}"
        f" {'ratio':>6}"
    )
    print(
        f"{'fresh':>5} {resident_mb():>10.1f} {'':>6} {world.bodies.count:>6}"
        f" {one_object_step_ms(world, templates, handle):>17.2f}"
    )
    first_mb = first_ms = None
    for round_ in range(rounds):
        objects = [
            add(
                world,
                templates,
                handle,
                [0.25 * (k % 32), 0.1 + 0.25 * (k // 1024), 0.25 * ((k // 32) % 32)],
            )
            for k in range(n_objects)
        ]
        world.step_physics(FRAME)
        for obj in objects:
            rom.remove_object_by_id(obj.object_id)
        del objects
        step_ms = one_object_step_ms(world, templates, handle)
        mb = resident_mb()
        first_mb = mb if first_mb is None else first_mb
        first_ms = step_ms if first_ms is None else first_ms
        print(
            f"{round_ + 1:>5} {mb:>10.1f} {mb - first_mb:>6.1f} {world.bodies.count:>6}"
            f" {step_ms:>17.2f} {step_ms / first_ms:>6.2f}",
            flush=True,
        )


def crowd(primitive: str, n: int, seconds: float = 3.0) -> None:
    world, templates = make_world()
    handle = register_primitive(templates, primitive, (0.1, 0.1, 0.1))
    bodies = [add(world, templates, handle, [0.0, 1.0, 0.0]) for _ in range(n)]
    index = [b.object_id for b in bodies]
    fastest, lowest, apart_at = 0.0, np.inf, None
    start = time.perf_counter()
    for frame in range(int(round(seconds / FRAME))):
        world.step_physics(FRAME)
        b = world.bodies
        fastest = max(fastest, np.linalg.norm(b.body_linear_velocity[index], axis=1).max())
        lowest = min(lowest, b.body_position[index, 1].min())
        deepest = max(
            [-p.contact_distance for p in world.get_physics_contact_points() if p.object_id_a != 0],
            default=0.0,
        )
        if apart_at is None and deepest < 0.02 and frame * FRAME > 0.5:
            apart_at = (frame + 1) * FRAME
    wall = time.perf_counter() - start
    apart = f"{apart_at:.2f} s" if apart_at is not None else f"not in {seconds} s"
    print(
        f"{n} x {primitive:<26} apart after {apart:<10} fastest {fastest:.2f} m/s, "
        f"lowest center {lowest:.3f} m (floor + half size 0.100), deepest overlap at the "
        f"end {deepest * 100:.1f} cm, {wall:.1f} s wall",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller rounds and crowds")
    args = parser.parse_args()
    if args.quick:
        lifecycle(3, 300)
        crowd("cubeSolid", 30)
        crowd("icosphereSolid_subdivs_1", 30)
    else:
        lifecycle(10, 1000)
        crowd("cubeSolid", 100)
        crowd("icosphereSolid_subdivs_1", 100)


if __name__ == "__main__":
    main()
