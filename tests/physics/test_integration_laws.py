"""Laws of the integrator for one free body: Newton with a mass, damping, speed limits and
the torque-free rotation of an asymmetric body (the Dzhanibekov effect).

Every scene has no floor, so nothing but the integrator moves the body. The fixed step is
h = 0.008 s; one ``step_physics(1/60)`` call runs whole fixed steps, so world time is always
``n h`` and the discrete laws below hold to rounding.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive
from scipy.integrate import solve_ivp

H = 0.008


def _free_box(half=(0.1, 0.1, 0.1), gravity=(0.0, 0.0, 0.0), **fields):
    world, templates = make_world(floor=False, gravity=gravity)
    fields.setdefault("linear_damping", 0.0)
    fields.setdefault("angular_damping", 0.0)
    handle = register_primitive(templates, "cubeSolid", half, **fields)
    return world, add(world, templates, handle, [0.0, 0.0, 0.0])


def _n_steps(world) -> int:
    return round(world.get_world_time() / H)


def test_force_on_a_2kg_body_accelerates_at_f_over_m_plus_g():
    world, box = _free_box(gravity=(0.0, -9.8, 0.0))
    box.mass = 2.0
    force = np.array([3.0, 4.0, -1.0])  # newtons
    for _ in range(12):
        box.apply_force(force, [0.0, 0.0, 0.0])
        world.step_physics(1.0 / 60.0)
    t = _n_steps(world) * H
    # Newton: a = F / m + g = (1.5, 2 - 9.8, -0.5) m/s^2; explicit Euler is exact for constant a
    expected = (force / 2.0 + [0.0, -9.8, 0.0]) * t
    np.testing.assert_allclose(box.linear_velocity, expected, rtol=0, atol=1e-9)


def test_torque_on_a_heavy_box_gives_alpha_equal_tau_over_inertia():
    world, box = _free_box()
    box.mass = 3.0  # keeps the inertia: alpha depends on I only, not on m
    inertia = np.asarray(box.intertia_diagonal)
    torque = np.array([0.0, 0.0, 0.02])  # about a principal axis: no gyroscopic coupling
    for _ in range(6):
        box.apply_torque(torque)
        world.step_physics(1.0 / 60.0)
    t = _n_steps(world) * H
    np.testing.assert_allclose(box.angular_velocity, torque / inertia * t, rtol=0, atol=1e-9)


@pytest.mark.parametrize("damping", [0.1, 0.5, 0.9])
def test_damping_decays_velocities_as_one_minus_d_to_the_t(damping):
    # Bullet / Habitat damping: v(t) = v0 (1 - d)^t for t in seconds, independent of h
    world, box = _free_box(linear_damping=damping, angular_damping=damping / 3.0)
    box.linear_velocity = [1.0, -2.0, 0.5]
    box.angular_velocity = [0.0, 3.0, 0.0]  # a cube: no gyroscopic term
    for _ in range(30):
        world.step_physics(1.0 / 60.0)
    t = _n_steps(world) * H
    np.testing.assert_allclose(
        box.linear_velocity, np.array([1.0, -2.0, 0.5]) * (1.0 - damping) ** t, rtol=1e-12
    )
    np.testing.assert_allclose(
        box.angular_velocity, np.array([0.0, 3.0, 0.0]) * (1.0 - damping / 3.0) ** t, rtol=1e-12
    )


def test_speed_limits_scale_fast_bodies_down_keeping_direction():
    world, fast = _free_box()
    fast.linear_velocity = [300.0, 0.0, -400.0]  # 500 m/s > MAX_LINEAR_SPEED = 200 m/s
    fast.angular_velocity = [0.0, 600.0, 800.0]  # 1000 rad/s > MAX_ANGULAR_SPEED = 100 rad/s
    world.step_physics(H)
    np.testing.assert_allclose(fast.linear_velocity, [120.0, 0.0, -160.0], rtol=1e-12)
    np.testing.assert_allclose(fast.angular_velocity, [0.0, 60.0, 80.0], rtol=1e-12, atol=1e-12)
    # the position advanced with the clamped speed: x = h v_clamped
    np.testing.assert_allclose(fast.translation, [120.0 * H, 0.0, -160.0 * H], rtol=1e-12)


@pytest.mark.parametrize("component", [40.0, 90.0, 115.0])
def test_speeds_below_the_limits_are_untouched(component):
    # |v| = sqrt(3) * component < 200 m/s and |w| = component / 2 * sqrt(3) < 100 rad/s
    world, box = _free_box()
    box.linear_velocity = [component, -component, component]
    box.angular_velocity = [component / 2.0] * 3  # a cube: w stays constant
    world.step_physics(H)
    np.testing.assert_array_equal(box.linear_velocity, [component, -component, component])
    np.testing.assert_allclose(box.angular_velocity, [component / 2.0] * 3, rtol=1e-12)


def _euler_reference(inertia, w0, t_end):
    """Torque-free Euler equations in the body frame, integrated to 1e-11 (scipy)."""
    i1, i2, i3 = inertia

    def rhs(_t, w):
        # I1 w1' = (I2 - I3) w2 w3, and cyclic
        return [
            (i2 - i3) * w[1] * w[2] / i1,
            (i3 - i1) * w[2] * w[0] / i2,
            (i1 - i2) * w[0] * w[1] / i3,
        ]

    return solve_ivp(rhs, (0.0, t_end), w0, rtol=1e-11, atol=1e-12, dense_output=True)


def _sign_changes(times, values):
    return times[1:][np.sign(values[1:]) != np.sign(values[:-1])]


def test_asymmetric_box_flips_as_the_dzhanibekov_effect_predicts():
    # Half extents (0.1, 0.2, 0.3) m: the y axis is the intermediate principal axis. A spin
    # of 5 rad/s about it with a 1 % perturbation is unstable: the body flips over (body-frame
    # w_y changes sign) periodically. Flip times follow Euler's equations; the discrete step
    # drifts by ~1.5 % of the period in 20 s, so 3 % + one sample (1/15 s) is the tolerance.
    world, box = _free_box(half=(0.1, 0.2, 0.3))
    w0 = np.array([0.05, 5.0, 0.0])
    box.angular_velocity = w0
    inertia = np.asarray(box.intertia_diagonal)
    e0 = 0.5 * np.sum(inertia * w0**2)
    frame = 4.0 / 60.0
    times, w_body, energy, momentum = [], [], [], []
    for k in range(1, 300 + 1):  # 20 s
        world.step_physics(frame)
        r = np.asarray(box.rotation.to_matrix())
        w = np.asarray(box.angular_velocity)
        wb = r.T @ w  # body-frame angular velocity
        times.append(k * frame)
        w_body.append(wb)
        energy.append(0.5 * np.sum(inertia * wb**2))
        momentum.append(r @ (inertia * wb))  # world L = R I w_body
    times, w_body, energy = np.array(times), np.array(w_body), np.array(energy)

    # energy: never above the start (the update scales w down when it would rise), and
    # not lost either: a correct half-step orientation keeps 99.9 % of it over 20 s
    assert energy.max() <= e0 * (1.0 + 1e-12)
    assert np.all(np.diff(energy) <= 1e-12 * e0)
    assert energy.min() >= 0.995 * e0
    # world angular momentum held fixed (the energy scaling moves it by ~1e-4 relative)
    l0 = inertia * w0  # the body starts at the identity rotation
    np.testing.assert_allclose(momentum, np.broadcast_to(l0, (300, 3)), atol=1e-3 * l0[1])
    # the scaling only ever takes energy away: |L| never grows (a step that lost energy
    # keeps its w = I_w^-1 L, it is not scaled back up)
    size = np.linalg.norm(momentum, axis=1)
    assert size[0] <= np.linalg.norm(l0) * (1.0 + 1e-12)
    assert np.all(np.diff(size) <= 1e-12 * size[0])

    reference = _euler_reference(inertia, w0, times[-1])
    fine = np.linspace(0.0, times[-1], 200_001)
    expected = _sign_changes(fine, reference.sol(fine)[1])
    observed = _sign_changes(times, w_body[:, 1])
    assert len(expected) == 4  # flips at ~2.3, 7.0, 11.7, 16.4 s
    assert len(observed) == len(expected)
    np.testing.assert_allclose(observed, expected, rtol=0.03, atol=frame)
