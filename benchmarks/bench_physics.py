"""Benchmark rigidsim's physics against pybullet on the same scenes (on demand).

Scenes (0.2 m boxes of 1 kg on a floor, fixed step 0.008 s driven at 1/60 s frames):

* ``pile-N``: N boxes dropped in a loose grid with random orientations (N = 10, 100, 500);
* ``stack-10``: a vertical stack of 10 boxes (quality: lateral drift of the top box);
* ``pyramid-6``: a pyramid with a base of 6 boxes (quality: largest displacement).

Reported per scene: milliseconds of wall time per simulated second (lower is better; under
1000 is faster than real time), the pybullet figure for the same scene and the ratio, the
number of bodies asleep at the end, for piles the moment all boxes first sleep (simulated
and wall seconds: "settles faster than real time" when wall < simulated), and rigidsim's
profile split (broad phase, collide =
narrow phase + manifolds, solve, the rest). Ratios measured in one run are the numbers to
compare; absolute times vary a lot on a shared machine.

Usage::

    python benchmarks/bench_physics.py              # full: 10 s per scene (500-pile: 3 s)
    python benchmarks/bench_physics.py --quick      # 2 s per scene, 500-pile skipped
    python benchmarks/bench_physics.py --reference  # also time the reference path
                                                    # (use_vectorized=False) on each scene
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "physics"))

from helpers import add, make_world, register_primitive  # noqa: E402

from engine import mn  # noqa: E402

FRAME = 1.0 / 60.0
HALF = 0.1


def pile_positions(n: int, seed: int = 0):
    """Loose grid of ``n`` drop positions and random unit quaternions [x, y, z, w]."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(min(n, 100))))
    positions, rotations = [], []
    for k in range(n):
        layer, cell = divmod(k, side * side)
        row, col = divmod(cell, side)
        positions.append([(col - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
                          0.3 + 0.3 * layer + rng.uniform(0, 0.05),
                          (row - side / 2) * 0.25 + rng.uniform(-0.03, 0.03)])
        q = rng.normal(size=4)
        rotations.append(q / np.linalg.norm(q))
    return positions, rotations


def stack_positions(n: int = 10):
    return [[0.0, HALF + 0.201 * i, 0.0] for i in range(n)], [[0, 0, 0, 1.0]] * n


def pyramid_positions(base: int = 6):
    positions = []
    for level in range(base):
        for i in range(base - level):
            positions.append([(i - (base - 1 - level) / 2) * 0.202, HALF + level * 0.201, 0.0])
    return positions, [[0, 0, 0, 1.0]] * len(positions)


def run_rigidsim(positions, rotations, seconds, vectorized=True):
    world, templates = make_world(floor_half=20.0)
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, "cubeSolid", (HALF, HALF, HALF))
    boxes = []
    for p, q in zip(positions, rotations, strict=True):
        box = add(world, templates, handle, p)
        box.rotation = mn.Quaternion.from_xyzw(q)
        boxes.append(box)
    start = time.perf_counter()
    settled = None  # (simulated s, wall s) when every box first sleeps
    for frame in range(int(round(seconds / FRAME))):
        world.step_physics(FRAME)
        if settled is None and not world.bodies.body_awake[1:world.bodies.count].any():
            settled = ((frame + 1) * FRAME, time.perf_counter() - start)
    wall = time.perf_counter() - start
    final = np.array([np.asarray(b.translation) for b in boxes])
    asleep = sum(not b.awake for b in boxes)
    return wall, final, asleep, dict(world.profile), settled


def run_pybullet(positions, rotations, seconds):
    import pybullet as p

    client = p.connect(p.DIRECT)
    p.setGravity(0, -9.8, 0, physicsClientId=client)
    p.setTimeStep(0.008, physicsClientId=client)
    plane = p.createCollisionShape(p.GEOM_BOX, halfExtents=[20, 0.05, 20], physicsClientId=client)
    p.createMultiBody(0, plane, basePosition=[0, -0.05, 0], physicsClientId=client)
    box = p.createCollisionShape(p.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=client)
    bodies = [p.createMultiBody(1.0, box, basePosition=pos, baseOrientation=list(q),
                                physicsClientId=client)
              for pos, q in zip(positions, rotations, strict=True)]
    steps, accumulated = 0, 0.0
    start = time.perf_counter()
    for _ in range(int(round(seconds / FRAME))):  # the same accumulator as step_physics
        accumulated += FRAME
        while accumulated >= 0.008:
            p.stepSimulation(physicsClientId=client)
            accumulated -= 0.008
            steps += 1
    wall = time.perf_counter() - start
    final = np.array([p.getBasePositionAndOrientation(b, physicsClientId=client)[0]
                      for b in bodies])
    p.disconnect(client)
    return wall, final


def quality(name, start, final):
    if name.startswith("stack"):
        return f"top drift {np.linalg.norm((final[-1] - start[-1])[[0, 2]]) * 100:.2f} cm"
    if name.startswith("pyramid"):
        return f"max displacement {np.abs(final - start).max() * 100:.2f} cm"
    return f"lowest center {final[:, 1].min():.3f} m"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 s per scene, no 500 pile")
    parser.add_argument("--reference", action="store_true",
                        help="also run the reference path (use_vectorized=False)")
    args = parser.parse_args()
    seconds = 2.0 if args.quick else 10.0
    scenes = [("pile-10", pile_positions(10), seconds), ("pile-100", pile_positions(100), seconds),
              ("stack-10", stack_positions(), seconds), ("pyramid-6", pyramid_positions(), seconds)]
    if not args.quick:
        scenes.append(("pile-500", pile_positions(500), 3.0))
    try:
        import pybullet  # noqa: F401

        have_bullet = True
    except ImportError:
        have_bullet = False
    print(f"{'scene':<10} {'sim s':>5} {'rigidsim ms/s':>13} {'pybullet ms/s':>13} {'ratio':>6} "
          f"{'asleep':>7}  quality (rigidsim | pybullet)   profile % (broad/collide/solve/rest)")
    for name, (positions, rotations), sim_seconds in scenes:
        start = np.array(positions)
        wall, final, asleep, profile, settled = run_rigidsim(positions, rotations, sim_seconds)
        ours = wall / sim_seconds * 1000
        total = sum(profile.values()) or 1.0
        split = [profile.get("broad phase", 0.0), profile.get("collide", 0.0)
                 - profile.get("broad phase", 0.0), profile.get("solve", 0.0),
                 profile.get("forces", 0.0) + profile.get("integrate", 0.0)
                 + profile.get("sleep", 0.0)]
        split_text = "/".join(f"{100 * s / total:.0f}" for s in split)
        if have_bullet:
            bullet_wall, bullet_final = run_pybullet(positions, rotations, sim_seconds)
            theirs = bullet_wall / sim_seconds * 1000
            ratio = f"{ours / theirs:6.1f}"
            bullet_quality = quality(name, start, bullet_final)
        else:
            theirs, ratio, bullet_quality = float("nan"), "   n/a", "n/a"
        print(f"{name:<10} {sim_seconds:5.1f} {ours:13.1f} {theirs:13.1f} {ratio} "
              f"{asleep:4d}/{len(positions):<3d} {quality(name, start, final)} | {bullet_quality}"
              f"   {split_text}")
        if args.reference:
            reference_wall = run_rigidsim(positions, rotations, sim_seconds, False)[0]
            print(f"{'':<10} reference path: {reference_wall / sim_seconds * 1000:.1f} ms/s "
                  f"({reference_wall / wall:.1f}x the vectorized path)")
        if settled is not None and name.startswith("pile"):
            print(f"{'':<10} settled: all {len(positions)} asleep after {settled[0]:.2f} s "
                  f"simulated, {settled[1]:.2f} s wall ({settled[0] / settled[1]:.2f}x real time)")


if __name__ == "__main__":
    main()
