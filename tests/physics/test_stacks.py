"""docs/physics.md, validation: stacks, pyramid, pile, anti-gravity hover."""

from __future__ import annotations

import numpy as np
from helpers import add, make_world, register_primitive, run

HALF = 0.1


def _box_template(world, templates, **fields):
    return register_primitive(templates, "cubeSolid", (HALF, HALF, HALF), **fields)


def test_ten_box_stack_stands_ten_seconds_with_small_drift():
    world, templates = make_world()
    handle = _box_template(world, templates)
    rng = np.random.default_rng(3)
    boxes = []
    for level in range(10):
        jitter = rng.uniform(-0.002, 0.002, size=2)  # 2 mm placement noise
        boxes.append(
            add(
                world,
                templates,
                handle,
                [jitter[0], HALF + 2 * HALF * level + 0.001 * level, jitter[1]],
            )
        )
    start = np.array([np.asarray(b.translation) for b in boxes])
    run(world, 10.0)
    end = np.array([np.asarray(b.translation) for b in boxes])
    lateral = np.linalg.norm((end - start)[:, [0, 2]], axis=1)
    assert lateral.max() < 0.01  # < 1 cm lateral drift (docs/physics.md)
    # still a stack: each box one box-height above the one below (2 mm slop per contact)
    np.testing.assert_allclose(np.diff(end[:, 1]), 2 * HALF, atol=5e-3)


def test_pyramid_of_base_six_stands_ten_seconds():
    world, templates = make_world()
    handle = _box_template(world, templates)
    boxes, start = [], []
    for level in range(6):
        for i in range(6 - level):
            x = (i - (5 - level) / 2) * (2 * HALF + 0.002)
            boxes.append(add(world, templates, handle, [x, HALF + level * (2 * HALF + 0.001), 0]))
    start = np.array([np.asarray(b.translation) for b in boxes])
    run(world, 10.0)
    end = np.array([np.asarray(b.translation) for b in boxes])
    assert np.abs(end - start).max() < 0.02  # pybullet's pyramid drifts up to 2 cm


def _pile(n_boxes, seconds, seed=0):
    world, templates = make_world()
    handle = _box_template(world, templates)
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n_boxes)))
    boxes = []
    for k in range(n_boxes):
        layer, cell = divmod(k, side * side)
        row, col = divmod(cell, side)
        position = [
            (col - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
            0.3 + 0.3 * layer + rng.uniform(0, 0.05),
            (row - side / 2) * 0.25 + rng.uniform(-0.03, 0.03),
        ]
        box = add(world, templates, handle, position)
        box.rotation = _random_rotation(rng)
        boxes.append(box)
    run(world, seconds)
    return world, boxes


def _random_rotation(rng):
    from engine import mn

    q = rng.normal(size=4)
    return mn.Quaternion.from_xyzw(q / np.linalg.norm(q))


def _check_settled_pile(world, boxes):
    assert all(not b.awake for b in boxes)
    heights = np.array([b.translation[1] for b in boxes])
    # a box's center is at least its half width above the floor minus 1 cm of overlap
    assert heights.min() > HALF - 0.01
    # no pair overlaps by more than 1 cm: measured by the deepest manifold point
    depths = [(p.contact_distance) for p in world.get_physics_contact_points()]
    assert min(depths) > -0.01


def test_small_pile_settles_without_overlap_and_sleeps():
    world, boxes = _pile(16, 8.0)
    _check_settled_pile(world, boxes)


def test_hundred_box_pile_settles_within_ten_seconds():
    world, boxes = _pile(100, 10.0)
    _check_settled_pile(world, boxes)


def test_anti_gravity_boxes_hover_and_spin_under_torque():
    world, templates = make_world(floor=False)
    handle = _box_template(world, templates)
    hover = add(world, templates, handle, [0.0, 1.0, 0.0])
    spinner = add(world, templates, handle, [1.0, 1.0, 0.0])
    gravity = np.asarray(world.get_gravity())
    for _ in range(3 * 60):
        for box in (hover, spinner):
            box.apply_force(-gravity * box.mass, [0.0, 0.0, 0.0])
        spinner.apply_torque([0.0, 0.01, 0.0])
        world.step_physics(1.0 / 60.0)
    assert np.linalg.norm(np.asarray(hover.translation) - [0.0, 1.0, 0.0]) < 1e-3  # < 1 mm
    assert np.linalg.norm(np.asarray(spinner.translation) - [1.0, 1.0, 0.0]) < 1e-3
    assert spinner.angular_velocity[1] > 0.5  # tau / I = 1.5 rad/s^2, damped by 0.2/s
