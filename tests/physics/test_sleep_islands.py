"""Who falls asleep and who is woken: thresholds, islands through the floor, kinematic pushers.

A dynamic body rests while |v| < 0.05 m/s and |w| < 0.1 rad/s; an island of bodies joined
by dynamic-dynamic contacts sleeps once all its bodies rested 0.5 s, with its velocities
zeroed. Static and kinematic bodies (the floor, a pusher) never join islands.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import add, make_world, register_primitive, run

from engine.physics import MotionType
from engine.physics.core import settings

FRAME = 1.0 / 60.0


def _drifting_box(linear, angular):
    """A cube floating in zero gravity (no floor, no damping) with the given velocities."""
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    handle = register_primitive(templates, linear_damping=0.0, angular_damping=0.0)
    box = add(world, templates, handle, [0.0, 0.0, 0.0])
    box.linear_velocity = linear
    box.angular_velocity = angular
    return world, box


@pytest.mark.parametrize(
    "linear, angular",
    [([0.07, 0.0, 0.0], [0.0, 0.0, 0.0]), ([0.0, 0.0, 0.0], [0.0, 0.15, 0.0])],
)
def test_a_body_moving_above_a_sleep_threshold_keeps_moving(linear, angular):
    # 0.07 m/s > 0.05 m/s, 0.15 rad/s > 0.1 rad/s: not resting, so never put to sleep
    world, box = _drifting_box(linear, angular)
    run(world, 2.0)
    assert box.awake
    np.testing.assert_allclose(box.linear_velocity, linear, atol=1e-12)
    np.testing.assert_allclose(box.angular_velocity, angular, atol=1e-12)
    np.testing.assert_allclose(box.translation, np.array(linear) * world.get_world_time())


@pytest.mark.parametrize(
    "linear, angular",
    [
        ([0.03, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ([0.0, 0.0, 0.0], [0.0, 0.05, 0.0]),
        ([0.0, -0.04, 0.0], [0.0, 0.0, -0.08]),
    ],
)
def test_a_slow_body_sleeps_after_the_rest_time_with_its_velocities_zeroed(linear, angular):
    world, box = _drifting_box(linear, angular)
    run(world, settings.TIME_TO_SLEEP - 0.1)
    assert box.awake  # rested 0.4 s < 0.5 s
    run(world, 0.2)
    assert not box.awake
    np.testing.assert_array_equal(box.linear_velocity, [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(box.angular_velocity, [0.0, 0.0, 0.0])
    position, rotation = np.asarray(box.translation), box.rotation
    run(world, 1.0)  # asleep: it does not move any more
    np.testing.assert_array_equal(box.translation, position)
    assert box.rotation == rotation


def test_a_box_landing_on_the_floor_does_not_wake_a_sleeper_two_meters_away():
    # the floor is static: it does not join the two boxes into one island
    world, templates = make_world()
    handle = register_primitive(templates)
    sleeper = add(world, templates, handle, [0.0, 0.1, 0.0])
    run(world, 0.7)
    assert not sleeper.awake
    dropped = add(world, templates, handle, [2.0, 0.5, 0.0])
    awake_frames = 0
    for _ in range(60):  # it falls, lands and bounces within 1 s
        world.step_physics(FRAME)
        awake_frames += sleeper.awake
    assert dropped.translation[1] < 0.11  # it landed
    assert awake_frames == 0


def test_a_box_pushed_slowly_by_a_kinematic_body_stays_awake_and_moves_with_it():
    # The pusher moves at 0.03 m/s, below the 0.05 m/s sleep threshold: the pushed box is
    # slow but not resting; it is carried along the whole time (no sleep, no lag).
    world, templates = make_world(stage_friction=0.4)
    handle = register_primitive(templates)
    pushed = add(world, templates, handle, [0.0, 0.1, 0.0])
    run(world, 0.7)
    assert not pushed.awake
    pusher = add(world, templates, handle, [-0.205, 0.1, 0.0])  # 5 mm gap
    pusher.motion_type = MotionType.KINEMATIC
    control = pusher.velocity_control
    control.controlling_lin_vel = True
    control.linear_velocity = [0.03, 0.0, 0.0]
    asleep_frames = 0
    for _ in range(120):  # 2 s: contact after ~0.17 s, then 5.5 cm of pushing
        world.step_physics(FRAME)
        in_contact = pusher.translation[0] > -0.2 + 1e-3  # 1 mm past first touch
        asleep_frames += in_contact and not pushed.awake
    assert asleep_frames == 0
    # the pushed box keeps touching the pusher: its center 0.2 m ahead (within 5 mm)
    gap = pushed.translation[0] - pusher.translation[0]
    assert 0.2 - 5e-3 <= gap <= 0.2 + 5e-3
    assert pusher.translation[0] == pytest.approx(-0.205 + 0.03 * 2.0, abs=1e-9)


def test_a_kinematic_body_moving_elsewhere_does_not_keep_a_resting_stack_awake():
    # a kinematic box slides along the floor 3 m away: the two stacked boxes at the origin
    # (one island through their contact) fall asleep as if it were not there
    world, templates = make_world()
    handle = register_primitive(templates)
    lower = add(world, templates, handle, [0.0, 0.1, 0.0])
    upper = add(world, templates, handle, [0.0, 0.3, 0.0])
    kinematic = add(world, templates, handle, [3.0, 0.1, 0.0])
    kinematic.motion_type = MotionType.KINEMATIC
    kinematic.velocity_control.controlling_lin_vel = True
    kinematic.velocity_control.linear_velocity = [0.0, 0.0, 0.5]
    run(world, 1.2)
    assert not lower.awake and not upper.awake
    assert kinematic.translation[2] == pytest.approx(0.6, abs=1e-9)  # it kept moving


def test_a_box_on_a_still_kinematic_platform_falls_asleep():
    # a kinematic platform that does not move is a floor: the box on it rests and sleeps
    world, templates = make_world(floor=False)
    handle = register_primitive(templates)
    platform = add(world, templates, register_primitive(templates, half=(1.0, 0.1, 1.0)), [0, 0, 0])
    platform.motion_type = MotionType.KINEMATIC
    box = add(world, templates, handle, [0.0, 0.2, 0.0])
    run(world, 1.0)
    assert not box.awake
    assert box.translation[1] == pytest.approx(0.2, abs=5e-3)  # resting on the platform


def test_a_box_woken_by_the_user_stays_awake_for_the_rest_time():
    # waking restarts the rest timer: a resting box needs TIME_TO_SLEEP again to sleep
    world, templates = make_world()
    box = add(world, templates, register_primitive(templates), [0.0, 0.1, 0.0])
    run(world, 1.0)
    assert not box.awake
    box.awake = True
    run(world, settings.TIME_TO_SLEEP - 0.1)
    assert box.awake
    run(world, 0.2)
    assert not box.awake


def test_a_box_hitting_a_sleeping_box_conserves_momentum():
    # zero gravity, no floor: a cube at 1 m/s hits an equal cube that was put to sleep. The
    # sleeper is woken in the step of the hit (it is not a wall for one step), so the
    # collision conserves momentum: m v_a + m v_b = m * 1 m/s, and the sleeper moves off.
    world, templates = make_world(floor=False, gravity=(0.0, 0.0, 0.0))
    handle = register_primitive(templates, linear_damping=0.0, angular_damping=0.0)
    mover = add(world, templates, handle, [0.0, 0.0, 0.0])
    sleeper = add(world, templates, handle, [0.3, 0.0, 0.0])  # 0.1 m gap
    sleeper.awake = False
    mover.linear_velocity = [1.0, 0.0, 0.0]
    run(world, 0.5)
    assert sleeper.awake and sleeper.linear_velocity[0] > 0.1
    total = np.asarray(mover.linear_velocity) + np.asarray(sleeper.linear_velocity)
    np.testing.assert_allclose(total, [1.0, 0.0, 0.0], atol=1e-6)


def test_removing_the_lower_box_of_a_sleeping_stack_lets_the_upper_box_fall():
    world, templates = make_world()
    handle = register_primitive(templates)
    lower = add(world, templates, handle, [0.0, 0.1, 0.0])
    upper = add(world, templates, handle, [0.0, 0.3, 0.0])
    run(world, 1.2)
    assert not lower.awake and not upper.awake
    world.rigid_object_manager.remove_object_by_id(lower.object_id)
    assert upper.awake  # its support is gone: the island around it was woken
    run(world, 1.0)
    assert upper.translation[1] == pytest.approx(0.1, abs=5e-3)  # resting on the floor now


def test_a_box_under_a_spinning_box_stays_awake_in_its_island():
    # The upper box spins at 1 rad/s about the vertical (dynamic velocity control) on a
    # resting lower box. Their contact joins them into one island, which rests only when
    # all its bodies do: the lower box, itself still, is awake every frame of 2 s.
    world, templates = make_world()
    handle = register_primitive(templates)
    lower = add(world, templates, handle, [0.0, 0.1, 0.0])
    upper = add(world, templates, handle, [0.0, 0.3, 0.0])
    control = upper.velocity_control
    control.controlling_ang_vel = True
    control.angular_velocity = [0.0, 1.0, 0.0]
    asleep_frames = 0
    for _ in range(120):
        world.step_physics(FRAME)
        asleep_frames += not lower.awake
    assert asleep_frames == 0
    assert upper.awake
    assert np.linalg.norm(np.asarray(lower.translation) - [0.0, 0.1, 0.0]) < 5e-3  # still
