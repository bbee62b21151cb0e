"""The world side of ``physics_probe.py``: the three stages, bodies made through the
Habitat-style object API, a :class:`Scenario` and the checks run after every frame (finite
state, lowest point and center against the floor, speed within the fall and the throw) and
after settling (asleep, resting overlaps by fcl). ``physics_probe.py`` holds the scenario
families and the command line.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import fcl
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "physics"))
sys.path.insert(0, str(ROOT / "benchmarks"))

from helpers import add, make_world, register_primitive  # noqa: E402

from engine import mn  # noqa: E402
from engine.attributes import StageAttributes  # noqa: E402
from engine.physics import MotionType  # noqa: E402
from engine.physics.core.quaternions import quat_to_matrix  # noqa: E402
from engine.scene.assets import MeshData, load_meshes  # noqa: E402

FRAME = 1.0 / 60.0
GRAVITY = 9.8
DEPTH_LIMIT = 0.02  # m, deepest allowed point below the floor, and overlap at rest
SHAPES = {
    "cube": "cubeSolid",
    "sphere": "icosphereSolid_subdivs_1",
    "cylinder": "cylinderSolid_rings_1_segments_12_halfLen_1_useTexCoords_false"
    "_useTangents_false_capEnds_true",
    "cone": "coneSolid_segments_12_halfLen_1_rings_1_useTexCoords_false"
    "_useTangents_false_capEnd_true",
    "capsule": "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
    "_useTexCoords_false_useTangents_false",
}
ROUND = ("sphere", "capsule", "cylinder", "cone")  # kinds that may roll on for ever
FLOOR = {"box": 0.0, "plane": 0.0, "apartment": -1.45}
SPOT = {"box": (0.0, 0.0), "plane": (0.0, 0.0), "apartment": (1.5, 0.4)}  # clear floor
_MESHES: dict[str, list] = {}


# ------------------------------------------------------------------------------------------
# worlds and bodies
# ------------------------------------------------------------------------------------------
def stage_meshes(stage: str) -> list:
    """The stage's meshes (loaded once)."""
    if stage not in _MESHES:
        if stage == "apartment":
            from engine.demo import demo_data_path

            path = demo_data_path() / "scene_datasets" / "demo" / "apartment.glb"
            _MESHES[stage] = load_meshes(path)
        else:
            from physics_scenes import stage_triangles

            vertices, faces = stage_triangles(stage)
            _MESHES[stage] = [MeshData(vertices=vertices, faces=faces)]
    return _MESHES[stage]


def world_for(stage: str, vectorized: bool):
    """``(world, templates)`` on a stage: ``box`` (a 400 m floor: nothing falls off its
    edge), ``plane`` or ``apartment``."""
    if stage == "box":
        world, templates = make_world(floor_half=200.0)
    else:
        world, templates = make_world(floor=False)
        world.set_stage(stage_meshes(stage), StageAttributes())
    world.settings.use_vectorized = vectorized
    return world, templates


def template_scale(shape: str, size: float, thickness: float | None) -> tuple:
    """Template scale of a body ``size`` m across (``thickness``: a slab's height)."""
    half = size / 2
    if shape == "capsule":  # radius r, half height r + 0.75 r
        return (half / 1.75,) * 3
    if thickness is not None:
        return (half, thickness / 2, half)
    return (half,) * 3


def random_rotation(rng: np.random.Generator) -> mn.Quaternion:
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    return mn.Quaternion(mn.Vector3(*q[:3]), float(q[3]))


def new_body(world, templates, shape: str, size: float, position, rng, **options):
    """Add a primitive ``size`` m across at ``position``. Options: ``thickness`` (a slab),
    ``turned`` (random orientation, default True), ``mass`` (template mass, kg), any other
    object property (set after creation)."""
    thickness = options.pop("thickness", None)
    turned = options.pop("turned", True)
    fields = {"mass": options.pop("mass")} if "mass" in options else {}
    handle = register_primitive(
        templates,
        SHAPES[shape],
        half=template_scale(shape, size, thickness),
        handle=f"{shape}_{size:.5f}_{thickness}_{fields}",
        **fields,
    )
    body = add(world, templates, handle, list(position))
    for name, value in options.items():
        setattr(body, name, value)
    if turned:
        body.rotation = random_rotation(rng)
    return body


def fall_speed(height: float, throw: float = 0.0) -> float:
    """m/s, speed after a throw at ``throw`` m/s and a fall of ``height`` m."""
    return float(np.sqrt(throw**2 + 2 * GRAVITY * max(height, 0.0)))


# ------------------------------------------------------------------------------------------
# a scenario and its checks
# ------------------------------------------------------------------------------------------
@dataclass
class Scenario:
    """One probe run: its bodies, the speed they may reach, the frames to run while a
    ``drive`` callback (frame index -> None) acts, then the frames to settle."""

    name: str
    stage: str
    world: Any
    bodies: list = field(default_factory=list)
    speed_limit: float = 0.0
    drive_frames: int = 0
    drive: Callable[[int], None] | None = None
    settle_frames: int = 240
    grace: int = 0  # settle frames before the depth check (bodies created inside)
    problems: list = field(default_factory=list)
    deepest: float = 0.0
    fastest: float = 0.0

    def fail(self, message: str) -> None:
        if len(self.problems) < 4:
            self.problems.append(message)


def lowest_point(world, index: int) -> float:
    """World y of body ``index``'s lowest hull vertex, m."""
    b = world.bodies
    vertices = np.concatenate([shape.hull_vertices for shape in b.shapes[index]])
    rotation = quat_to_matrix(b.body_rotation[index][None])[0]
    return float((vertices @ rotation.T)[:, 1].min() + b.body_position[index][1])


def dynamic_bodies(scenario: Scenario) -> list[int]:
    b = scenario.world.bodies
    return [
        o.object_id
        for o in scenario.bodies
        if o.is_alive and b.body_motion_type[o.object_id] == int(MotionType.DYNAMIC)
    ]


def check_frame(scenario: Scenario, label: str, depth_checked: bool) -> None:
    """Finite state, depth below the floor, center above it, speed within the limit."""
    b, floor = scenario.world.bodies, FLOOR[scenario.stage]
    for i in dynamic_bodies(scenario):
        state = (b.body_position[i], b.body_linear_velocity[i], b.body_angular_velocity[i])
        if not all(np.all(np.isfinite(x)) for x in state):
            scenario.fail(f"{label} body {i}: non-finite state")
            continue
        depth = floor - lowest_point(scenario.world, i)
        if depth_checked:
            scenario.deepest = max(scenario.deepest, depth)
            if depth > DEPTH_LIMIT:
                scenario.fail(f"{label} body {i}: lowest point {100 * depth:.1f} cm in the floor")
        if b.body_position[i][1] < floor - 0.002:
            scenario.fail(f"{label} body {i}: center below the floor")
        speed = float(np.linalg.norm(b.body_linear_velocity[i]))
        scenario.fastest = max(scenario.fastest, speed)
        if speed > scenario.speed_limit:
            scenario.fail(f"{label} body {i}: {speed:.2f} m/s > {scenario.speed_limit:.2f}")


def collision_objects(world, index: int) -> list:
    """fcl objects of body ``index``'s shapes at its pose."""
    b = world.bodies
    rotation = quat_to_matrix(b.body_rotation[index][None])[0]
    objects = []
    for shape in b.shapes[index]:
        pose = shape.body_from_shape
        transform = fcl.Transform(
            rotation @ pose[:3, :3], b.body_position[index] + rotation @ pose[:3, 3]
        )
        objects.append(fcl.CollisionObject(shape.geometry, transform))
    return objects


def overlap(world, i: int, j: int) -> float:
    """Deepest fcl penetration between bodies ``i`` and ``j``, m (0 when apart)."""
    deepest = 0.0
    for a in collision_objects(world, i):
        for c in collision_objects(world, j):
            result = fcl.CollisionResult()
            request = fcl.CollisionRequest(num_max_contacts=8, enable_contact=True)
            if fcl.collide(a, c, request, result):
                deepest = max([deepest] + [float(x.penetration_depth) for x in result.contacts])
    return deepest


def check_rest(scenario: Scenario) -> None:
    """Non-round bodies asleep; no two bodies overlapping by more than DEPTH_LIMIT."""
    b, world = scenario.world.bodies, scenario.world
    ids = dynamic_bodies(scenario)
    for i in ids:
        if b.body_awake[i] and b.shapes[i][0].kind.value not in ROUND:
            speed = np.linalg.norm(b.body_linear_velocity[i])
            scenario.fail(f"body {i} still awake at {speed:.3f} m/s")
    for k, i in enumerate(ids):
        for j in ids[k + 1 :]:
            if (depth := overlap(world, i, j)) > DEPTH_LIMIT:
                scenario.fail(f"bodies {i}, {j} overlap by {100 * depth:.1f} cm at rest")


def run(scenario: Scenario) -> Scenario:
    """Drive, settle and check a scenario (an exception is a failure too)."""
    try:
        for frame in range(scenario.drive_frames):
            if scenario.drive is not None:
                scenario.drive(frame)
            scenario.world.step_physics(FRAME)
            check_frame(scenario, f"frame {frame}", True)
        for frame in range(scenario.settle_frames):
            scenario.world.step_physics(FRAME)
            label = f"frame {scenario.drive_frames + frame}"
            check_frame(scenario, label, frame >= scenario.grace)
        check_rest(scenario)
    except Exception as error:  # noqa: BLE001 - the probe reports it as a failure
        scenario.fail(f"{type(error).__name__}: {error}")
    return scenario
