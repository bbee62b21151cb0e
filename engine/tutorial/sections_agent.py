"""Tutorial sections with an embodied agent: a dynamic robot, then a kinematic one on the navmesh.

Port of the ``[embodied_agent]`` and ``[embodied_agent_navmesh]`` blocks of Habitat-sim's
``examples/tutorials/nb_python/managed_rigid_object_tutorial.py`` (MIT License, Copyright (c)
Meta Platforms, Inc. and its affiliates).

The locobot is added with the agent's scene node as its root node, so the agent (and its
cameras) moves with the robot. In ``embodied_agent`` the robot is DYNAMIC and its own
VelocityControl overwrites its velocity each step while gravity and contacts act. In the
navmesh sections it is KINEMATIC: a separate VelocityControl integrates a target state,
``sim.step_filter`` snaps it to the navmesh (sliding along walls or stopping at them, by
``sim.config.sim_cfg.allow_sliding``) and the result is set on the robot.
"""

from __future__ import annotations

import os
from typing import Any

import engine as habitat_sim
from engine.tutorial.context import (
    SectionResult,
    TutorialContext,
    finish,
    pose,
    simulate,
    vec,
    world_y_extent,
)
from engine.tutorial.recording import VideoSpec
from engine.tutorial.scene_setup import FRAME_DT

ROBOT_START = [1.75, -1.02, 0.4]


def _add_locobot(ctx: TutorialContext) -> Any:
    """Load the locobot template and add it with the agent's scene node attached."""
    # load the locobot_merged asset
    locobot_template_id = ctx.obj_templates_mgr.load_configs(
        str(os.path.join(ctx.data_path, "objects/locobot_merged"))
    )[0]
    # add robot object to the scene with the agent/camera SceneNode attached
    return ctx.rigid_obj_mgr.add_object_by_template_id(
        locobot_template_id, ctx.sim.agents[0].scene_node
    )


# ------------------------------------------------------------------------------------------
# [embodied_agent]: a dynamic robot driven by its own VelocityControl.
# ------------------------------------------------------------------------------------------
def embodied_agent(ctx: TutorialContext) -> SectionResult:
    # rigidsim: recorded from the 3rd-person camera with the 1st-person color and depth
    # overlays, as the tutorial's published robot_control video shows (the script's
    # make_video call names the 1st-person camera)
    recorder = ctx.new_recorder(
        VideoSpec("robot_control", "rgba_camera_3rdperson", "color", _overlay_settings(ctx.sim))
    )
    start_time = ctx.sim.get_world_time()
    locobot = _add_locobot(ctx)
    locobot.translation = ROBOT_START

    vel_control = locobot.velocity_control
    vel_control.linear_velocity = [0.0, 0.0, -1.0]
    vel_control.angular_velocity = [0.0, 2.0, 0.0]

    # simulate robot dropping into place
    steps = [simulate(recorder, dt=1.5)]
    settled = {**pose(locobot), "y_extent": world_y_extent(locobot)}

    vel_control.controlling_lin_vel = True
    vel_control.controlling_ang_vel = True
    vel_control.lin_vel_is_local = True
    vel_control.ang_vel_is_local = True
    # simulate forward and turn
    steps.append(simulate(recorder, dt=1.0))

    vel_control.controlling_lin_vel = False
    vel_control.angular_velocity = [0.0, 1.0, 0.0]
    # simulate turn only
    steps.append(simulate(recorder, dt=1.5))

    vel_control.angular_velocity = [0.0, 0.0, 0.0]
    vel_control.controlling_lin_vel = True
    vel_control.controlling_ang_vel = True
    # simulate forward only with damped angular velocity
    steps.append(simulate(recorder, dt=1.0))

    vel_control.angular_velocity = [0.0, -1.25, 0.0]
    # simulate forward and turn
    steps.append(simulate(recorder, dt=2.0))

    vel_control.controlling_ang_vel = False
    vel_control.controlling_lin_vel = False
    # simulate settling
    steps.append(simulate(recorder, dt=3.0))

    outcomes: dict[str, Any] = {
        "settled": settled,
        "robot": {**pose(locobot), "y_extent": world_y_extent(locobot)},
        "agent_position": vec(ctx.sim.agents[0].get_state().position),
        "steps": steps,
    }
    # remove the agent's body while preserving the SceneNode
    ctx.rigid_obj_mgr.remove_object_by_id(locobot.object_id, delete_object_node=False)
    outcomes["robot_is_alive_after_removal"] = bool(locobot.is_alive)
    outcomes["agent_position_after_removal"] = vec(ctx.sim.agents[0].get_state().position)
    return finish("embodied_agent", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [embodied_agent_navmesh]: a kinematic robot snapped to the navmesh, with and without sliding.
# ------------------------------------------------------------------------------------------
def _overlay_settings(sim: Any) -> list[dict[str, Any]]:
    """The tutorial's two 1st-person overlays (color, depth) at a quarter of the frame."""
    sensor_dims = sim.get_agent(0).agent_config.sensor_specifications[0].resolution
    overlay_dims = (int(sensor_dims[1] / 4), int(sensor_dims[0] / 4))
    return [
        {
            "obs": "rgba_camera_1stperson",
            "type": "color",
            "dims": overlay_dims,
            "pos": (10, 10),
            "border": 2,
        },
        {
            "obs": "depth_camera_1stperson",
            "type": "depth",
            "dims": overlay_dims,
            "pos": (10, 30 + overlay_dims[1]),
            "border": 2,
        },
    ]


def _kinematic_locobot(ctx: TutorialContext) -> tuple[Any, Any, Any]:
    """The navmesh sections' robot (created once), its initial rotation and its controller."""
    if "locobot" not in ctx.shared:
        locobot = _add_locobot(ctx)
        initial_rotation = locobot.rotation
        # set the agent's body to kinematic since we will be updating position manually
        locobot.motion_type = habitat_sim.physics.MotionType.KINEMATIC
        # create and configure a new VelocityControl structure
        # Note: this is NOT the object's VelocityControl, so it will not be consumed
        # automatically in sim.step_physics
        vel_control = habitat_sim.physics.VelocityControl()
        vel_control.controlling_lin_vel = True
        vel_control.lin_vel_is_local = True
        vel_control.controlling_ang_vel = True
        vel_control.ang_vel_is_local = True
        vel_control.linear_velocity = [0.0, 0.0, -1.0]
        ctx.shared["locobot"] = (locobot, initial_rotation, vel_control)
    return ctx.shared["locobot"]


def embodied_agent_navmesh(ctx: TutorialContext, allow_sliding: bool) -> SectionResult:
    """One pass of the navmesh experiment (the tutorial's loop body; sliding pass first)."""
    video_prefix = "robot_control_sliding" if allow_sliding else "robot_control_no_sliding"
    video = VideoSpec(video_prefix, "rgba_camera_3rdperson", "color", _overlay_settings(ctx.sim))
    recorder = ctx.new_recorder(video)
    start_time = ctx.sim.get_world_time()
    locobot, initial_rotation, vel_control = _kinematic_locobot(ctx)
    # reset robot state
    locobot.translation = ROBOT_START
    locobot.rotation = initial_rotation
    vel_control.angular_velocity = [0.0, 0.0, 0.0]
    ctx.sim.config.sim_cfg.allow_sliding = allow_sliding

    steps = _drive_on_navmesh(ctx, recorder, locobot, vel_control, dt=6.0)

    outcomes = {
        "robot": pose(locobot),
        "navmesh_loaded": bool(ctx.sim.pathfinder.is_loaded),
        "allow_sliding": allow_sliding,
        **steps,
    }
    name = "embodied_agent_navmesh_" + ("sliding" if allow_sliding else "no_sliding")
    return finish(name, recorder, start_time, outcomes)


def _drive_on_navmesh(
    ctx: TutorialContext, recorder: Any, locobot: Any, vel_control: Any, dt: float
) -> dict[str, list]:
    """Integrate, filter through the navmesh, set, step (the tutorial's loop).

    Returns per step: ``step_start``, ``step_target``, ``step_end`` (each ``(n, 3)`` lists,
    world frame, m), ``collided`` (the filter shortened the step) and ``end_on_navmesh``
    (``pathfinder.is_navigable(end)``).
    """
    sim, time_step = ctx.sim, FRAME_DT
    start_time, last_velocity_set = sim.get_world_time(), 0.0
    log: dict[str, list] = {k: [] for k in ("step_start", "step_target", "step_end")}
    log.update(collided=[], end_on_navmesh=[])
    while sim.get_world_time() < start_time + dt:
        previous_rigid_state = locobot.rigid_state
        # manually integrate the rigid state
        target_rigid_state = vel_control.integrate_transform(time_step, previous_rigid_state)
        # snap rigid state to navmesh and set state to object/agent
        end_pos = sim.step_filter(previous_rigid_state.translation, target_rigid_state.translation)
        locobot.translation = end_pos
        locobot.rotation = target_rigid_state.rotation

        # collided: the filter shortened the step (squared lengths, the tutorial's EPS = 1e-5)
        dist_moved_before_filter = (
            target_rigid_state.translation - previous_rigid_state.translation
        ).dot()
        dist_moved_after_filter = (end_pos - previous_rigid_state.translation).dot()
        log["collided"].append(bool(dist_moved_after_filter + 1e-5 < dist_moved_before_filter))
        log["step_start"].append(vec(previous_rigid_state.translation))
        log["step_target"].append(vec(target_rigid_state.translation))
        log["step_end"].append(vec(end_pos))
        log["end_on_navmesh"].append(bool(sim.pathfinder.is_navigable(end_pos)))

        recorder.step(time_step)  # run any dynamics simulation, render observation

        # randomize angular velocity once per world second
        last_velocity_set += time_step
        if last_velocity_set >= 1.0:
            vel_control.angular_velocity = [0.0, (ctx.rng.random() - 0.5) * 2.0, 0.0]
            last_velocity_set = 0
    return log
