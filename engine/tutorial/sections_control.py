"""Tutorial sections that drive a kinematic clamp: by hand, then by velocity control.

Port of the ``[kinematic_update]``, ``[velocity_control]`` and ``[local_velocity_control]``
blocks of Habitat-sim's ``examples/tutorials/nb_python/managed_rigid_object_tutorial.py``
(MIT License, Copyright (c) Meta Platforms, Inc. and its affiliates).

The three sections share one KINEMATIC clamp. Each returns the clamp's rigid state at the
start and at the end and the number of ``step_physics(1/60)`` calls of each phase, so a test
can replay the commands: kinematic velocity control integrates once per call with explicit
Euler (see :class:`engine.physics.VelocityControl`)::

    t1 = t0 + v dt                  (v rotated by q0 when lin_vel_is_local)
    q1 = normalize(dq(|w| dt, w/|w|) * q0)   (w rotated by q0 when ang_vel_is_local)
"""

from __future__ import annotations

import engine as habitat_sim
from engine import mn
from engine.tutorial.context import SectionResult, TutorialContext, finish, pose, simulate
from engine.tutorial.recording import VideoSpec
from engine.tutorial.scene_setup import FRAME_DT


# ------------------------------------------------------------------------------------------
# [kinematic_update]: set the clamp's state by hand before every step.
# ------------------------------------------------------------------------------------------
def kinematic_update(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("kinematic_update"))
    start_time = ctx.sim.get_world_time()
    clamp_template_handle = ctx.obj_templates_mgr.get_template_handles(
        "data/objects/example_objects/largeclamp"
    )[0]
    clamp_obj = ctx.rigid_obj_mgr.add_object_by_template_handle(clamp_template_handle)
    clamp_obj.motion_type = habitat_sim.physics.MotionType.KINEMATIC
    clamp_obj.translation = [0.8, 0.2, 0.5]
    ctx.shared["clamp_obj"] = clamp_obj
    clamp_start = pose(clamp_obj)

    while ctx.sim.get_world_time() < start_time + 1.0:
        # manually control the object's kinematic state
        clamp_obj.translation += [0.0, 0.0, 0.01]
        clamp_obj.rotation = (
            mn.Quaternion.rotation(mn.Rad(0.05), [-1.0, 0.0, 0.0]) * clamp_obj.rotation
        )
        recorder.step(FRAME_DT)

    outcomes = {"clamp_start": clamp_start, "clamp": pose(clamp_obj), "steps": recorder.frames}
    return finish("kinematic_update", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [velocity_control]: constant global linear and angular velocity, then reverse.
# ------------------------------------------------------------------------------------------
def velocity_control(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("velocity_control"))
    start_time = ctx.sim.get_world_time()
    clamp_obj = ctx.shared["clamp_obj"]
    clamp_start = pose(clamp_obj)

    # get object VelocityControl structure and setup control
    vel_control = clamp_obj.velocity_control
    vel_control.linear_velocity = [0.0, 0.0, -1.0]
    vel_control.angular_velocity = [4.0, 0.0, 0.0]
    vel_control.controlling_lin_vel = True
    vel_control.controlling_ang_vel = True

    steps_forward = simulate(recorder, dt=1.0)

    # reverse linear direction
    vel_control.linear_velocity = [0.0, 0.0, 1.0]

    steps_back = simulate(recorder, dt=1.0)

    outcomes = {
        "clamp_start": clamp_start,
        "clamp": pose(clamp_obj),
        "steps": [steps_forward, steps_back],
    }
    return finish("velocity_control", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [local_velocity_control]: the same control with velocities in the clamp's own frame.
# ------------------------------------------------------------------------------------------
def local_velocity_control(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("local_velocity_control"))
    start_time = ctx.sim.get_world_time()
    clamp_obj = ctx.shared["clamp_obj"]
    clamp_start = pose(clamp_obj)

    vel_control = clamp_obj.velocity_control
    vel_control.linear_velocity = [0.0, 0.0, 2.3]
    vel_control.angular_velocity = [-4.3, 0.0, 0.0]
    vel_control.lin_vel_is_local = True
    vel_control.ang_vel_is_local = True

    steps = simulate(recorder, dt=1.5)

    outcomes = {"clamp_start": clamp_start, "clamp": pose(clamp_obj), "steps": steps}
    ctx.rigid_obj_mgr.remove_all_objects()
    return finish("local_velocity_control", recorder, start_time, outcomes)
