"""Physics does not depend on where the world origin is (Galilean / translation invariance).

Contact impulses act at lever arms ``r = p - x`` measured from each body's own centre; a
scene moved away from the origin must behave as it does at the origin. Scenes that sit at
the origin cannot show a lever arm measured from the wrong point (for a body at x = z = 0,
``r x n`` of a vertical normal does not depend on the height of the centre), so these are
placed meters away from it.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine.physics.core import settings

HALF = 0.1


@pytest.mark.parametrize("where", [(0.0, 0.0), (3.0, -2.0), (-5.0, 4.0)])
def test_two_box_stack_stands_wherever_it_is_built(where):
    """Two 20 cm cubes, one on the other, on the floor at (x, z): after 2 s both are still
    upright at their rest heights HALF and 3 HALF (each contact may keep the penetration
    slop) and have not moved sideways."""
    x, z = where
    world, templates = make_world()
    handle = register_primitive(templates, "cubeSolid", (HALF,) * 3)
    bottom = add(world, templates, handle, [x, HALF, z])
    top = add(world, templates, handle, [x, 3 * HALF, z])
    run(world, 2.0)
    slop = settings.PENETRATION_SLOP
    for box, rest in ((bottom, HALF), (top, 3 * HALF)):
        position = world.bodies.body_position[box.object_id]
        quaternion = world.bodies.body_rotation[box.object_id]  # (x, y, z, w)
        assert np.hypot(position[0] - x, position[2] - z) < 1e-3
        assert rest - 2 * slop - 1e-3 < position[1] < rest + 1e-3
        # rotation angle 2 acos(|w|) under a tenth of a degree
        assert 2.0 * np.degrees(np.arccos(min(1.0, abs(quaternion[3])))) < 0.1
