"""Small builders shared by the physics tests: a world with a floor, templates, boxes."""

from __future__ import annotations

import numpy as np

from engine.attributes import PhysicsManagerAttributes, StageAttributes
from engine.attributes_managers import ObjectAttributesManager
from engine.physics import PhysicsWorld
from engine.scene.assets import MeshData
from engine.scene.graph import SceneNode


def floor_mesh(half: float = 10.0, height: float = 0.0, slope_deg: float = 0.0) -> MeshData:
    """A square floor (two triangles, CCW seen from +Y), optionally tilted about Z."""
    v = np.array([[-half, 0, -half], [half, 0, -half], [half, 0, half], [-half, 0, half]], float)
    angle = np.radians(slope_deg)
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    v = v @ rot.T + [0, height, 0]
    return MeshData(vertices=v, faces=np.array([[0, 2, 1], [0, 3, 2]], dtype=np.int64))


def make_world(
    floor: bool = True,
    gravity=(0.0, -9.8, 0.0),
    timestep: float = 0.008,
    stage_friction: float = 0.4,
    stage_restitution: float = 0.1,
    slope_deg=0.0,
    floor_half: float = 10.0,
):
    """A PhysicsWorld with an optional floor stage; returns (world, template_manager)."""
    physics = PhysicsManagerAttributes()
    physics.timestep = timestep
    physics.gravity = list(gravity)
    templates = ObjectAttributesManager()
    world = PhysicsWorld(physics, SceneNode(), templates)
    if floor:
        stage = StageAttributes()
        stage.friction_coefficient = stage_friction
        stage.restitution_coefficient = stage_restitution
        world.set_stage([floor_mesh(floor_half, slope_deg=slope_deg)], stage)
    return world, templates


def register_primitive(
    templates,
    primitive: str = "cubeSolid",
    half=(0.1, 0.1, 0.1),
    handle: str | None = None,
    **fields,
) -> str:
    """Register a template of a scaled Magnum primitive (cube half extents = scale)."""
    handle = handle or f"{primitive}_{'_'.join(f'{h:g}' for h in half)}_{len(fields)}"
    template = templates.create_new_template(handle)
    template.render_asset_handle = primitive
    template.collision_asset_handle = primitive
    template.scale = list(half)
    for name, value in fields.items():
        setattr(template, name, value)
    templates.register_template(template, handle)
    return handle


def add(world, templates, handle, position, **props):
    obj = world.rigid_object_manager.add_object_by_template_handle(handle)
    obj.translation = position
    for name, value in props.items():
        setattr(obj, name, value)
    return obj


def run(world, seconds: float, dt: float = 1.0 / 60.0) -> None:
    for _ in range(int(round(seconds / dt))):
        world.step_physics(dt)
