"""A capsule falling across the edge of a platform lands on it, not inside it.

A 10 cm capsule (the soak's: radius 0.1 m, axis half length 0.075 m) lies nearly flat
across the edge of a closed box platform (x >= 0, top y = 0) standing on a lower floor
(y = -0.15) and falls onto the edge at 3.7 m/s, its center 1.3 cm past the platform's side
face, above the top (the state of the walls soak that recorded a capsule 14.5 cm inside
such a platform). The side face cuts the capsule near its middle, so for its end spheres'
contacts the capsule's center says nothing about which side of the face the capsule is on
(:func:`engine.physics.collision.contact_helpers.center_decides`, as for polyhedra): the
face keeps its front, and the end hanging beyond the edge is pushed away from the side
face, never along it into the platform. Checked on the batched and the reference path.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, floor_mesh, make_world, register_primitive

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.collision.contact_helpers import segment_in_body
from engine.physics.core.quaternions import quat_to_matrix
from engine.scene.assets import MeshData

SOAK_CAPSULE = (
    "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
    "_useTexCoords_false_useTangents_false"
)
RADIUS = 0.1
LOWER_FLOOR = -0.15  # the floor beside the platform; the platform's top is y = 0
SINK_TOLERANCE = 0.02  # m, as the soak's: a surface point this far below has sunk


def platform_mesh() -> MeshData:
    """A closed box x in [0, 1], y in [-0.3, 0], z in [-1, 1], faces outward."""
    v = np.array(
        [[x, y, z] for x in (0.0, 1.0) for y in (-0.3, 0.0) for z in (-1.0, 1.0)], dtype=float
    )
    # vertex index = 4 ix + 2 iy + iz; two outward triangles per face
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], dtype=np.int64)
    return MeshData(vertices=v, faces=faces)


def axis_rotation(direction: np.ndarray) -> mn.Quaternion:
    """The rotation taking the capsule's axis (body +Y) onto ``direction``."""
    d = direction / np.linalg.norm(direction)
    axis = np.cross([0.0, 1.0, 0.0], d)
    angle = np.arccos(np.clip(d[1], -1.0, 1.0))
    return mn.Quaternion.rotation(mn.Rad(angle), mn.Vector3(*(axis / np.linalg.norm(axis))))


def end_depths(world, body: int) -> list[float]:
    """How far (m) each end sphere's lowest point is below the surface under its center:
    the platform's top over x >= 0, the lower floor beside it."""
    b = world.bodies
    rotation, position = quat_to_matrix(b.body_rotation[body]), b.body_position[body]
    start, end, radius = segment_in_body(b.shapes[body][0])
    depths = []
    for point in (rotation @ start + position, rotation @ end + position):
        surface = 0.0 if point[0] >= 0.0 else LOWER_FLOOR
        depths.append(max(0.0, surface - (point[1] - radius)))
    return depths


@pytest.mark.parametrize("vectorized", [True, False], ids=["batched", "reference"])
def test_capsule_falling_across_a_platform_edge_does_not_sink_into_it(vectorized):
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    world.set_stage([platform_mesh(), floor_mesh(height=LOWER_FLOOR)], StageAttributes())
    handle = register_primitive(templates, SOAK_CAPSULE, (0.1, 0.1, 0.1))
    capsule = add(
        world,
        templates,
        handle,
        [0.0132, 0.1104, 0.0],
        linear_velocity=[-0.2347, -3.6522, -0.1153],
        angular_velocity=[3.5867, 0.7128, 1.589],
    )
    capsule.rotation = axis_rotation(np.array([0.1473, -0.0281, -0.0028]))
    body = capsule.object_id
    deepest = 0.0
    for _ in range(60):  # 1 s: onto the edge, then off it or resting on it
        world.step_physics(1.0 / 60.0)
        deepest = max(deepest, *end_depths(world, body))
    assert deepest < SINK_TOLERANCE
