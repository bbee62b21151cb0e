"""Fast-spinning bodies against thin stage walls: the sweep follows each vertex's path
(translation and turn) and never lets the body's center cross a wall.

The walls soak (``benchmarks/soak.py --walls``) lost a 25 cm cone through a 10 cm wall: it
lay on the floor against the wall while forces and pushes spun it to 35-38 rad/s, its
center went into the wall and out at the far side. These tests build that in a box scene
(a floor and a wall of two facing triangle pairs and a top) and check every frame on both
solver paths.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.core import settings
from engine.physics.core.quaternions import quat_to_matrix, rotation_quat
from engine.physics.solver.sweep import path_points
from engine.scene.assets import MeshData

FRAME = 1.0 / 60.0
#: the soak's cone template: Habitat's cone primitive scaled to a 10 cm radius, 25 cm long
CONE = "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false_useTangents_false_capEnd_true"
NEAR, FAR, TOP = -1.0, -1.1, 1.0  # the wall's room-side face, far face and top (m)


def wall_mesh(half_length: float = 3.0) -> MeshData:
    """A 10 cm thick wall from z = -1.0 (facing +z, the room) to z = -1.1 (facing -z),
    1 m high: two facing triangle pairs and its top, wound to face out."""
    x = half_length
    corners = [
        [-x, 0, NEAR], [x, 0, NEAR], [x, TOP, NEAR], [-x, TOP, NEAR],
        [-x, 0, FAR], [x, 0, FAR], [x, TOP, FAR], [-x, TOP, FAR],
    ]  # fmt: skip
    faces = [[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6], [3, 2, 6], [3, 6, 7]]
    return MeshData(vertices=np.array(corners, float), faces=np.array(faces, dtype=np.int64))


def test_wall_mesh_faces_out():
    """The helper's winding: the room-side face +z, the far face -z, the top +y."""
    mesh = wall_mesh()
    v = mesh.vertices[mesh.faces]
    normal = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    expected = [[0, 0, 1]] * 2 + [[0, 0, -1]] * 2 + [[0, 1, 0]] * 2
    np.testing.assert_allclose(normal, expected, atol=1e-12)


def wall_world(vectorized: bool):
    world, templates = make_world(floor=False)
    world.set_stage([floor_mesh(10.0), wall_mesh()], StageAttributes())
    world.settings.use_vectorized = vectorized
    handle = register_primitive(templates, CONE, half=(0.1, 0.1, 0.1))
    return world, templates, handle


def lowest_vertex_z(world, index: int) -> float:
    """The least world z of body ``index``'s hull vertices, m (how far it is into the wall)."""
    b = world.bodies
    vertices = np.concatenate([shape.hull_vertices for shape in b.shapes[index]])
    rotation = quat_to_matrix(b.body_rotation[index])
    return float((vertices @ rotation.T)[:, 2].min() + b.body_position[index][2])


@pytest.mark.parametrize("seed", [8, 46, 47, 53])
@pytest.mark.parametrize("vectorized", [True, False])
def test_cone_spun_against_a_thin_wall_never_gets_its_center_into_it(vectorized, seed):
    """The cone dropped beside the wall at a random orientation settles for a second, then
    is spun to 37 rad/s about a random axis and struck toward the wall at 3 m/s; every 5
    frames, as the soak's pushes do, a 120 m/s^2 force drives it at the wall and its spin is
    restored to 37 rad/s. Before the path sweep its center crossed the wall's face in these
    four seeds (on both paths; one left through the far side and ended 2 m behind it): its
    tip, held only by a floor contact in the corner, crept 1-1.5 cm a step into the wall
    until the center followed. Now a center that would cross the face is pushed back out
    with the body's depth behind it."""
    rng = np.random.default_rng(seed)
    world, templates, handle = wall_world(vectorized)
    cone = add(world, templates, handle, [0.0, 0.1, NEAR + 0.13])
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    cone.rotation = mn.Quaternion(mn.Vector3(*q[:3]), q[3])
    for _ in range(60):
        world.step_physics(FRAME)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    spin = 37.0 * axis
    cone.angular_velocity = list(spin)
    cone.linear_velocity = [rng.uniform(-1.0, 1.0), 0.0, -3.0]
    centers, deepest = [], []
    for frame in range(60):
        if frame % 5 == 0:
            cone.apply_force([0.0, 0.0, -120.0 * cone.mass], [0.0, 0.0, 0.0])
            if np.linalg.norm(np.asarray(cone.angular_velocity)) < 0.8 * 37.0:
                cone.angular_velocity = list(spin)
        world.step_physics(FRAME)
        centers.append(np.asarray(cone.translation))
        deepest.append(NEAR - lowest_vertex_z(world, cone.object_id))
    centers = np.array(centers)
    assert centers[:, 2].min() > NEAR  # the center never into the wall
    assert centers[-1][1] > 0.0  # and on the floor in the room at the end
    # the sweep pushes the whole cone out of the wall when its center would cross: never
    # half of it (12.5 cm, the center's depth) behind the face
    assert max(deepest) < 0.125


def test_path_points_follow_the_arc_of_a_turn_at_a_constant_rate():
    """A vertex 20 cm from the center of a body turning 0.8 rad (100 rad/s over a 1/125 s
    step) while moving 5 cm: 4 chords, every cut on the circle about the moving center at
    the fraction of the turn, the ends at the two poses exactly."""
    vertex = np.array([[0.2, 0.0, 0.0]])
    start = (np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]))
    end_rotation = rotation_quat(np.array([0.0, 0.8, 0.0]))
    end = (np.array([0.05, 0.0, 0.0]), end_rotation)
    points = path_points(vertex, start, end)[:, 0]
    assert len(points) == int(np.ceil(0.8 / settings.CCD_ARC_ANGLE)) + 1 == 5
    t = np.linspace(0.0, 1.0, 5)
    angle = 0.8 * t  # about +y: x' = x cos a, z' = -x sin a
    expected = np.stack([0.2 * np.cos(angle) + 0.05 * t, 0 * t, -0.2 * np.sin(angle)], 1)
    np.testing.assert_allclose(points, expected, atol=1e-12)
    np.testing.assert_allclose(points[-1], quat_to_matrix(end_rotation) @ vertex[0] + end[0])
