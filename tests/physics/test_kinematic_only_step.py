"""A world with no DYNAMIC body, no manifold and no constraint skips its step's stages
(``PhysicsWorld._nothing_to_simulate``: the tutorial's robot driven over the navmesh). The
world must come out bit for bit as the full step leaves it, and a dynamic body added later
must move exactly as in a world that never skipped."""

from __future__ import annotations

import pytest
from helpers import add, make_world, register_primitive

import engine as habitat_sim
from engine.physics.world import PhysicsWorld

MotionType = habitat_sim.physics.MotionType


def slab_and_robot(vectorized: bool = True):
    """A static slab (top at y = 0) and a kinematic cube driven over it by velocity control,
    on the batched or the reference path; returns (world, templates, the cube's handle)."""
    world, templates = make_world(floor=False)
    world.settings.use_vectorized = vectorized
    slab = register_primitive(templates, half=(6.0, 0.1, 6.0), handle="slab")
    add(world, templates, slab, [0.0, -0.1, 0.0], motion_type=MotionType.STATIC)
    cube = register_primitive(templates, half=(0.1, 0.1, 0.1), handle="cube")
    robot = add(world, templates, cube, [0.0, 0.6, 0.0], motion_type=MotionType.KINEMATIC)
    control = robot.velocity_control
    control.controlling_lin_vel = control.controlling_ang_vel = True
    control.linear_velocity, control.angular_velocity = [0.5, -0.5, 0.0], [0.0, 1.0, 0.0]
    return world, templates, cube


def history(world, templates, cube) -> list[tuple[str, int, int]]:
    """World hash, broad-phase pairs and contact points after each of 100 steps: 40 with
    the robot alone, then with a box dropped onto the slab."""
    rows = []
    for step in range(100):
        if step == 40:
            add(world, templates, cube, [1.5, 0.5, 0.0])
        world.step_physics(1.0 / 60.0)
        rows.append(
            (
                world.state_hash(),
                world.get_physics_num_active_overlapping_pairs(),
                len(world.get_physics_contact_points()),
            )
        )
    return rows


@pytest.mark.parametrize("vectorized", [True, False])
def test_a_world_without_dynamic_bodies_skips_its_steps_bit_for_bit(monkeypatch, vectorized):
    skipped_steps = []
    original = PhysicsWorld._nothing_to_simulate

    def counting(self):
        skip = original(self)
        skipped_steps.append(skip)
        return skip

    monkeypatch.setattr(PhysicsWorld, "_nothing_to_simulate", counting)
    skipped = history(*slab_and_robot(vectorized))
    assert skipped_steps.count(True) >= 80  # the robot's 40 frames, two fixed steps each
    assert skipped_steps.count(False) >= 100  # with the box
    monkeypatch.setattr(PhysicsWorld, "_nothing_to_simulate", lambda self: False)
    full = history(*slab_and_robot(vectorized))
    assert skipped == full
    assert all(pairs == 0 and points == 0 for _, pairs, points in skipped[:40])
    assert all(points > 0 for _, _, points in skipped[-10:])  # the box rests on the slab


@pytest.mark.parametrize("what", ["dynamic body", "manifold", "constraint"])
def test_a_step_is_skipped_only_without_dynamic_bodies_manifolds_and_constraints(what):
    world, templates, cube = slab_and_robot()
    assert world._nothing_to_simulate()
    box = add(world, templates, cube, [1.5, 0.12, 0.0])
    assert not world._nothing_to_simulate()  # a dynamic body
    if what == "manifold":
        for _ in range(10):
            world.step_physics(1.0 / 60.0)  # lands on the slab: a manifold
        box.motion_type = MotionType.KINEMATIC  # no dynamic body left, the manifold stays
        assert len(world.manifolds) > 0
        assert not world._nothing_to_simulate()
    elif what == "constraint":
        settings = habitat_sim.physics.RigidConstraintSettings()
        settings.object_id_a = box.object_id
        world.constraints.create(world, settings)
        box.motion_type = MotionType.KINEMATIC
        assert not world._nothing_to_simulate()
    else:
        box.motion_type = MotionType.KINEMATIC
        assert world._nothing_to_simulate()
