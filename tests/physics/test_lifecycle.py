"""Issue 10: adding and removing objects leaks nothing; ids are recycled as in Habitat.

Habitat's ``PhysicsManager::allocateObjectID`` pops the most recently freed id from its
``recycledObjectIDs_`` stack before it hands out a new one; rigidsim's body slots follow
the same rule, so the body arrays stay as long as the most objects ever alive at once.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive

from engine.physics import DeadObjectError


@pytest.fixture()
def scene():
    world, templates = make_world()
    return world, templates, register_primitive(templates, half=(0.1,) * 3)


def test_freed_ids_are_reused_most_recent_first_like_habitat(scene):
    world, templates, handle = scene
    rom = world.rigid_object_manager
    ids = [add(world, templates, handle, [0, 0.1 + 0.3 * k, 0]).object_id for k in range(4)]
    assert ids == [1, 2, 3, 4]
    rom.remove_object_by_id(2)
    rom.remove_object_by_id(3)
    new = [add(world, templates, handle, [1, 0.1 + 0.3 * k, 0]).object_id for k in range(3)]
    assert new == [3, 2, 5]  # the recycled-id stack first (last freed on top), then a new id


def test_stale_wrapper_stays_dead_when_its_slot_is_reused(scene):
    world, templates, handle = scene
    rom = world.rigid_object_manager
    old = add(world, templates, handle, [0, 0.5, 0])
    old.linear_velocity = [1.0, 0.0, 0.0]
    rom.remove_object_by_id(old.object_id)
    new = add(world, templates, handle, [2.0, 0.1, 0.0])
    assert new.object_id == old._index  # the same slot...
    assert not old.is_alive and new.is_alive  # ...but the old wrapper stays dead
    with pytest.raises(DeadObjectError):
        _ = old.translation
    assert rom.get_object_by_id(new.object_id) is new
    # the reused slot starts fresh: no velocity, awake, not asleep-timed
    np.testing.assert_array_equal(np.asarray(new.linear_velocity), 0.0)
    assert new.awake
    assert world.bodies.body_sleep_time[new.object_id] == 0.0
    for _ in range(30):
        world.step_physics(1.0 / 60.0)
    np.testing.assert_allclose(np.asarray(new.translation), [2.0, 0.1, 0.0], atol=2e-3)


def _sizes(world) -> tuple:
    """Every per-body container of the world, by length."""
    objects, sync = world.collision_objects, world.node_sync
    return (
        world.bodies.count,
        world.bodies.capacity,
        len(objects.shape_objects),
        len(objects.probe_objects),
        len(world.nodes),
        len(world.velocity_controls),
        len(world.render_meshes),
        len(world.creation_state),
        len(sync._node_pose),
        len(sync._node_stamp),
        len(world.manifolds),
        len(world.manifolds.count),
    )


def test_ten_rounds_of_adding_and_removing_objects_leave_every_container_bounded(scene):
    world, templates, handle = scene
    rom = world.rigid_object_manager
    sizes = []
    for round_ in range(10):
        objects = [
            add(world, templates, handle, [0.25 * (k % 10), 0.1 + 0.25 * (k // 10), 0.25 * round_])
            for k in range(60)
        ]
        world.step_physics(1.0 / 60.0)  # make contacts and manifolds
        for obj in objects:
            rom.remove_object_by_id(obj.object_id)
        world.step_physics(1.0 / 60.0)
        sizes.append(_sizes(world))
        assert rom.get_num_objects() == 0
        assert not world.bodies.body_alive[1 : world.bodies.count].any()
    assert len(set(sizes)) == 1  # identical after every round
    count, capacity, *per_body = sizes[0]
    assert count == 61 and capacity <= 128  # the stage + the 60 slots of one round
    # fcl and probe objects of the stage only: nothing is kept for dead bodies
    assert per_body[:9] == [1, 1, 0, 0, 0, 0, 0, 0, 0]
