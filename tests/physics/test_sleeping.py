"""Sleeping rules: overlapping bodies stay awake, user-put-to-sleep bodies stay asleep."""

from __future__ import annotations

import numpy as np

from engine import mn
from engine.physics.core import settings
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

from .helpers import add, make_world, register_primitive, run


def _overlapping_pair(position_correction: bool):
    """Box B placed 3 cm deep into box A, which rests on the floor; both at rest."""
    world, templates = make_world()
    world.settings.position_correction = position_correction
    handle = register_primitive(templates)
    lower = add(world, templates, handle, [0.0, 0.1, 0.0])
    upper = add(world, templates, handle, [0.0, 0.27, 0.0])  # 0.2 m boxes: 3 cm overlap
    return world, lower, upper


def test_a_pair_overlapping_deeper_than_the_limit_does_not_fall_asleep():
    # without position correction nothing separates them and nothing moves either: only
    # the penetration rule keeps the island awake
    world, lower, upper = _overlapping_pair(position_correction=False)
    run(world, 2.0)
    gap = upper.translation[1] - lower.translation[1]
    assert gap < 0.2 - settings.SLEEP_MAX_PENETRATION
    assert upper.awake and lower.awake


def test_an_overlapping_pair_separates_then_sleeps():
    world, lower, upper = _overlapping_pair(position_correction=True)
    run(world, 3.0)
    gap = upper.translation[1] - lower.translation[1]
    assert gap > 0.2 - settings.PENETRATION_SLOP - 1e-3  # pushed apart to within the slop
    assert not upper.awake and not lower.awake


def test_a_body_put_to_sleep_stays_asleep_until_disturbed():
    world, templates = make_world()
    handle = register_primitive(templates)
    resting = add(world, templates, handle, [0.0, 0.1, 0.0])
    falling = add(world, templates, handle, [1.0, 1.0, 0.0])  # keeps the world awake
    resting.awake = False
    run(world, 0.5)
    assert not resting.awake and falling.awake
    resting.apply_force([5.0, 0.0, 0.0], [0.0, 0.0, 0.0])  # a force wakes it
    assert resting.awake


def test_three_donuts_settle_and_sleep_on_the_plane(test_assets):
    """The 38 g donut hull (964 vertices) rests on the stage within the slop and sleeps."""
    config = SimulatorConfiguration(scene_id=str(test_assets / "scenes" / "plane.glb"))
    with Simulator(Configuration(config)) as sim:
        templates = sim.get_object_template_manager()
        templates.load_configs(str(test_assets / "objects"))
        handle = templates.get_template_handles("donut")[0]
        rng = np.random.default_rng(0)
        donuts = []
        for k in range(3):
            donut = sim.get_rigid_object_manager().add_object_by_template_handle(handle)
            donut.translation = [0.05 * k, 0.3 + 0.15 * k, 0.02 * k]
            q = rng.normal(size=4)
            donut.rotation = mn.Quaternion.from_xyzw(q / np.linalg.norm(q))
            donuts.append(donut)
        sim.step_physics(6.0)
        for donut in donuts:
            shape = sim._world.bodies.shapes[donut.object_id][0]
            rotation = np.asarray(donut.rotation.to_matrix())
            lowest = (shape.hull_vertices @ rotation.T + np.asarray(donut.translation))[:, 1]
            assert lowest.min() > -0.006  # the plane is y = 0; slop 4 mm + one step of sinking
            assert not donut.awake
