"""Scenes and runners of ``bench_physics.py``: the same cube scenes in rigidsim and pybullet.

Scene builders return drop positions and unit quaternions ``[x, y, z, w]`` of 0.2 m, 1 kg
cubes; :func:`run_rigidsim` and :func:`run_pybullet` step them at the same 0.008 s step
through the same 1/60 s frame accumulator and return wall and CPU time plus what the
report measures (deepest true overlaps, energy, fastest body, stage timers, when every
body fell asleep). Both engines collide with the same stage triangles
(:func:`stage_triangles`): ``box`` (a 40 x 40 m floor of two triangles, y = 0), ``plane``
(Habitat's test asset ``plane.glb``: 2,048 triangles, 200 x 200 m, y = 0) or ``apartment``
(the demo apartment, 1,562 triangles, floor at y = -1.45); pybullet gets them as a static
concave triangle mesh (``GEOM_FORCE_CONCAVE_TRIMESH``).

pybullet's bodies are btRigidBody, the body Habitat-sim's ``BulletRigidObject`` builds:
``createMultiBody(..., useMaximalCoordinates=True)`` (without it pybullet builds a Featherstone
btMultiBody, about 2x slower per step on these scenes). Habitat leaves a btRigidBody's
activation at Bullet's defaults (it sleeps after 2 s below 0.8 m/s and 1 rad/s); pybullet
forbids sleeping unless a body is created with ``URDF_ENABLE_SLEEPING``, so the sleeping scenes
pass that flag, and the scenes with sleeping off switch it off in both engines.
``multibody=True`` builds the btMultiBody instead (for a column labelled so).
"""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "physics"))

from helpers import add, make_world, register_primitive  # noqa: E402

from engine import mn  # noqa: E402
from engine.attributes import StageAttributes  # noqa: E402
from engine.physics.core import settings as physics_settings  # noqa: E402
from engine.physics.core.quaternions import quat_to_matrix  # noqa: E402
from engine.scene.assets import MeshData, load_meshes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PLANE_GLB = ROOT / "tests" / "habitat_data" / "test_assets" / "scenes" / "plane.glb"
APARTMENT_FLOOR = -1.45  # m, the demo apartment's floor height
TABLE_TOP = -1.05  # m, its coffee table's top
FRAME = 1.0 / 60.0
STEP = 0.008
HALF = 0.1
GRAVITY = 9.8


# ------------------------------------------------------------------------------------------
# scenes
# ------------------------------------------------------------------------------------------
def column_positions(n: int, height: float = 5.0, seed: int = 0):
    """A loose column of ``n`` cubes: 12 layers (fewer when n < 12) from 0.3 m up to
    ``height``, each layer a jittered square grid of 0.36 m pitch (more than a cube's
    0.35 m diagonal, so no two cubes start overlapping); random orientations."""
    rng = np.random.default_rng(seed)
    layers = min(n, 12)
    per_layer = int(np.ceil(n / layers))
    side = int(np.ceil(np.sqrt(per_layer)))
    pitch_y = (height - 0.3) / max(layers - 1, 1)
    positions, rotations = [], []
    for k in range(n):
        layer, cell = divmod(k, per_layer)
        row, col = divmod(cell, side)
        positions.append(
            [
                (col - (side - 1) / 2) * 0.36 + rng.uniform(-0.005, 0.005),
                0.3 + pitch_y * layer,
                (row - (side - 1) / 2) * 0.36 + rng.uniform(-0.005, 0.005),
            ]
        )
        q = rng.normal(size=4)
        rotations.append(q / np.linalg.norm(q))
    return positions, rotations


def pile_positions(n: int, seed: int = 0):
    """Loose grid of ``n`` drop positions and random unit quaternions [x, y, z, w]."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(min(n, 100))))
    positions, rotations = [], []
    for k in range(n):
        layer, cell = divmod(k, side * side)
        row, col = divmod(cell, side)
        positions.append(
            [
                (col - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
                0.3 + 0.3 * layer + rng.uniform(0, 0.05),
                (row - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
            ]
        )
        q = rng.normal(size=4)
        rotations.append(q / np.linalg.norm(q))
    return positions, rotations


def apartment_positions(n: int = 30, seed: int = 0):
    """``n`` cubes dropped onto the demo apartment's coffee table (x 2.25..2.85, z
    -0.4..0.5, top y = -1.05) and the clear floor beside it (around x 1.5, z 0.4): 2 x 3
    per layer over the table, 3 x 3 per layer over the floor, layers 0.3 m apart."""
    rng = np.random.default_rng(seed)
    over_table = [(x, z) for x in (2.42, 2.68) for z in (-0.2, 0.05, 0.3)]
    over_floor = [(x, z) for x in (1.2, 1.5, 1.8) for z in (0.1, 0.4, 0.7)]
    positions, rotations = [], []
    for k in range(n):
        spots, base, index = (
            (over_table, TABLE_TOP, k // 2) if k % 2 == 0 else (over_floor, APARTMENT_FLOOR, k // 2)
        )
        layer, cell = divmod(index, len(spots))
        x, z = spots[cell]
        positions.append([x, base + 0.3 + 0.3 * layer + rng.uniform(0, 0.02), z])
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


def named_scene(name: str):
    """``((positions, rotations), stage)`` of a report scene by name: ``column-N``,
    ``plane-column-N``, ``pile-N``, ``apartment-30`` (what a baseline checkout is asked to
    step, so both checkouts drop the same cubes on the same triangles)."""
    n = int(name.rsplit("-", 1)[1])
    if name.startswith("plane-column-"):
        return column_positions(n), "plane"
    if name.startswith("column-"):
        return column_positions(n), "box"
    if name.startswith("pile-"):
        return pile_positions(n), "box"
    if name.startswith("apartment-"):
        return apartment_positions(n), "apartment"
    raise ValueError(f"no scene named {name!r}")


def stage_triangles(stage: str) -> tuple[np.ndarray, np.ndarray]:
    """World-frame ``(vertices (V, 3), faces (F, 3))`` of a benchmark stage (module docstring)."""
    if stage == "box":
        from helpers import floor_mesh

        mesh = floor_mesh(20.0)
        return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces)
    if stage == "plane":
        # Habitat's plane.glb as rigidsim's Simulator places it (its stage frame: y up)
        from engine import Configuration, Simulator, SimulatorConfiguration

        sim = Simulator(Configuration(SimulatorConfiguration(scene_id=str(PLANE_GLB))))
        tris = sim.get_physics_world().bodies.shapes[0][0].ray_triangles  # (F, 3, 3) world
        sim.close()
        return tris.reshape(-1, 3).copy(), np.arange(3 * len(tris)).reshape(-1, 3)
    if stage == "apartment":
        from engine.demo import demo_data_path

        meshes = load_meshes(demo_data_path() / "scene_datasets" / "demo" / "apartment.glb")
        vertices, faces, offset = [], [], 0
        for mesh in meshes:
            vertices.append(np.asarray(mesh.vertices, dtype=np.float64))
            faces.append(np.asarray(mesh.faces) + offset)
            offset += len(mesh.vertices)
        return np.concatenate(vertices), np.concatenate(faces)
    raise KeyError(f"unknown benchmark stage {stage!r}: use 'box', 'plane' or 'apartment'")


@contextlib.contextmanager
def sleeping_disabled(disabled: bool):
    """Switch rigidsim's sleeping off (an island would need infinite rest to sleep)."""
    saved = physics_settings.TIME_TO_SLEEP
    if disabled:
        physics_settings.TIME_TO_SLEEP = float("inf")
    try:
        yield
    finally:
        physics_settings.TIME_TO_SLEEP = saved


# ------------------------------------------------------------------------------------------
# measurements
# ------------------------------------------------------------------------------------------
def floor_height(stage: str) -> float:
    """m, the floor's height in a benchmark stage."""
    return APARTMENT_FLOOR if stage == "apartment" else 0.0


def penetration(world, floor: float = 0.0) -> tuple[float, float]:
    """Deepest true overlaps of the cubes, m: ``(floor, pair)``, below the floor (y =
    ``floor``; a table top is not checked) by their lowest corner, and between touching
    cubes by the separating-axis overlap (the smallest overlap over the 15 axes of two
    boxes, Ericson 4.4.1), not the manifold's bookkept point depths."""
    b, n = world.bodies, world.bodies.count
    ids = np.arange(1, n)[b.body_alive[1:n]]
    if len(ids) == 0:
        return 0.0, 0.0
    rotation = quat_to_matrix(b.body_rotation[:n])
    half = b.body_shape_half[:n]
    center = b.body_position[:n] + np.einsum("nij,nj->ni", rotation, b.body_shape_center[:n])
    # lowest corner: y of the center minus the box's half height along world Y
    lowest = center[ids, 1] - (np.abs(rotation[ids, 1, :]) * half[ids]).sum(axis=1)
    floor, deepest = max(0.0, float(floor - lowest.min())), 0.0
    store = world.manifolds
    rows = store.rows_with_points()
    pairs = store.bodies[rows]
    pairs = pairs[pairs[:, 0] != 0]
    if len(pairs):
        a, c = pairs[:, 0], pairs[:, 1]
        axes_a, axes_c = rotation[a], rotation[c]  # box axes = matrix columns
        cross = np.cross(axes_a[:, :, :, None], axes_c[:, :, None, :], axis=1)  # (p, 3, 3, 3)
        axes = np.concatenate([axes_a, axes_c, cross.reshape(len(a), 3, 9)], axis=2)  # (p,3,15)
        length = np.linalg.norm(axes, axis=1)  # (p, 15)
        usable = length > 1e-6  # parallel edges give no axis
        axes = axes / np.maximum(length, 1e-12)[:, None, :]
        # projected radius of box k on axis L: sum_i h_i |a_i . L|
        radius_a = (np.abs(np.einsum("pij,pik->pjk", axes_a, axes)) * half[a][:, :, None]).sum(1)
        radius_c = (np.abs(np.einsum("pij,pik->pjk", axes_c, axes)) * half[c][:, :, None]).sum(1)
        distance = np.abs(np.einsum("pi,pik->pk", center[c] - center[a], axes))
        overlap = np.where(usable, radius_a + radius_c - distance, np.inf).min(axis=1)
        deepest = max(deepest, float(overlap.max()))
    return floor, deepest


def energy(world) -> float:
    """Kinetic + potential energy of the dynamic bodies, J (potential: m g y)."""
    b, n = world.bodies, world.bodies.count
    ids = np.arange(1, n)[b.body_alive[1:n]]
    m, v, w = b.body_mass[ids], b.body_linear_velocity[ids], b.body_angular_velocity[ids]
    rotation = quat_to_matrix(b.body_rotation[ids])
    w_body = np.einsum("nji,nj->ni", rotation, w)  # R^T w: body-frame angular velocity
    kinetic = 0.5 * (m * (v * v).sum(1)).sum() + 0.5 * (b.body_inertia[ids] * w_body**2).sum()
    return float(kinetic + (m * GRAVITY * b.body_position[ids, 1]).sum())


#: s, penetration and energy drift are measured from this time on (the loose piles start
#: with overlapping cubes, and falling cubes first convert potential energy)
WATCH_FROM = 1.0


def build_world(positions, rotations, stage: str, vectorized: bool = True):
    """``(world, boxes)``: rigidsim's world with the stage's triangles and the cubes."""
    world, templates = make_world(floor=False)
    vertices, faces = stage_triangles(stage)
    stage_attributes = StageAttributes()
    stage_attributes.friction_coefficient, stage_attributes.restitution_coefficient = 0.4, 0.1
    world.set_stage([MeshData(vertices=vertices, faces=faces)], stage_attributes)
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, "cubeSolid", (HALF, HALF, HALF))
    boxes = []
    for p, q in zip(positions, rotations, strict=True):
        box = add(world, templates, handle, p)
        box.rotation = mn.Quaternion.from_xyzw(q)
        boxes.append(box)
    world.timer.reset()
    return world, boxes


#: s, the window whose steps :func:`count_operations` counts (after the drop, when the
#: cubes of the columns land: the busiest part of the timed runs)
OPS_WINDOW = (1.0, 1.5)


def count_operations(positions, rotations, sleep=True, stage="box", window=OPS_WINDOW):
    """NumPy operations per fixed step (``op_counter``'s definition, the repository's own
    code counted) over the frames of ``window`` (s); returns ``(per step, OpCounter)``."""
    from op_counter import OpCounter

    with sleeping_disabled(not sleep):
        world, _ = build_world(positions, rotations, stage)
        counter = OpCounter()
        steps = 0
        for frame in range(int(round(window[1] / FRAME))):
            if frame * FRAME < window[0] - 1e-9:
                world.step_physics(FRAME)
                continue
            before = world._time
            with counter:
                world.step_physics(FRAME)
            steps += int(round((world._time - before) / STEP))
    return counter.total / max(steps, 1), counter


def run_rigidsim(
    positions, rotations, seconds, sleep=True, watch=True, vectorized=True, stage="box"
):
    """Step a scene; wall time counts ``step_physics`` only (measurements are outside)."""
    with sleeping_disabled(not sleep):
        world, boxes = build_world(positions, rotations, stage, vectorized)
        energy_start = None
        wall, cpu, settled, deepest = 0.0, 0.0, None, np.zeros(2)
        steps_before = world._time
        for frame in range(int(round(seconds / FRAME))):
            start, start_cpu = time.perf_counter(), time.process_time()
            world.step_physics(FRAME)
            wall += time.perf_counter() - start
            cpu += time.process_time() - start_cpu
            if (frame + 1) * FRAME >= WATCH_FROM - 1e-9:
                if energy_start is None:
                    energy_start = energy(world)
                if watch:
                    deepest = np.maximum(deepest, penetration(world, floor_height(stage)))
            if settled is None and not world.bodies.body_awake[1 : world.bodies.count].any():
                settled = ((frame + 1) * FRAME, wall)
        steps = int(round((world._time - steps_before) / STEP))
        b, n = world.bodies, world.bodies.count
        speed = np.linalg.norm(b.body_linear_velocity[1:n], axis=1).max(initial=0.0)
        return {
            "wall": wall,
            "cpu": cpu,
            "steps": steps,
            "settled": settled,
            "final": np.array([np.asarray(box.translation) for box in boxes]),
            "asleep": sum(not box.awake for box in boxes),
            "profile": dict(world.profile),
            "deepest": deepest,
            "resting_depth": np.array(penetration(world, floor_height(stage))),
            "energy_change": energy(world) - (energy_start or energy(world)),
            "touching_pairs": len(world.manifolds.rows_with_points()),
            "end_speed": float(speed),
        }


def run_pybullet(positions, rotations, seconds, sleep=True, stage="box", multibody=False):
    """The scene in pybullet, the stage's triangles as a static concave mesh: btRigidBody
    bodies as Habitat uses (``multibody=True``: btMultiBody, not what Habitat uses), sleeping
    as Habitat leaves it when ``sleep`` (module docstring); ``settled``: simulated seconds
    until every velocity is exactly zero (Bullet zeroes the velocities of sleeping islands),
    checked outside the timing."""
    import pybullet as p

    client = p.connect(p.DIRECT)
    p.setGravity(0, -GRAVITY, 0, physicsClientId=client)
    p.setTimeStep(STEP, physicsClientId=client)
    vertices, faces = stage_triangles(stage)
    floor = p.createCollisionShape(
        p.GEOM_MESH,
        vertices=vertices.tolist(),
        indices=faces.reshape(-1).tolist(),
        flags=p.GEOM_FORCE_CONCAVE_TRIMESH,
        physicsClientId=client,
    )
    maximal = not multibody
    p.createMultiBody(0, floor, useMaximalCoordinates=maximal, physicsClientId=client)
    box = p.createCollisionShape(p.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=client)
    bodies = [
        p.createMultiBody(
            1.0,
            box,
            basePosition=pos,
            baseOrientation=list(q),
            useMaximalCoordinates=maximal,
            flags=p.URDF_ENABLE_SLEEPING if sleep else 0,
            physicsClientId=client,
        )
        for pos, q in zip(positions, rotations, strict=True)
    ]
    if not sleep:
        for body in bodies:
            p.changeDynamics(
                body,
                -1,
                activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                physicsClientId=client,
            )
    steps, accumulated, wall, cpu, settled = 0, 0.0, 0.0, 0.0, None
    for frame in range(int(round(seconds / FRAME))):  # the same accumulator as step_physics
        start, start_cpu = time.perf_counter(), time.process_time()
        accumulated += FRAME
        while accumulated >= STEP:
            p.stepSimulation(physicsClientId=client)
            accumulated -= STEP
            steps += 1
        wall += time.perf_counter() - start
        cpu += time.process_time() - start_cpu
        if sleep and settled is None and frame % 6 == 5:  # every 0.1 s
            moving = any(
                any(p.getBaseVelocity(body, physicsClientId=client)[k])
                for body in bodies
                for k in (0, 1)
            )
            settled = None if moving else (frame + 1) * FRAME
    final = np.array(
        [p.getBasePositionAndOrientation(b, physicsClientId=client)[0] for b in bodies]
    )
    p.disconnect(client)
    return {"wall": wall, "cpu": cpu, "steps": steps, "final": final, "settled": settled}


def have_pybullet() -> bool:
    try:
        import pybullet  # noqa: F401
    except ImportError:
        return False
    return True
