"""Defects found by the reliability probe of issue 22's follow-up (docs/reliability.md,
"Probe"), each reduced to its smallest repro: the world stays finite whatever inertia a
template or the Habitat setter gives a body, within the engine's speed limits.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics import settings

FRAME = 1.0 / 60.0


def _state_is_finite(world) -> bool:
    b, n = world.bodies, world.bodies.count
    arrays = (b.body_position, b.body_rotation, b.body_linear_velocity, b.body_angular_velocity)
    return all(bool(np.all(np.isfinite(a[:n]))) for a in arrays)


@pytest.mark.parametrize("inertia", [1e-300, 1e-200])
@pytest.mark.parametrize("through_setter", [False, True])
@pytest.mark.parametrize("vectorized", [True, False])
def test_cube_with_a_vanishing_inertia_stays_finite_on_the_floor(
    inertia, through_setter, vectorized
):
    """A 1 kg, 20 cm cube given an inertia of 1e-300 kg m^2 (accepted: Habitat takes any
    positive inertia) and dropped tilted onto the floor: its split-impulse turn
    I^-1 lambda overflowed the rotation to NaN 16 frames later. The turn now obeys the
    angular speed limit like the velocity does."""
    world, templates = make_world()
    world.settings.use_vectorized = vectorized
    fields = {} if through_setter else {"inertia": [inertia] * 3}
    handle = register_primitive(templates, handle="cube", **fields)
    cube = add(world, templates, handle, [0.0, 0.3, 0.0])
    if through_setter:
        cube.intertia_diagonal = [inertia] * 3
    cube.rotation = mn.Quaternion(mn.Vector3(0.1, 0.2, 0.0), 0.97)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no overflow on the way
        for _ in range(60):
            world.step_physics(FRAME)
            assert _state_is_finite(world)
            w = np.asarray(cube.angular_velocity)
            assert np.linalg.norm(w) <= settings.MAX_ANGULAR_SPEED * (1 + 1e-12)
