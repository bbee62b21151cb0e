"""A DYNAMIC cube under velocity control, driven into a wall: the contacts win.

Habitat-sim's ``BulletPhysicsManager::stepPhysics`` sets a controlled DYNAMIC body's
velocities once, before the Bullet step; the step's contact solve then acts on them, so a
body driven into a wall stops at the wall's surface whatever the commanded speed. Here a
0.2 m cube on a floor is commanded at 1 m/s (world frame, or its local frame turned 90
degrees about +Y, and with a spin about +Y) into a wall at ``x = 0.5`` for two seconds, on
the batched and the reference path: the wall holds it (the velocity into the wall the steps
leave is small, the cube stays put, no vertex 4 cm in), checked against a mutation that
sets the commanded velocity after the solve (1 m/s left, 5.1 cm in). The 2 cm bound of the
soak is an xfail: the stage manifold's slot choice lets a corner 2.4 to 3.4 cm in.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.core.quaternions import quat_to_matrix
from engine.scene.assets import MeshData

WALL_X = 0.5
HALF = 0.1  # the cube's half side, m
SPEED = 1.0  # m/s, the soak's largest commanded speed
TOLERANCE = 0.02  # m, the soak's sink tolerance
SECONDS = 2.0


def wall_mesh() -> MeshData:
    """A wall plane at ``x = WALL_X`` facing -X (toward the cube)."""
    vertices = np.array(
        [[WALL_X, -1, -2], [WALL_X, 2, -2], [WALL_X, 2, 2], [WALL_X, -1, 2]], dtype=float
    )
    return MeshData(vertices=vertices, faces=np.array([[0, 1, 2], [0, 2, 3]]))


def driven_cube(vectorized: bool, local: bool, spin: bool):
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([floor_mesh(), wall_mesh()], StageAttributes())
    cube = add(world, templates, register_primitive(templates, half=(HALF,) * 3), [0, HALF, 0])
    control = cube.velocity_control
    control.controlling_lin_vel = True
    if local:  # local +Z is world +X once turned 90 degrees about +Y
        cube.rotation = mn.Quaternion.rotation(mn.Deg(90.0), [0.0, 1.0, 0.0])
        control.lin_vel_is_local = True
        control.linear_velocity = [0.0, 0.0, SPEED]
    else:
        control.linear_velocity = [SPEED, 0.0, 0.0]
    if spin:
        control.controlling_ang_vel = True
        control.angular_velocity = [0.0, 1.0, 0.0]
    return world, cube


def hull_extremes(world, index: int) -> tuple[float, float]:
    """``(largest x, smallest y)`` of the body's hull vertices in the world frame."""
    b = world.bodies
    points = np.concatenate([shape.hull_vertices for shape in b.shapes[index]])
    rotation = quat_to_matrix(b.body_rotation[index : index + 1])[0]
    world_points = points @ rotation.T + b.body_position[index]
    return float(world_points[:, 0].max()), float(world_points[:, 1].min())


def drive(vectorized: bool, local: bool, spin: bool) -> dict[str, float]:
    """Two seconds of driving: the deepest hull vertex into the wall and the floor (m), the
    center's travel along x over the last second (m) and whether the cube reached the wall."""
    world, cube = driven_cube(vectorized, local, spin)
    index = cube.object_id
    into_wall, into_floor, reached, held_at = 0.0, 0.0, False, 0.0
    pressing = []  # the velocity into the wall each call leaves, over the last second
    steps = int(SECONDS * 60)
    for step in range(steps):
        world.step_physics(1.0 / 60.0)
        right, bottom = hull_extremes(world, index)
        into_wall = max(into_wall, right - WALL_X)
        into_floor = max(into_floor, -bottom)
        reached |= right > WALL_X - 0.01
        if step == steps // 2:
            held_at = float(world.bodies.body_position[index][0])
        if step >= steps // 2:
            pressing.append(float(world.bodies.body_linear_velocity[index][0]))
    travel = float(world.bodies.body_position[index][0]) - held_at
    return {
        "wall": into_wall,
        "floor": into_floor,
        "travel": travel,
        "reached": reached,
        "pressing": float(np.mean(pressing)),
    }


PATHS = pytest.mark.parametrize("vectorized", [True, False], ids=["batched", "reference"])
DRIVES = pytest.mark.parametrize(
    ("local", "spin"),
    [(False, False), (True, False), (False, True)],
    ids=["world", "local", "spin"],
)


@PATHS
@DRIVES
def test_a_cube_driven_into_a_wall_is_held_by_it(vectorized, local, spin):
    """The control's 1 m/s, set again before every call, never wins over the wall: over the
    last second the velocity into the wall the steps leave averages under 0.2 m/s (under
    0.09 measured; a control applied after the solve leaves 1 m/s), the center moves less
    than 2 cm, and no vertex goes 4 cm into the wall (3.4 cm measured; 5.1 cm when the
    control overrides the solve)."""
    result = drive(vectorized, local, spin)
    assert result["reached"], "the cube never reached the wall"
    assert result["pressing"] < 0.2 * SPEED, result
    assert abs(result["travel"]) < TOLERANCE, result
    assert result["wall"] < 0.04, result
    assert result["floor"] < TOLERANCE, result


@PATHS
@DRIVES
@pytest.mark.xfail(
    strict=True,
    reason="the cube-stage manifold's four slots are shared by the floor and the wall: on "
    "impact it keeps three floor points and one wall corner, the wall's impulse at that one "
    "corner spins the cube about +Y and the other corners go 2.4 to 3.4 cm into the wall "
    "(stage manifold slot choice, not the velocity control)",
)
def test_a_cube_driven_into_a_wall_stays_within_2cm_of_its_surface(vectorized, local, spin):
    result = drive(vectorized, local, spin)
    assert result["wall"] < TOLERANCE, f"{result['wall'] * 100:.2f} cm into the wall"
