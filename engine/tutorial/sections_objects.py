"""Tutorial sections on dynamic objects: basics, user attributes, forces, kinematic obstacles.

Port of the ``[basics]``, ``[object_user_configurations]``, ``[dynamic_control]`` and
``[kinematic_interactions]`` blocks of Habitat-sim's
``examples/tutorials/nb_python/managed_rigid_object_tutorial.py`` (MIT License, Copyright (c)
Meta Platforms, Inc. and its affiliates). The code keeps the tutorial's lines; it records
frames through the section's recorder and returns the final poses as outcomes (world frame,
meters, quaternions ``[x, y, z, w]``).
"""

from __future__ import annotations

import os

import engine as habitat_sim
from engine import mn
from engine.tutorial.context import (
    SectionResult,
    TutorialContext,
    finish,
    pose,
    simulate,
    vec,
)
from engine.tutorial.recording import VideoSpec
from engine.tutorial.scene_setup import FRAME_DT


# ------------------------------------------------------------------------------------------
# [basics]: load a template, add a sphere above the table, let it fall.
# ------------------------------------------------------------------------------------------
def basics(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("sim_basics"))
    start_time = ctx.sim.get_world_time()
    # load some object templates from configuration files
    sphere_template_id = ctx.obj_templates_mgr.load_configs(
        str(os.path.join(ctx.data_path, "test_assets/objects/sphere"))
    )[0]
    ctx.shared["sphere_template_id"] = sphere_template_id

    # add a sphere to the scene, returns the object
    sphere_obj = ctx.rigid_obj_mgr.add_object_by_template_id(sphere_template_id)
    # move sphere
    sphere_obj.translation = [2.50, 0.0, 0.2]

    simulate(recorder, dt=1.5)

    outcomes = {
        "sphere": pose(sphere_obj),
        "sphere_linear_velocity": vec(sphere_obj.linear_velocity),
    }
    ctx.rigid_obj_mgr.remove_all_objects()
    return finish("basics", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [object_user_configurations]: set and read back user-defined values.
# ------------------------------------------------------------------------------------------
def object_user_configurations(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(None)
    start_time = ctx.sim.get_world_time()
    sphere_template_id = ctx.obj_templates_mgr.load_configs(
        str(os.path.join(ctx.data_path, "test_assets/objects/sphere"))
    )[0]
    sphere_obj = ctx.rigid_obj_mgr.add_object_by_template_id(sphere_template_id)

    # set user-defined configuration values
    user_attributes_dict = {
        "obj_val_0": "This is a sphere object named " + sphere_obj.handle,
        "obj_val_1": 17,
        "obj_val_2": False,
        "obj_val_3": 19.7,
        "obj_val_4": [2.50, 0.0, 0.2],
        "obj_val_5": mn.Quaternion.rotation(mn.Deg(90.0), [-1.0, 0.0, 0.0]),
    }
    for k, v in user_attributes_dict.items():
        sphere_obj.user_attributes.set(k, v)
    as_strings = {k: sphere_obj.user_attributes.get_as_string(k) for k in user_attributes_dict}

    ctx.rigid_obj_mgr.remove_all_objects()
    outcomes = {"user_attributes": as_strings}
    return finish("object_user_configurations", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [dynamic_control]: anti-gravity forces, constant torques, a thrown sphere.
# ------------------------------------------------------------------------------------------
BOX_POSITIONS = [
    [2.39, -0.37, 0.0],
    [2.39, -0.64, 0.0],
    [2.39, -0.91, 0.0],
    [2.39, -0.64, -0.22],
    [2.39, -0.64, 0.22],
]


def dynamic_control(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("dynamic_control"))
    start_time = ctx.sim.get_world_time()
    obj_templates_mgr, rigid_obj_mgr = ctx.obj_templates_mgr, ctx.rigid_obj_mgr
    obj_templates_mgr.load_configs(str(os.path.join(ctx.data_path, "objects/example_objects/")))
    # search for an object template by key sub-string
    cheezit_template_handle = obj_templates_mgr.get_template_handles(
        "data/objects/example_objects/cheezit"
    )[0]
    box_orientation = mn.Quaternion.rotation(mn.Deg(90.0), [-1.0, 0.0, 0.0])
    boxes = []
    for position in BOX_POSITIONS:
        boxes.append(rigid_obj_mgr.add_object_by_template_handle(cheezit_template_handle))
        boxes[-1].translation = position
        boxes[-1].rotation = box_orientation

    # anti-gravity force f=m(-g) using first object's mass (all objects have the same mass)
    anti_grav_force = -1.0 * ctx.sim.get_gravity() * boxes[0].mass

    # throw a sphere at the boxes from the agent position
    sphere_template = obj_templates_mgr.get_template_by_id(ctx.shared["sphere_template_id"])
    sphere_template.scale = [0.5, 0.5, 0.5]
    obj_templates_mgr.register_template(sphere_template)
    sphere_obj = rigid_obj_mgr.add_object_by_template_id(ctx.shared["sphere_template_id"])
    sphere_obj.translation = ctx.sim.agents[0].get_state().position + [0.0, 1.0, 0.0]
    # get the vector from the sphere to a box; apply an initial velocity for one step
    target_direction = boxes[0].translation - sphere_obj.translation
    sphere_obj.linear_velocity = target_direction * 5
    sphere_obj.angular_velocity = [0.0, -1.0, 0.0]
    sphere_start = vec(sphere_obj.translation)

    box_tracks = []  # (frames, 5, 3) box translations after each step
    while ctx.sim.get_world_time() < start_time + 3.0:
        # set forces/torques before stepping the world
        for box in boxes:
            box.apply_force(anti_grav_force, [0.0, 0.0, 0.0])
            box.apply_torque([0.0, 0.01, 0.0])
        recorder.step(FRAME_DT)
        box_tracks.append([vec(box.translation) for box in boxes])

    outcomes = {
        "boxes_start": BOX_POSITIONS,
        "boxes": [pose(box) for box in boxes],
        "box_tracks": box_tracks,
        "box_mass": float(boxes[0].mass),
        "boxes_angular_velocity": [vec(box.angular_velocity) for box in boxes],
        "sphere_start": sphere_start,
        "sphere": pose(sphere_obj),
    }
    rigid_obj_mgr.remove_all_objects()
    return finish("dynamic_control", recorder, start_time, outcomes)


# ------------------------------------------------------------------------------------------
# [kinematic_interactions]: a kinematic can that dynamic cans fall onto.
# ------------------------------------------------------------------------------------------
CAN_POSITIONS = [[2.4, -0.64, 0.28], [2.4, -0.64, -0.28], [2.4, -0.3, 0.0]]


def kinematic_interactions(ctx: TutorialContext) -> SectionResult:
    recorder = ctx.new_recorder(VideoSpec("kinematic_interactions"))
    start_time = ctx.sim.get_world_time()
    rigid_obj_mgr = ctx.rigid_obj_mgr
    chefcan_template_handle = ctx.obj_templates_mgr.get_template_handles(
        "data/objects/example_objects/chefcan"
    )[0]
    chefcan_obj = rigid_obj_mgr.add_object_by_template_handle(chefcan_template_handle)
    chefcan_obj.translation = [2.4, -0.64, 0.0]
    # set object to kinematic
    chefcan_obj.motion_type = habitat_sim.physics.MotionType.KINEMATIC

    # drop some dynamic objects
    dynamic_cans = []
    for position in CAN_POSITIONS:
        dynamic_cans.append(rigid_obj_mgr.add_object_by_template_handle(chefcan_template_handle))
        dynamic_cans[-1].translation = position

    simulate(recorder, dt=1.5)

    outcomes = {
        "kinematic_can": pose(chefcan_obj),
        "dynamic_cans_start": CAN_POSITIONS,
        "dynamic_cans": [pose(can) for can in dynamic_cans],
    }
    rigid_obj_mgr.remove_all_objects()
    return finish("kinematic_interactions", recorder, start_time, outcomes)
