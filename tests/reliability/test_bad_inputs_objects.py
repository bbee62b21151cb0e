"""Bad input to rigid objects and ray casts: a clear exception, the world unchanged.

Object setters get non-finite, wrongly shaped and out-of-range values, values beyond the
32-bit float range poses and velocity targets live in (``translate`` by 1e308, a 1e308 m/s
velocity target: refused the first time), and values that only overflow when used (a second
huge impulse, a kinematic velocity that would carry the object out of range at the step);
``cast_ray`` gets non-rays, bad distances and huge rays. Every refusal is checked by
:func:`bad_inputs.assert_refused` (exception type and an unchanged ``world_hash``) on the
``sim`` of ``conftest.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from bad_inputs import (
    EXAMPLES,
    assert_refused,
    bad_number,
    bad_vector,
    finite,
    junk,
    objects,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from world_hash import bodies_are_finite, world_hash

import engine as habitat_sim

VECTOR_TARGETS = {
    "translation": (3, lambda o, v: setattr(o, "translation", v)),
    "rotation": (4, lambda o, v: setattr(o, "rotation", v)),
    "linear_velocity": (3, lambda o, v: setattr(o, "linear_velocity", v)),
    "angular_velocity": (3, lambda o, v: setattr(o, "angular_velocity", v)),
    "translate": (3, lambda o, v: o.translate(v)),
    "translate_local": (3, lambda o, v: o.translate_local(v)),
    "apply_force": (3, lambda o, v: o.apply_force(v, [0.0, 0.0, 0.0])),
    "apply_force at": (3, lambda o, v: o.apply_force([1.0, 0.0, 0.0], v)),
    "apply_torque": (3, lambda o, v: o.apply_torque(v)),
    "apply_impulse": (3, lambda o, v: o.apply_impulse(v, [0.0, 0.0, 0.0])),
    "apply_impulse at": (3, lambda o, v: o.apply_impulse([1.0, 0.0, 0.0], v)),
    "apply_impulse_torque": (3, lambda o, v: o.apply_impulse_torque(v)),
    "intertia_diagonal": (3, lambda o, v: setattr(o, "intertia_diagonal", v)),
    "rotate axis": (3, lambda o, v: o.rotate(habitat_sim.mn.Rad(0.1), v)),
    "vc linear": (3, lambda o, v: setattr(o.velocity_control, "linear_velocity", v)),
    "vc angular": (3, lambda o, v: setattr(o.velocity_control, "angular_velocity", v)),
    "node scaling": (3, lambda o, v: setattr(o.root_scene_node, "scaling", v)),
    "node translation": (3, lambda o, v: setattr(o.root_scene_node, "translation", v)),
}

SCALAR_TARGETS = {
    "mass": (dict(low=0.0, low_open=True), lambda o, v: setattr(o, "mass", v)),
    "friction_coefficient": (dict(low=0.0), lambda o, v: setattr(o, "friction_coefficient", v)),
    "restitution_coefficient": (
        dict(low=0.0, high=1.0),
        lambda o, v: setattr(o, "restitution_coefficient", v),
    ),
    "linear_damping": (dict(low=0.0, high=1.0), lambda o, v: setattr(o, "linear_damping", v)),
    "angular_damping": (dict(low=0.0, high=1.0), lambda o, v: setattr(o, "angular_damping", v)),
    "rotate angle": ({}, lambda o, v: o.rotate_x(v)),
    "motion_type": (dict(low=0.0, high=2.5), lambda o, v: setattr(o, "motion_type", v)),
    "step_physics dt": ({}, lambda o, v: o._world.step_physics(v)),
}


# -- objects ---------------------------------------------------------------------------------------
@EXAMPLES
@given(data=st.data())
def test_object_vector_setters_refuse_bad_vectors(sim, data):
    name = data.draw(st.sampled_from(sorted(VECTOR_TARGETS)), label="target")
    size, call = VECTOR_TARGETS[name]
    obj = data.draw(st.sampled_from(objects(sim)), label="object")
    value = data.draw(bad_vector(size), label="value")
    assert_refused(sim, lambda: call(obj, value))


@EXAMPLES
@given(data=st.data())
def test_object_scalar_setters_refuse_bad_numbers(sim, data):
    name = data.draw(st.sampled_from(sorted(SCALAR_TARGETS)), label="target")
    bounds, call = SCALAR_TARGETS[name]
    obj = data.draw(st.sampled_from(objects(sim)), label="object")
    value = data.draw(bad_number(**bounds), label="value")
    if name == "motion_type" and isinstance(value, float) and value in (0.0, 1.0, 2.0):
        value = 0.5  # a float equal to a member is still not a MotionType
    assert_refused(sim, lambda: call(obj, value))


@EXAMPLES
@given(
    a=st.floats(1e-6, 1e3),
    b=st.floats(1e-6, 1e3),
    excess=st.floats(1e-4, 1e3),
    order=st.permutations([0, 1, 2]),
)
def test_inertia_breaking_the_triangle_inequality_is_refused(sim, a, b, excess, order):
    inertia = np.array([a, b, (a + b) * (1.0 + excess)])[list(order)]
    obj = objects(sim)[0]
    assert_refused(
        sim, lambda: setattr(obj, "intertia_diagonal", inertia), match="triangle inequality"
    )


OVERFLOW_TARGETS = (
    "translate",
    "apply_impulse",
    "apply_force",
    "apply_torque",
    "apply_impulse_torque",
    "transformation",
)


@EXAMPLES
@given(
    name=st.sampled_from(OVERFLOW_TARGETS),
    big=st.floats(0.9e308, 1.7e308),
    sign=st.sampled_from([-1.0, 1.0]),
    axis=st.integers(0, 2),
)
def test_values_that_overflow_only_when_used_are_refused(sim, name, big, sign, axis):
    """The first call is fine (finite result) or already refused (``translate``: beyond the
    32-bit float range), the second would overflow: refused."""
    obj = objects(sim)[0]  # dynamic
    original = (obj.translation, obj.rotation, obj.linear_velocity, obj.angular_velocity)
    vector = np.zeros(3)
    vector[axis] = sign * big
    try:
        if name == "transformation":
            matrix = np.eye(4)
            matrix[:3, :3] *= big  # columns of norm 1e308: fine; their squares overflow
            matrix[axis, 3] = 1.0
            obj.transformation = matrix
            assert bodies_are_finite(sim.get_physics_world())
            matrix[:3, :3] = np.diag([1.0, 1.0, -1.0]) * 1e300  # a (huge) reflection
            assert_refused(sim, lambda: setattr(obj, "transformation", matrix), ValueError)
            return
        call = {
            "translate": lambda: obj.translate(vector),
            "apply_impulse": lambda: obj.apply_impulse(vector * obj.mass, [0, 0, 0]),
            "apply_force": lambda: obj.apply_force(vector, [0, 0, 0]),
            "apply_torque": lambda: obj.apply_torque(vector),
            "apply_impulse_torque": lambda: obj.apply_impulse_torque(vector),
        }[name]
        try:
            call()  # may already be refused (a force's h F / m), else it is finite
        except ValueError:
            pass
        assert bodies_are_finite(sim.get_physics_world())
        assert_refused(sim, call, ValueError, match="too large")
    finally:
        sim.get_physics_world().bodies.body_force[obj.object_id] = 0.0
        sim.get_physics_world().bodies.body_torque[obj.object_id] = 0.0
        obj.translation, obj.rotation = original[0], original[1]
        obj.linear_velocity, obj.angular_velocity = original[2], original[3]


@settings(
    max_examples=6,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(speed=st.floats(1e154, 1.7e308), angular=st.booleans())
def test_huge_speeds_are_clamped_to_the_limit_not_to_zero(sim, speed, angular):
    from engine.physics.core import settings as constants

    obj = objects(sim)[2]
    original = obj.translation
    obj.translation = [3.0, 30.0, 0.0]  # in the air: nothing to hit in one step
    try:
        if angular:
            obj.angular_velocity = [0.0, speed, 0.0]
        else:
            obj.linear_velocity = [speed, 0.0, 0.0]
        sim.step_physics(0.0)  # one fixed step; in the air nothing is hit
        value = obj.angular_velocity if angular else obj.linear_velocity
        limit = constants.MAX_ANGULAR_SPEED if angular else constants.MAX_LINEAR_SPEED
        assert bodies_are_finite(sim.get_physics_world())
        assert np.linalg.norm(np.asarray(value)) == pytest.approx(limit, rel=1e-6)
    finally:
        obj.translation, obj.linear_velocity, obj.angular_velocity = original, [0, 0, 0], [0, 0, 0]


def test_huge_rotation_components_are_normalized_without_overflow(sim):
    obj = objects(sim)[0]
    original = obj.rotation
    obj.rotation = [1e300, 1e300, 0.0, 0.0]
    np.testing.assert_allclose(
        np.asarray(obj.rotation.xyzw), [math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0], atol=1e-12
    )
    obj.rotation = original
    assert bodies_are_finite(sim.get_physics_world())


def test_a_kinematic_node_with_zero_scale_is_refused(sim):
    kinematic = objects(sim)[1]
    assert_refused(
        sim,
        lambda: setattr(kinematic.root_scene_node, "scaling", [0.0, 0.0, 0.0]),
        ValueError,
        match="scaling",
    )


# -- ray casts -----------------------------------------------------------------------------------
@EXAMPLES
@given(
    ray=st.one_of(junk, st.integers(), st.lists(finite, max_size=6)),
    distance=st.one_of(bad_number(0.0), st.just(100.0)),
)
def test_cast_ray_refuses_non_rays_and_bad_distances(sim, ray, distance):
    if distance == 100.0:
        assert_refused(sim, lambda: sim.cast_ray(ray, distance), TypeError, match="ray")
    else:
        good = habitat_sim.geo.Ray([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
        assert_refused(sim, lambda: sim.cast_ray(good, distance))


@EXAMPLES
@given(
    origin=st.lists(st.floats(-1e300, 1e300), min_size=3, max_size=3),
    direction=st.lists(st.floats(-1e300, 1e300), min_size=3, max_size=3),
)
def test_cast_ray_with_huge_rays_returns_finite_hits(sim, origin, direction):
    before = world_hash(sim)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no overflow anywhere
        results = sim.cast_ray(habitat_sim.geo.Ray(origin, direction), 10.0)
    for hit in results.hits:
        assert np.all(np.isfinite(np.asarray(hit.point))) and math.isfinite(hit.ray_distance)
    assert world_hash(sim) == before


def test_kinematic_velocity_control_that_would_overflow_is_refused_at_the_step(sim):
    kinematic = objects(sim)[1]
    original = kinematic.translation
    kinematic.translation = [3.3e38, 0.5, 0.0]  # near the edge of the 32-bit float range
    control = kinematic.velocity_control
    control.controlling_lin_vel, control.linear_velocity = True, [1e38, 0.0, 0.0]
    try:
        assert_refused(sim, lambda: sim.step_physics(1.0), ValueError, match="linear_velocity")
    finally:
        control.controlling_lin_vel, control.linear_velocity = False, [0.0, 0.0, 0.0]
        kinematic.translation = original


@pytest.mark.parametrize("target", ["linear_velocity", "angular_velocity"])
@pytest.mark.parametrize("kinematic", [True, False])
def test_velocity_control_targets_beyond_float32_are_refused_when_set(sim, target, kinematic):
    obj = objects(sim)[1 if kinematic else 0]
    control = obj.velocity_control
    before = getattr(control, target)
    assert_refused(sim, lambda: setattr(control, target, [1e308, 0.0, 0.0]), ValueError, target)
    assert getattr(control, target) == before
    setattr(control, target, [-3.4e38, 0.0, 0.0])  # the largest float32 values are accepted
    setattr(control, target, before)


@pytest.mark.parametrize("call", ["translate", "translate_local", "translation"])
def test_poses_beyond_float32_are_refused_the_first_time(sim, call):
    obj = objects(sim)[1]  # kinematic
    start = obj.translation
    move = {
        "translate": lambda: obj.translate([0.0, -1e308, 0.0]),
        "translate_local": lambda: obj.translate_local([0.0, 0.0, 1e308]),
        "translation": lambda: setattr(obj, "translation", [1e39, 0.0, 0.0]),
    }[call]
    assert_refused(sim, move, ValueError, match="32-bit float range")
    assert obj.translation == start
    sim.step_physics(1.0 / 60.0)  # nothing was poisoned: the world still steps
