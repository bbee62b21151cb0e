"""Spheres on a stage mesh (the exact sphere-triangle contact of
:func:`engine.physics.collision.collide.round_stage_contacts`): rest heights, sideways drift and the
edge of the stage.

The floor is two triangles (the plane y = 0, x and z in [-5, 5]); a sphere of radius r at
rest on it has its centre at y = r (within the penetration slop) and, the contact normal
being +y, nothing pushes it sideways. A sphere whose centre lies beyond the floor's edge
touches only that edge: the contact normal points from the edge to the centre, outward
and up, so the sphere rolls off and falls.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine.physics.core import settings

SPHERE = "icosphereSolid_subdivs_1"
RADIUS = 0.1
HALF = 5.0  # the floor's half size
# the solver leaves up to the penetration slop of overlap (plus a margin for its last step)
REST_TOLERANCE = settings.PENETRATION_SLOP + 1e-4
# over the first triangle only, over the second only, on their shared diagonal, near a corner
SPOTS = [(3.0, -3.0), (-3.0, 3.0), (0.5, 0.5), (-4.8, -4.8)]


@pytest.fixture(scope="module")
def settled():
    world, templates = make_world(floor_half=HALF)
    handle = register_primitive(templates, SPHERE, (RADIUS,) * 3)
    resting = [add(world, templates, handle, [x, RADIUS + 0.05, z]) for x, z in SPOTS]
    beyond = add(world, templates, handle, [HALF + 0.06, 0.05, 1.0])  # overhangs the edge
    run(world, 1.0)
    return resting, beyond


@pytest.mark.parametrize("spot", range(len(SPOTS)), ids=[str(s) for s in SPOTS])
def test_a_sphere_rests_one_radius_above_the_floor_where_it_was_dropped(settled, spot):
    position = np.asarray(settled[0][spot].translation)
    assert position[1] == pytest.approx(RADIUS, abs=REST_TOLERANCE)
    np.testing.assert_allclose(position[[0, 2]], SPOTS[spot], atol=1e-3)


def test_a_sphere_overhanging_the_edge_rolls_off_and_falls(settled):
    position = np.asarray(settled[1].translation)
    assert position[0] > HALF + 0.06  # pushed outward, away from the edge
    assert position[1] < -1.0  # then fell (free fall for most of the second)
    assert position[2] == pytest.approx(1.0, abs=1e-3)  # the edge runs along z: no z push


def test_a_sphere_teleported_with_its_centre_just_under_the_floor_is_pushed_up():
    """Its centre 3 cm below the plane y = 0 but its top above it: the floor's front (up)
    holds it, so it comes out on top and rests there (pushed down, it would fall)."""
    world, templates = make_world(floor_half=HALF)
    handle = register_primitive(templates, SPHERE, (RADIUS,) * 3)
    sphere = add(world, templates, handle, [1.0, -0.03, 2.0])
    run(world, 1.0)
    assert np.asarray(sphere.translation)[1] == pytest.approx(RADIUS, abs=REST_TOLERANCE)
