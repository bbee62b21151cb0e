"""A parameter sweep with ``run_batch``: bounce height against restitution, on every core.

Each episode builds its own simulator, drops a ball from 1 m on a static floor and returns
the first bounce's apex; ``run_batch`` spreads the episodes over worker processes (or a Ray
cluster), gives episode ``i`` a seed that depends only on the batch seed and ``i`` (the same
results on any backend), and writes one JSON line per finished episode. The apex follows
e^2 h (restitution e, drop height h).

    python examples/batch_sweep.py                   # worker processes, all cores
    python examples/batch_sweep.py --backend ray     # Ray (pip install 'rigidsim[ray]');
                                                     # RAY_ADDRESS=host:6379 for a cluster
    python examples/batch_sweep.py --output-dir runs/drops   # results.jsonl, resumable
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import engine as habitat_sim
from engine.batch import run_batch

MotionType = habitat_sim.physics.MotionType


def drop_ball(params: dict[str, Any], seed: int) -> dict[str, float]:
    """One episode: the apex of the first bounce of a 0.1 m ball dropped from about 1 m."""
    rng = np.random.default_rng(seed)
    sim = habitat_sim.Simulator(habitat_sim.Configuration())
    templates, objects = sim.get_object_template_manager(), sim.get_rigid_object_manager()
    floor_template = templates.get_template_by_handle(
        templates.get_template_handles("cubeSolid")[0]
    )
    floor_template.scale = [2.0, 0.1, 2.0]
    floor = objects.add_object_by_template_id(templates.register_template(floor_template, "floor"))
    floor.translation = [0.0, -0.1, 0.0]  # top face at y = 0
    floor.motion_type = MotionType.STATIC
    floor.restitution_coefficient = 1.0  # pair restitution = ball's x floor's
    ball = objects.add_object_by_template_handle(
        templates.get_template_handles("icosphereSolid")[0]
    )
    radius = 0.1  # the primitive templates' scale: a 0.2 m sphere
    height = 1.0 + rng.uniform(-0.05, 0.05)
    ball.translation = [0.0, radius + height, 0.0]
    ball.restitution_coefficient = params["restitution"]
    ball.linear_damping = 0.0
    apex, falling, bounced = 0.0, True, False
    for _ in range(250):  # 2 s of 0.008 s steps
        sim.step_physics(0.008)
        velocity_y = ball.linear_velocity[1]
        if falling and velocity_y > 0:
            falling, bounced = False, True
        if bounced:
            apex = max(apex, ball.translation[1] - radius)
            if velocity_y < 0:
                break
    sim.close()
    return {"height": height, "apex": apex}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", choices=["process", "ray", "serial"], default="process")
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    parser.add_argument("--output-dir", default=None)
    parser.add_argument("--fast", action="store_true", help="4 episodes (the test suite's mode)")
    args = parser.parse_args()

    restitutions = np.linspace(0.2, 0.8, 4 if args.fast else 13)
    results = run_batch(
        drop_ball,
        [{"restitution": float(e)} for e in restitutions],
        backend=args.backend,
        workers=args.workers,
        seed=0,
        output_dir=args.output_dir,
        resume=args.output_dir is not None,
    )
    print(" e     apex / h   e^2   status")
    for e, record in zip(restitutions, results, strict=True):
        if record.ok:
            ratio = record.value["apex"] / record.value["height"]
            print(f"{e:.2f}  {ratio:8.3f}  {e * e:.3f}  {record.status}")
        else:
            print(f"{e:.2f}  {'':8s}  {e * e:.3f}  {record.status}")


if __name__ == "__main__":
    main()
