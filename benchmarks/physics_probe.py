"""Reliability probe of the physics: seeded random scenarios, checked after every frame.

Habitat-style use through the object API (``add_object_by_template_handle``,
``obj.translation``, ``obj.linear_velocity``, ``obj.motion_type``, ``obj.mass`` ...) on three
stages: a flat box floor (``tests/physics/helpers.py``), Habitat's ``plane.glb`` and the demo
apartment (floor y = -1.45). Families (each seed draws its shape, size, speed ...):

``drop``        a primitive (cube, sphere, cylinder, cone, capsule), 1 cm - 2 m, random pose
``thin``        a 1 mm slab, 5 cm - 1 m wide, thrown down at up to 30 m/s
``throw-floor`` a primitive, 1 cm - 50 cm, thrown at the floor at 5-30 m/s, spinning
``throw-wall``  the same thrown sideways at the apartment's walls and furniture
``collide``     two primitives (masses 0.03-30 kg) thrown at each other at up to 15 m/s
``mass``        a heavy body on a light one and vice versa (template masses 1:1000)
``overlap``     2-8 equal bodies created inside each other and the floor
``kinematic``   a kinematic box pushing a body, by velocity control or by its translation
``teleport``    a body teleported 10-45 % of its size into the floor or another body
``props``       mass, friction and restitution changed at run time (Habitat's setters)
``remove``      the bottom or middle of a stack of four removed while they rest
``nonuniform``  round primitives scaled non-uniformly (convex hulls), 1 cm - 2 m

Checks after every frame, for every dynamic body: a finite state; its lowest hull point
less than 2 cm below the floor and its center not below it (after ``grace`` frames for
bodies created or teleported inside: the push out is capped at 2 m/s); its speed within
what the fall and the throw allow (no energy from nowhere). After the settling time:
non-round bodies asleep (round ones may roll on) and no two bodies overlapping by more than
2 cm (fcl penetration depth). On demand, never in CI; deterministic for a seed::

    python benchmarks/physics_probe.py                     # 3 seeds of every family
    python benchmarks/physics_probe.py --seeds 10 --families thin,kinematic --stages box
    python benchmarks/physics_probe.py --reference         # the plain reference path
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from probe_world import (  # noqa: E402
    FLOOR,
    FRAME,
    SHAPES,
    SPOT,
    MotionType,
    Scenario,
    add,
    fall_speed,
    new_body,
    random_rotation,
    register_primitive,
    run,
    world_for,
)


# ------------------------------------------------------------------------------------------
# families: (stage, seed, vectorized) -> Scenario
# ------------------------------------------------------------------------------------------
def log_uniform(rng: np.random.Generator, low: float, high: float) -> float:
    return float(np.exp(rng.uniform(np.log(low), np.log(high))))


def drop(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    shape, size = str(rng.choice(list(SHAPES))), log_uniform(rng, 0.01, 2.0)
    (x, z), height = SPOT[stage], size + rng.uniform(0.05, 1.0)
    body = new_body(world, templates, shape, size, [x, FLOOR[stage] + height, z], rng)
    limit = 1.05 * fall_speed(height) + 0.3
    return Scenario(f"{shape} {size:.3f} m", stage, world, [body], limit)


def thin(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    size, speed, (x, z) = float(rng.uniform(0.05, 1.0)), rng.uniform(0, 30), SPOT[stage]
    position = [x, FLOOR[stage] + 0.6, z]
    slab = new_body(world, templates, "cube", size, position, rng, thickness=0.001)
    direction = np.array([rng.uniform(-0.3, 0.3), -1.0, rng.uniform(-0.3, 0.3)])
    slab.linear_velocity = list(speed * direction / np.linalg.norm(direction))
    limit = 1.05 * fall_speed(0.6, speed) + 0.3
    return Scenario(f"1 mm slab {size:.2f} m at {speed:.0f} m/s", stage, world, [slab], limit)


def throw(stage: str, rng, vectorized: bool, at_wall: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    shape, size = str(rng.choice(list(SHAPES))), log_uniform(rng, 0.01, 0.5)
    speed = rng.uniform(5, 30)
    if at_wall:
        start, angle = [2.0, -0.5, -0.5], rng.uniform(0, 2 * np.pi)
        direction = np.array([np.cos(angle), rng.uniform(-0.4, 0.2), np.sin(angle)])
    else:
        (x, z), restitution = SPOT[stage], float(rng.uniform(0, 0.9))
        start = [x, FLOOR[stage] + size + 0.3, z]
        direction = np.array([rng.uniform(-1, 1), -1.0, rng.uniform(-1, 1)])
    body = new_body(world, templates, shape, size, start, rng)
    if not at_wall:
        body.restitution_coefficient = restitution
        body.angular_velocity = list(5 * rng.normal(size=3))
    body.linear_velocity = list(speed * direction / np.linalg.norm(direction))
    limit = 1.05 * fall_speed(start[1] - FLOOR[stage], speed) + 0.3
    name = f"{shape} {size:.3f} m at {speed:.0f} m/s"
    return Scenario(name, stage, world, [body], limit, settle_frames=300)


def collide(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), bodies, names, fastest = SPOT[stage], [], [], 0.0
    for side in (1, -1):
        shape, size = str(rng.choice(list(SHAPES))), log_uniform(rng, 0.02, 0.6)
        speed, mass = rng.uniform(2, 15), log_uniform(rng, 0.03, 30.0)
        position = [x + side * 0.8, FLOOR[stage] + 0.6, z]
        body = new_body(world, templates, shape, size, position, rng, mass=mass)
        body.linear_velocity = [-side * speed, rng.uniform(-1, 2), 0.0]
        bodies.append(body)
        names.append(f"{shape} {size:.2f} m {mass:.2g} kg")
        fastest = max(fastest, speed)
    # a light body may leave at up to twice the closing speed
    limit = fall_speed(1.2, 4 * fastest) + 0.5
    return Scenario(" vs ".join(names), stage, world, bodies, limit, settle_frames=300)


def mass_ratio(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), floor = SPOT[stage], FLOOR[stage]
    (lower, upper), (low_size, up_size) = rng.choice(list(SHAPES), 2), rng.uniform(0.05, 0.4, 2)
    low_mass, up_mass = (1000.0, 1.0) if rng.integers(2) else (0.1, 100.0)
    under = new_body(
        world, templates, str(lower), low_size, [x, floor + low_size / 2 + 0.01, z], rng,
        turned=False, mass=low_mass,
    )  # fmt: skip
    over_position = [x + rng.uniform(-0.02, 0.02), floor + low_size + up_size / 2 + 0.1, z]
    over = new_body(
        world, templates, str(upper), up_size, over_position, rng, turned=False, mass=up_mass
    )
    name = f"{upper} {up_size:.2f} m {up_mass:g} kg on {lower} {low_size:.2f} m {low_mass:g} kg"
    limit = 1.05 * fall_speed(low_size + up_size + 0.2) + 0.5
    return Scenario(name, stage, world, [under, over], limit, settle_frames=300)


def overlapping(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), count = SPOT[stage], int(rng.integers(2, 9))
    shape, size = str(rng.choice(list(SHAPES))), float(rng.uniform(0.05, 0.4))
    sunk, bodies = rng.uniform(0, 0.4) * size, []
    for _ in range(count):
        jitter = rng.uniform(-0.3, 0.3, 2) * size
        height = FLOOR[stage] + size / 2 - sunk + rng.uniform(0, size)
        bodies.append(
            new_body(world, templates, shape, size, [x + jitter[0], height, z + jitter[1]], rng)
        )
    limit = 2.0 + fall_speed(2 * size + 0.5) + 0.5  # pushed apart at <= 2 m/s, then a fall
    name = f"{count} x {shape} {size:.2f} m, {100 * sunk:.1f} cm in the floor"
    return Scenario(name, stage, world, bodies, limit, settle_frames=360, grace=6)


def kinematic(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), floor = SPOT[stage], FLOOR[stage]
    shape, size = str(rng.choice(list(SHAPES))), float(rng.uniform(0.03, 0.3))
    speed, by_control = rng.uniform(0.2, 3.0), bool(rng.integers(2))
    pusher = new_body(world, templates, "cube", 0.4, [x - 0.6, floor + 0.21, z], rng, turned=False)
    pusher.motion_type = MotionType.KINEMATIC
    body = new_body(world, templates, shape, size, [x, floor + 0.9 * size + 0.01, z], rng)
    if by_control:
        pusher.velocity_control.controlling_lin_vel = True
        pusher.velocity_control.linear_velocity = [speed, 0.0, 0.0]

    def push(frame: int) -> None:
        if not by_control:
            pusher.translation = list(np.asarray(pusher.translation) + [speed * FRAME, 0, 0])

    how = "velocity control" if by_control else "translation"
    name = f"{shape} {size:.2f} m pushed at {speed:.1f} m/s by {how}"
    limit = 2 * speed + fall_speed(0.5) + 2.5
    frames = int(2.0 / speed * 60) + 30  # 2 m of travel
    return Scenario(name, stage, world, [body], limit, frames, push)


def teleport(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), floor = SPOT[stage], FLOOR[stage]
    shape, size = str(rng.choice(list(SHAPES))), float(rng.uniform(0.05, 0.5))
    depth, into_body = rng.uniform(0.1, 0.45) * size, bool(rng.integers(2))
    body = new_body(world, templates, shape, size, [x, floor + size / 2, z], rng, turned=False)
    bodies = [body]
    if into_body:
        bodies.append(
            new_body(world, templates, "cube", 0.3, [x + 1, floor + 0.15, z], rng, turned=False)
        )
    for _ in range(60):
        world.step_physics(FRAME)
    if into_body:
        body.translation = [x + 1 + rng.uniform(-0.05, 0.05), floor + 0.3 + size / 2 - depth, z]
    else:
        body.translation = [x, floor + size / 2 - depth, z]
    name = f"{shape} {size:.2f} m, {100 * depth:.1f} cm into the {'cube' if into_body else 'floor'}"
    limit = 2.0 + fall_speed(size + 0.3) + 0.5
    return Scenario(name, stage, world, bodies, limit, settle_frames=300, grace=6)


def properties(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), floor = SPOT[stage], FLOOR[stage]
    shape, size = str(rng.choice(list(SHAPES))), float(rng.uniform(0.05, 0.4))
    body = new_body(world, templates, shape, size, [x, floor + size + 0.3, z], rng)
    position = [x, floor + 2 * size + 0.6, z]
    cube = new_body(world, templates, "cube", 0.1, position, rng, turned=False)
    scenario = Scenario(
        f"{shape} {size:.2f} m under a cube", stage, world, [body, cube],
        1.05 * fall_speed(2 * size + 0.7) + 0.5, 240,
    )  # fmt: skip

    def change(frame: int) -> None:
        if frame % 30 != 15:
            return
        kind, target = int(rng.integers(3)), scenario.bodies[int(rng.integers(2))]
        if kind == 0:
            target.mass = log_uniform(rng, 0.01, 1000.0)
            scenario.name += f"; frame {frame}: body {target.object_id} mass {target.mass:.3g}"
        elif kind == 1:
            target.friction_coefficient = float(rng.uniform(0, 2))
        else:
            target.restitution_coefficient = float(rng.uniform(0, 1))

    scenario.drive = change
    return scenario


def removal(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), floor, bodies = SPOT[stage], FLOOR[stage], []
    for level in range(4):
        shape = str(rng.choice(["cube", "cylinder"]))
        position = [x, floor + 0.1 + 0.201 * level, z]
        bodies.append(new_body(world, templates, shape, 0.2, position, rng, turned=False))
    victim = bodies[int(rng.integers(3))]

    def remove(frame: int) -> None:
        if frame == 89:
            world.rigid_object_manager.remove_object_by_id(victim.object_id)

    name = f"stack of 4, level {bodies.index(victim)} removed at rest"
    return Scenario(name, stage, world, bodies, fall_speed(1.0) + 0.5, 90, remove)


def nonuniform(stage: str, rng, vectorized: bool) -> Scenario:
    world, templates = world_for(stage, vectorized)
    (x, z), shape = SPOT[stage], str(rng.choice(list(SHAPES)))
    scale = np.exp(rng.uniform(np.log(0.005), np.log(1.0), 3))
    handle = register_primitive(templates, SHAPES[shape], half=tuple(scale), handle=f"{scale}")
    height = 2.2 * scale.max() + 0.2
    body = add(world, templates, handle, [x, FLOOR[stage] + height, z])
    body.rotation = random_rotation(rng)
    name = f"{shape} scaled {np.round(scale, 3).tolist()}"
    return Scenario(name, stage, world, [body], 1.05 * fall_speed(height) + 0.3, settle_frames=300)


FAMILIES: dict[str, Callable[..., Scenario]] = {
    "drop": drop,
    "thin": thin,
    "throw-floor": lambda stage, rng, vectorized: throw(stage, rng, vectorized, False),
    "throw-wall": lambda stage, rng, vectorized: throw("apartment", rng, vectorized, True),
    "collide": collide,
    "mass": mass_ratio,
    "overlap": overlapping,
    "kinematic": kinematic,
    "teleport": teleport,
    "props": properties,
    "remove": removal,
    "nonuniform": nonuniform,
}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds per family and stage")
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--stages", default="box,plane,apartment")
    parser.add_argument("--reference", action="store_true", help="the plain reference path")
    args = parser.parse_args()
    passed = total = 0
    print(f"{'family':12s} {'stage':10s} {'seed':>4s}  result  deepest  fastest  scenario")
    for family in args.families.split(","):
        stages = ["apartment"] if family == "throw-wall" else args.stages.split(",")
        for stage in stages:
            for seed in range(args.first_seed, args.first_seed + args.seeds):
                start = time.perf_counter()
                rng = np.random.default_rng(seed)
                scenario = run(FAMILIES[family](stage, rng, not args.reference))
                ok = not scenario.problems
                passed, total = passed + ok, total + 1
                print(
                    f"{family:12s} {stage:10s} {seed:4d}  {'PASS' if ok else 'FAIL':6s} "
                    f"{100 * scenario.deepest:5.2f} cm {scenario.fastest:5.1f} m/s  "
                    f"{scenario.name} ({time.perf_counter() - start:.1f} s)",
                    flush=True,
                )
                for problem in scenario.problems:
                    print(f"{'':36s}{problem}")
    print(f"{passed} of {total} scenarios passed")
    return 0 if passed == total else 1


if __name__ == "__main__":
    sys.exit(main())
