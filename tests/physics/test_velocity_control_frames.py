"""Velocity control frames: local velocities turn with the object, world spins compose on the
left (``q1 = dq q0``), and only the controlled parts of the motion are overwritten.

Geometry used throughout: ``q0`` = 90 degrees about +Y maps the object's local axes to world
axes as local +X -> world -Z, local +Z -> world +X, local +Y -> world +Y.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics import MotionType, RigidState, VelocityControl

Q0 = mn.Quaternion.rotation(mn.Deg(90.0), [0.0, 1.0, 0.0])


def _matrix(q) -> np.ndarray:
    return np.asarray(q.to_matrix())


def _rot(axis, angle) -> np.ndarray:
    """Rotation matrix by ``angle`` rad about a unit ``axis`` (Rodrigues)."""
    k = np.array(
        [[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]], float
    )
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def _control(linear=None, angular=None, lin_local=False, ang_local=False) -> VelocityControl:
    vc = VelocityControl()
    if linear is not None:
        vc.controlling_lin_vel = True
        vc.linear_velocity = linear
    if angular is not None:
        vc.controlling_ang_vel = True
        vc.angular_velocity = angular
    vc.lin_vel_is_local = lin_local
    vc.ang_vel_is_local = ang_local
    return vc


def test_local_spin_turns_about_the_objects_own_axis():
    # spinning 1 rad/s about local +X for 0.5 s turns the object 0.5 rad about world -Z
    vc = _control(angular=[1.0, 0.0, 0.0], ang_local=True)
    state = vc.integrate_transform(0.5, RigidState(Q0, [0.0, 0.0, 0.0]))
    expected = _rot([0.0, 0.0, -1.0], 0.5) @ _matrix(Q0)
    np.testing.assert_allclose(_matrix(state.rotation), expected, atol=1e-12)


def test_world_spin_turns_every_body_vector_about_the_world_axis():
    # 2 rad/s about world +X for 0.25 s: every body-fixed vector turns 0.5 rad about +X,
    # whatever the object's orientation (q1 = dq q0, not q0 dq)
    vc = _control(angular=[2.0, 0.0, 0.0])
    state = vc.integrate_transform(0.25, RigidState(Q0, [1.0, 2.0, 3.0]))
    expected = _rot([1.0, 0.0, 0.0], 0.5) @ _matrix(Q0)
    np.testing.assert_allclose(_matrix(state.rotation), expected, atol=1e-12)
    np.testing.assert_array_equal(state.translation, [1.0, 2.0, 3.0])  # no linear control


def test_local_linear_velocity_moves_along_the_objects_axis():
    # local +X is world -Z: 2 m/s for 0.5 s moves 1 m along world -Z
    vc = _control(linear=[2.0, 0.0, 0.0], lin_local=True)
    state = vc.integrate_transform(0.5, RigidState(Q0, [1.0, 0.0, 0.0]))
    np.testing.assert_allclose(state.translation, [1.0, 0.0, -1.0], atol=1e-12)
    assert state.rotation == Q0  # no angular control: rotation untouched


def test_world_velocities_rotate_local_targets_into_the_world_frame():
    vc = _control(linear=[0.0, 0.0, 3.0], angular=[1.0, 0.0, 0.0], lin_local=True, ang_local=True)
    linear, angular = vc.world_velocities(Q0.xyzw)
    np.testing.assert_allclose(linear, [3.0, 0.0, 0.0], atol=1e-12)  # local +Z -> world +X
    np.testing.assert_allclose(angular, [0.0, 0.0, -1.0], atol=1e-12)  # local +X -> world -Z
    vc.lin_vel_is_local = vc.ang_vel_is_local = False
    linear, angular = vc.world_velocities(Q0.xyzw)
    np.testing.assert_array_equal(linear, [0.0, 0.0, 3.0])
    np.testing.assert_array_equal(angular, [1.0, 0.0, 0.0])


def test_uncontrolled_parts_are_none():
    vc = _control(angular=[0.0, 1.0, 0.0])
    assert vc.world_velocities(Q0.xyzw)[0] is None
    vc = _control(linear=[0.0, 1.0, 0.0])
    assert vc.world_velocities(Q0.xyzw)[1] is None


def test_angular_only_control_of_a_falling_dynamic_body_keeps_its_fall():
    # controlling the spin must not touch the linear velocity: the body falls at g
    world, templates = make_world(floor=False)
    handle = register_primitive(templates, linear_damping=0.0, angular_damping=0.0)
    box = add(world, templates, handle, [0.0, 10.0, 0.0])
    vc = box.velocity_control
    vc.controlling_ang_vel = True
    vc.angular_velocity = [0.0, 1.5, 0.0]
    for _ in range(30):
        world.step_physics(1.0 / 60.0)
    t = world.get_world_time()
    np.testing.assert_allclose(box.linear_velocity, [0.0, -9.8 * t, 0.0], atol=1e-9)
    np.testing.assert_allclose(box.angular_velocity, [0.0, 1.5, 0.0], atol=1e-9)


def test_kinematic_local_spin_turns_about_the_objects_axis_in_the_world():
    world, templates = make_world(floor=False)
    handle = register_primitive(templates)
    box = add(world, templates, handle, [0.0, 0.0, 0.0])
    box.motion_type = MotionType.KINEMATIC
    box.rotation = Q0
    vc = box.velocity_control
    vc.controlling_ang_vel = vc.ang_vel_is_local = True
    vc.angular_velocity = [0.6, 0.0, 0.0]
    world.step_physics(0.5)  # kinematic: one explicit Euler step of dt = 0.5 s
    expected = _rot([0.0, 0.0, -1.0], 0.3) @ _matrix(Q0)
    np.testing.assert_allclose(_matrix(box.rotation), expected, atol=1e-12)


def test_zero_angular_velocity_under_control_leaves_the_rotation_unchanged():
    vc = _control(angular=[0.0, 0.0, 0.0])
    state = vc.integrate_transform(1.0, RigidState(Q0, [0.0, 0.0, 0.0]))
    np.testing.assert_array_equal(state.rotation.xyzw, Q0.xyzw)


def test_long_spins_keep_a_unit_quaternion():
    vc = _control(angular=[0.3, -1.1, 0.7])
    state = RigidState(Q0, [0.0, 0.0, 0.0])
    for _ in range(2000):
        state = vc.integrate_transform(0.05, state)
    assert np.linalg.norm(state.rotation.xyzw) == pytest.approx(1.0, abs=1e-12)
    # 2000 x 0.05 s = 100 s at |w| rad/s about a fixed axis: one rotation by 100 |w| rad
    w = np.array([0.3, -1.1, 0.7])
    expected = _rot(w / np.linalg.norm(w), 100.0 * np.linalg.norm(w)) @ _matrix(Q0)
    np.testing.assert_allclose(_matrix(state.rotation), expected, atol=1e-9)


def test_defaults_are_off_and_zero_and_setters_round_trip():
    vc = VelocityControl()
    assert not vc.is_active
    for flag in ("controlling_lin_vel", "controlling_ang_vel", "lin_vel_is_local"):
        assert getattr(vc, flag) is False
    assert vc.ang_vel_is_local is False
    assert vc.linear_velocity == mn.Vector3(0.0, 0.0, 0.0)
    assert vc.angular_velocity == mn.Vector3(0.0, 0.0, 0.0)
    vc.linear_velocity = [1.0, 2.0, 3.0]
    vc.angular_velocity = mn.Vector3(-1.0, 0.5, 0.0)
    assert vc.linear_velocity == mn.Vector3(1.0, 2.0, 3.0)
    assert vc.angular_velocity == mn.Vector3(-1.0, 0.5, 0.0)
    vc.controlling_ang_vel = np.bool_(True)
    assert vc.controlling_ang_vel is True and vc.is_active
    vc.controlling_ang_vel = False
    vc.controlling_lin_vel = True
    assert vc.is_active
    state = RigidState()
    assert state.rotation == mn.Quaternion() and state.translation == mn.Vector3(0, 0, 0)


@pytest.mark.parametrize(
    "flag", ["controlling_lin_vel", "controlling_ang_vel", "lin_vel_is_local", "ang_vel_is_local"]
)
@pytest.mark.parametrize("value", [1, 0, "yes", None, 1.0])
def test_flags_accept_only_bools(flag, value):
    vc = VelocityControl()
    with pytest.raises(TypeError, match=flag):
        setattr(vc, flag, value)
    assert getattr(vc, flag) is False  # unchanged


def test_bad_integrate_transform_arguments_are_rejected_by_name():
    vc = _control(linear=[1e38, 0.0, 0.0])
    state = RigidState()
    for dt in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match="dt"):
            vc.integrate_transform(dt, state)
    with pytest.raises(TypeError, match="rigid_state"):
        vc.integrate_transform(0.1, (mn.Quaternion(), [0, 0, 0]))
    with pytest.raises(ValueError, match="linear_velocity"):
        vc.integrate_transform(1e10, state)  # 1e48 m: beyond the 32-bit float range
    with pytest.raises(AttributeError, match="no_such_flag"):
        _ = vc.no_such_flag
