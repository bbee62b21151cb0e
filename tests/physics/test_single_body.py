"""docs/physics.md, validation: one body, no contact (free fall, forces, spin, velocity control)."""

from __future__ import annotations

import numpy as np
from helpers import add, make_world, register_primitive

from engine import mn
from engine.physics import MotionType, RigidState, VelocityControl

H = 0.008
G = 9.8


def _free_body(world, templates, half=(0.1, 0.1, 0.1), position=(0.0, 10.0, 0.0)):
    handle = register_primitive(
        templates, "cubeSolid", half, linear_damping=0.0, angular_damping=0.0
    )
    return add(world, templates, handle, list(position))


def test_free_fall_matches_the_discrete_recurrence_and_the_parabola():
    world, templates = make_world(floor=False)
    box = _free_body(world, templates)
    for _ in range(60):  # 1 s of frames; 125 fixed steps (world time 0.992 .. 1.0)
        world.step_physics(1.0 / 60.0)
    n = round(world.get_world_time() / H)
    t = n * H
    # symplectic Euler: v_n = -g h n, y_n = y_0 - g h^2 n (n + 1) / 2, exact in float64 to 1e-9
    np.testing.assert_allclose(box.linear_velocity[1], -G * H * n, rtol=0, atol=1e-9)
    np.testing.assert_allclose(box.translation[1], 10.0 - G * H * H * n * (n + 1) / 2, atol=1e-9)
    # the recurrence leads 1/2 g t^2 by exactly g h t / 2 (it falls further, never gains energy)
    drop = 10.0 - box.translation[1]
    assert 0.5 * G * t * t <= drop <= 0.5 * G * t * t + G * H * t / 2 * (1 + 1e-9)


def test_constant_force_and_torque_accelerate_and_vanish_after_the_call():
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    box = _free_body(world, templates)
    inertia = np.asarray(box.intertia_diagonal)
    np.testing.assert_allclose(inertia, np.full(3, (0.01 + 0.01) / 3))  # m (b^2 + c^2) / 3
    for _ in range(10):
        box.apply_force([2.0, 0.0, 0.0], [0.0, 0.0, 0.0])
        box.apply_torque([0.0, 0.01, 0.0])
        world.step_physics(1.0 / 60.0)
    t = world.get_world_time()
    # a = F / m = 2 m/s^2; alpha = tau / I (the cube's inertia is isotropic, no gyroscopic drift)
    np.testing.assert_allclose(box.linear_velocity, [2.0 * t, 0, 0], atol=1e-9)
    np.testing.assert_allclose(box.angular_velocity, [0, 0.01 / inertia[1] * t, 0], atol=1e-9)
    before = np.asarray(box.linear_velocity)
    world.step_physics(1.0 / 60.0)  # no force applied: velocity unchanged (forces cleared)
    np.testing.assert_allclose(box.linear_velocity, before, atol=1e-12)


def test_torque_free_spin_of_an_asymmetric_box_conserves_momentum_and_never_gains_energy():
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    box = _free_body(world, templates, half=(0.1, 0.2, 0.3))
    box.angular_velocity = [0.05, 5.0, 0.0]  # intermediate axis + small perturbation
    inertia = np.asarray(box.intertia_diagonal)

    def energy_and_momentum():
        r = np.asarray(box.rotation.to_matrix())
        w = np.asarray(box.angular_velocity)
        momentum = r @ (inertia * (r.T @ w))  # L = R I R^T w
        return 0.5 * w @ momentum, momentum

    e0, l0 = energy_and_momentum()
    energies = []
    for _ in range(100 * 60 // 4):  # 100 s with 4-frame calls (same fixed steps)
        world.step_physics(4.0 / 60.0)
        energies.append(energy_and_momentum()[0])
    e1, l1 = energy_and_momentum()
    assert np.all(np.isfinite(energies))
    assert max(energies) <= 1.01 * e0  # docs/physics.md: never above 1.01 x start
    # the update holds L fixed in the world frame; 1e-3 relative is the validation bound
    np.testing.assert_allclose(l1, l0, atol=1e-3 * np.linalg.norm(l0))


def test_velocity_control_reference_numbers():
    vc = VelocityControl()
    vc.controlling_lin_vel = vc.controlling_ang_vel = True
    vc.lin_vel_is_local = vc.ang_vel_is_local = True
    vc.linear_velocity = [0.0, 0.0, -1.0]
    vc.angular_velocity = [1.0, 0.0, 0.0]
    state = RigidState(mn.Quaternion(), [0.0, 2.0, 0.0])
    for _ in range(1251):
        state = vc.integrate_transform(0.008, state)
    # Habitat's reference numbers (docs/habitat_api.md, 3 decimals)
    np.testing.assert_allclose(state.translation, [0.0, 3.836, 0.544], atol=1e-3)
    np.testing.assert_allclose(
        [state.rotation.scalar, state.rotation.vector[0]], [0.2875, -0.9578], atol=1e-4
    )


def test_kinematic_global_velocity_control_moves_one_meter_in_one_second():
    world, templates = make_world(floor=False)
    box = _free_body(world, templates, position=(0.0, 0.0, 0.0))
    box.motion_type = MotionType.KINEMATIC
    vc = box.velocity_control
    vc.controlling_lin_vel = True
    vc.linear_velocity = [1.0, 0.0, 0.0]
    for _ in range(60):
        world.step_physics(1.0 / 60.0)  # kinematic: integrated once per call with dt
    np.testing.assert_allclose(box.translation, [1.0, 0.0, 0.0], atol=1e-9)
    assert box.root_scene_node.translation == box.translation  # the node follows


def test_dynamic_velocity_control_overwrites_velocity_once_per_call():
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    box = _free_body(world, templates, position=(0.0, 0.0, 0.0))
    vc = box.velocity_control
    vc.controlling_lin_vel = True
    vc.lin_vel_is_local = True
    vc.linear_velocity = [0.0, 0.0, -2.0]
    box.rotation = mn.Quaternion.rotation(mn.Deg(90.0), [0.0, 1.0, 0.0])  # local -Z -> world -X
    world.step_physics(0.1)
    np.testing.assert_allclose(box.linear_velocity, [-2.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(box.translation, [-2.0 * world.get_world_time(), 0, 0], atol=1e-9)
