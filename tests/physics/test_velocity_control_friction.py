"""A DYNAMIC body under velocity control on a floor with friction (Habitat's semantics).

Habitat-sim (``BulletPhysicsManager::stepPhysics``) sets a dynamic object's controlled
velocity once per ``step_physics(dt)`` call, then lets Bullet run the fixed steps of ``dt``:
gravity and contacts act in between, and a box sliding on a floor loses ``mu g`` of speed
per second (Coulomb friction, pair ``mu`` = the product of the two coefficients).

With fixed steps of ``h``, semi-implicit Euler and no damping, a box set to ``v0`` moves
``n`` steps as

    v_k = max(v0 - k mu g h, 0),   x_n = h * sum_{k=1..n} v_k

so a controller that sets the velocity once per 0.1 s call averages far below ``v0`` on a
high-friction floor (0.21 m/s instead of 0.5 for mu = 0.5), while one that sets it before
every fixed step loses only ``mu g h`` (0.04 m/s). Without friction the box keeps ``v0``.
"""

from __future__ import annotations

import numpy as np
import pytest

import engine as habitat_sim

MotionType = habitat_sim.physics.MotionType
GRAVITY = 9.8
HALF = 0.1  # m: half size of the box


def sliding_box(box_friction: float, floor_friction: float = 1.0):
    """A 1 kg box of 0.2 m resting on a large static slab, damping off."""
    sim = habitat_sim.Simulator(habitat_sim.Configuration())
    templates, objects = sim.get_object_template_manager(), sim.get_rigid_object_manager()
    unit_cube = templates.get_template_handles("cubeSolid")[0]
    slab_template = templates.get_template_by_handle(unit_cube).copy()
    slab_template.scale = [10.0, 0.1, 10.0]
    slab = objects.add_object_by_template_id(templates.register_template(slab_template, "slab"))
    slab.translation = [0.0, -0.1, 0.0]
    slab.motion_type = MotionType.STATIC
    slab.friction_coefficient = floor_friction
    box_template = templates.get_template_by_handle(unit_cube).copy()
    box_template.scale, box_template.mass = [HALF] * 3, 1.0
    box = objects.add_object_by_template_id(templates.register_template(box_template, "box"))
    box.translation = [0.0, HALF, 0.0]
    box.friction_coefficient = box_friction
    box.linear_damping = box.angular_damping = 0.0
    for _ in range(20):  # settle on the slab
        sim.step_physics(1.0 / 60.0)
    control = box.velocity_control
    control.controlling_lin_vel = True
    control.linear_velocity = [0.5, 0.0, 0.0]
    return sim, box


def coulomb_distance(v0: float, mu: float, h: float, n: int) -> float:
    """Distance of a box set to ``v0`` after ``n`` steps of ``h`` under friction ``mu g``."""
    speeds = np.maximum(v0 - mu * GRAVITY * h * np.arange(1, n + 1), 0.0)
    return float(h * speeds.sum())


def drive(sim, box, seconds: float, call_dt: float) -> list[tuple[float, int]]:
    """Call ``step_physics(call_dt)`` for ``seconds``; (x distance, fixed steps) per call."""
    h = sim.get_physics_time_step()
    moves = []
    for _ in range(round(seconds / call_dt)):
        x0, t0 = float(box.translation[0]), sim.get_world_time()
        sim.step_physics(call_dt)
        moves.append((float(box.translation[0]) - x0, round((sim.get_world_time() - t0) / h)))
    return moves


@pytest.mark.parametrize("box_friction", [0.5, 0.2, 0.05])
def test_velocity_set_once_per_call_then_friction_decelerates(box_friction):
    sim, box = sliding_box(box_friction)
    h = sim.get_physics_time_step()
    try:
        moves = drive(sim, box, 1.0, 0.1)
    finally:
        sim.close()
    for distance, steps in moves:
        assert steps in (12, 13)  # 0.1 s of 0.008 s steps
        expected = coulomb_distance(0.5, box_friction, h, steps)
        assert distance == pytest.approx(expected, rel=0.01)
    mean_speed = sum(d for d, _ in moves) / 1.0
    if box_friction == 0.5:  # set once per 0.1 s: it stops before the next call
        assert mean_speed < 0.25


def test_velocity_set_before_every_step_loses_only_one_step_of_friction():
    sim, box = sliding_box(0.5)
    h = sim.get_physics_time_step()
    try:
        moves = drive(sim, box, 0.4, h)
    finally:
        sim.close()
    assert all(steps == 1 for _, steps in moves)
    speeds = np.array([distance / h for distance, _ in moves])
    np.testing.assert_allclose(speeds, 0.5 - 0.5 * GRAVITY * h, rtol=0.01)


def test_without_friction_the_box_keeps_the_commanded_speed():
    sim, box = sliding_box(0.0)
    try:
        moves = drive(sim, box, 1.0, 0.1)
        end_velocity = np.asarray(box.linear_velocity)
    finally:
        sim.close()
    world_time = sum(steps for _, steps in moves) * 0.008
    assert sum(d for d, _ in moves) == pytest.approx(0.5 * world_time, rel=1e-3)
    np.testing.assert_allclose(end_velocity, [0.5, 0.0, 0.0], atol=1e-3)
