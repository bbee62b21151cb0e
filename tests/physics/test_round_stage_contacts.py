"""Round bodies on stage ridges: the triangle normals face the body whatever their winding.

A capsule lying across a narrow ridge of the stage touches it only under the middle of its
axis: neither end sphere comes within the stage's speculative distance of the ridge, so the
contact takes the normal of the deepest triangle the stage's collision query reports, turned
to face the capsule's centre
(:func:`engine.physics.collision.collide.round_stage_contacts`). A normal facing away would
push the capsule into the ridge, and a zero one would not hold it up.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine import mn
from engine.attributes import StageAttributes
from engine.physics.core import settings
from engine.scene.assets import MeshData

# capsule of radius 0.1 m and axis half length 0.2 m (template scale 0.1)
LONG_CAPSULE = (
    "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_2.0"
    "_useTexCoords_false_useTangents_false"
)
RADIUS, HALF_AXIS = 0.1, 0.2
RIDGE_HALF_WIDTH = 0.05  # the ridge: x in [-0.05, 0.05], top at y = 0, along Z


def ridge_mesh(flip_winding: bool) -> MeshData:
    """A closed box x in [-w, w], y in [-1, 0], z in [-1, 1]; faces outward (CCW seen from
    outside) unless ``flip_winding``."""
    w = RIDGE_HALF_WIDTH
    v = np.array(
        [[x, y, z] for x in (-w, w) for y in (-1.0, 0.0) for z in (-1.0, 1.0)], dtype=float
    )
    # vertex index = 4 ix + 2 iy + iz; two outward triangles per face
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = []
    for a, b, c, d in quads:
        faces += [(a, b, c), (a, c, d)]
    faces = np.array(faces, dtype=np.int64)
    if flip_winding:
        faces = faces[:, ::-1]
    return MeshData(vertices=v, faces=faces)


@pytest.mark.parametrize("flip_winding", [False, True], ids=["outward", "inward"])
def test_capsule_lying_across_a_ridge_rests_on_it(flip_winding):
    """Hand geometry: the axis rests at y = r = 0.1 m above the ridge's top (within the
    penetration slop); the end spheres, 0.15 m beyond the ridge's sides, never touch it."""
    world, templates = make_world(floor=False)
    world.set_stage([ridge_mesh(flip_winding)], StageAttributes())
    handle = register_primitive(templates, LONG_CAPSULE, (0.1, 0.1, 0.1))
    capsule = add(world, templates, handle, [0.0, RADIUS + 0.002, 0.0])
    capsule.rotation = mn.Quaternion.rotation(mn.Rad(np.pi / 2), mn.Vector3(0, 0, 1))
    end_gap = np.hypot(HALF_AXIS - RIDGE_HALF_WIDTH, RADIUS) - RADIUS
    assert end_gap > settings.STAGE_SPECULATIVE_DISTANCE  # only the middle can touch
    # at rest (the position solve lifts it to 3.9 mm deep within about 1.5 s; at 1 s it was
    # 3.90 mm before the block normal solve, 4.01 mm with it, both still rising)
    run(world, 2.0)
    position = np.asarray(capsule.translation)
    assert position[1] == pytest.approx(RADIUS, abs=settings.PENETRATION_SLOP)
    assert abs(position[0]) < 0.01 and abs(position[2]) < 0.01


PLATFORM_HEIGHT = 1.0  # a one-sided horizontal platform: the plane y = 1, x, z in [-2, 2]


def platform_mesh() -> MeshData:
    """Two triangles at y = PLATFORM_HEIGHT, wound counter-clockwise seen from above (their
    winding normal is +y): a plane that does not pass through the origin."""
    y, s = PLATFORM_HEIGHT, 2.0
    vertices = np.array([[-s, y, -s], [-s, y, s], [s, y, s], [s, y, -s]], dtype=float)
    return MeshData(vertices=vertices, faces=np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64))


@pytest.mark.parametrize("shape", ["sphere", "capsule"])
def test_a_ball_thrown_up_under_a_one_sided_platform_bounces_off_its_underside(shape):
    """A body wholly behind a one-sided stage triangle stays behind it (the first rule of
    :func:`contact_helpers.new_contact_side`): thrown up at 3 m/s from y = 0.6 its apex would
    be y = 0.6 + v^2 / (2 g) = 1.06 without the platform, but its top stops at the
    underside, y = 1, so its centre never rises above 1 - r (slop allowed), and it falls."""
    world, templates = make_world(floor=False)
    world.set_stage([platform_mesh()], StageAttributes())
    if shape == "sphere":
        handle = register_primitive(templates, "icosphereSolid_subdivs_1", (RADIUS,) * 3)
    else:  # lying flat: its lowest and highest points are r from its axis
        handle = register_primitive(templates, LONG_CAPSULE, (0.1, 0.1, 0.1))
    body = add(world, templates, handle, [0.0, 0.6, 0.0], linear_velocity=[0.0, 3.0, 0.0])
    if shape == "capsule":
        body.rotation = mn.Quaternion.rotation(mn.Rad(np.pi / 2), mn.Vector3(0, 0, 1))
    heights = []
    for _ in range(30):  # 0.5 s: up, stopped by the platform, falling again
        world.step_physics(1.0 / 60.0)
        heights.append(float(body.translation[1]))
    assert max(heights) < PLATFORM_HEIGHT - RADIUS + settings.PENETRATION_SLOP
    assert heights[-1] < heights[len(heights) // 2]  # falling at the end
