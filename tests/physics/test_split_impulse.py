"""The split impulse (position correction on pseudo velocities) moves a body as an impulse at
its contact would, and adds no kinetic energy.

Scene: no gravity, a 0.2 m cube (1 kg, I = m (2a)^2 / 6 = (2/3) m a^2 about every axis) turned
by 20 degrees about X, created with its lowest edge 1 cm below a flat floor, at rest. The edge
is parallel to X, at z = a (cos t - sin t) from the centre in the world frame. Any pseudo
impulse P along the floor normal +Y applied at points of that edge gives

    dv_y = P / m,    dw_x = -z_edge P / I_xx     (r x n = (-r_z, 0, r_x) for n = +Y),

whatever its distribution between the edge's two ends (their r_x cancel in dw_x only through
P; r_z is the same for both, and also for any point straight above them on the floor). So the
pose change of one step has d(tilt) / d(height) = -m z_edge / I_xx, exactly, and the tilt
*decreases*: the push at the low edge turns the box towards lying flat.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics.core import settings
from engine.physics.core.quaternions import quat_to_matrix

HALF = 0.1
TILT = np.radians(20.0)
DEPTH = 0.01  # m, the lowest edge's initial penetration (2.5 x the slop)
H = 0.008


def _tilted_box_in_the_floor():
    world, templates = make_world(gravity=(0.0, 0.0, 0.0), timestep=H)
    handle = register_primitive(templates, "cubeSolid", (HALF,) * 3)
    c, s = np.cos(TILT), np.sin(TILT)
    box = add(world, templates, handle, [0.0, HALF * (c + s) - DEPTH, 0.0])
    box.rotation = mn.Quaternion.rotation(mn.Rad(TILT), mn.Vector3.x_axis())
    return world, box


def _tilt_and_lowest(world, index: int) -> tuple[float, float]:
    """Rotation angle about X (rad) and the lowest corner's height (m)."""
    b = world.bodies
    r = quat_to_matrix(b.body_rotation[index : index + 1])[0]
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * HALF
    lowest = float((corners @ r.T + b.body_position[index])[:, 1].min())
    return float(np.arctan2(r[2, 1], r[1, 1])), lowest


def test_push_out_of_a_tilted_box_turns_it_as_an_impulse_at_its_edge():
    world, box = _tilted_box_in_the_floor()
    i, b = box.object_id, world.bodies
    tilt0, low0 = _tilt_and_lowest(world, i)
    y0 = b.body_position[i, 1]
    assert tilt0 == pytest.approx(TILT, abs=1e-12)
    assert low0 == pytest.approx(-DEPTH, abs=1e-12)
    world.step_physics(H)  # one fixed step
    tilt1, low1 = _tilt_and_lowest(world, i)
    dy, dtilt = b.body_position[i, 1] - y0, tilt1 - tilt0
    assert dy > 1e-4  # pushed up out of the floor
    assert low1 > low0
    z_edge = HALF * (np.cos(TILT) - np.sin(TILT))
    inertia = 2.0 / 3.0 * box.mass * HALF**2
    # the rotation about X is exact (one fixed axis), so the ratio holds to rounding
    assert dtilt / dy == pytest.approx(-box.mass * z_edge / inertia, rel=1e-9)
    # pseudo velocities move the body this step only: no kinetic energy is added
    np.testing.assert_array_equal(b.body_linear_velocity[i], 0.0)
    np.testing.assert_array_equal(b.body_angular_velocity[i], 0.0)


def test_tilted_box_recovers_to_the_slop_without_gaining_speed():
    world, box = _tilted_box_in_the_floor()
    i, b = box.object_id, world.bodies
    for _ in range(60):
        world.step_physics(H)
        np.testing.assert_array_equal(b.body_linear_velocity[i], 0.0)
        np.testing.assert_array_equal(b.body_angular_velocity[i], 0.0)
    tilt, lowest = _tilt_and_lowest(world, i)
    # penetration beyond the slop is removed; the slop itself is left (no jitter from it)
    assert -settings.PENETRATION_SLOP - 1e-6 < lowest < -settings.PENETRATION_SLOP + 1e-3
    assert tilt < TILT - np.radians(1.0)  # turned towards lying flat, never away from it
