"""Drop objects, push them, drive one with velocity control: the rigid-object API on one page.

An empty world with a static floor; a cube and a sphere from the built-in primitive
templates fall under gravity, the cube is pushed with a force and an impulse, the sphere is
made KINEMATIC and driven by velocity control. Prints the poses as it goes.

    python examples/drop_and_push.py
"""

from __future__ import annotations

import numpy as np

import engine as habitat_sim
from engine import mn

MotionType = habitat_sim.physics.MotionType


def main() -> None:
    with habitat_sim.Simulator(habitat_sim.Configuration()) as sim:  # an empty scene
        templates = sim.get_object_template_manager()
        objects = sim.get_rigid_object_manager()

        # a 10 x 10 m floor: a scaled copy of the cube primitive, STATIC
        floor_template = templates.get_template_by_handle(
            templates.get_template_handles("cubeSolid")[0]
        )
        floor_template.scale = [5.0, 0.1, 5.0]
        floor_id = templates.register_template(floor_template, "floor")
        floor = objects.add_object_by_template_id(floor_id)
        floor.translation = [0.0, -0.1, 0.0]  # top face at y = 0
        floor.motion_type = MotionType.STATIC

        cube = objects.add_object_by_template_handle(templates.get_template_handles("cubeSolid")[0])
        cube.translation = [0.0, 1.0, 0.0]
        sphere = objects.add_object_by_template_handle(
            templates.get_template_handles("icosphereSolid")[0]
        )
        sphere.translation = [1.0, 0.5, 0.0]

        sim.step_physics(1.5)  # both fall and come to rest on the floor
        print(f"after 1.5 s: cube at {np.round(cube.translation, 3)}, awake={cube.awake}")

        cube.apply_force(mn.Vector3(0.0, 0.0, -8.0), mn.Vector3(0.0, 0.0, 0.0))  # for one call
        sim.step_physics(0.5)
        cube.apply_impulse(mn.Vector3(1.0, 0.0, 0.0), mn.Vector3(0.0, 0.0, 0.0))
        sim.step_physics(1.0)
        print(
            f"pushed: cube at {np.round(cube.translation, 3)}, "
            f"speed {np.linalg.norm(cube.linear_velocity):.3f} m/s"
        )

        sphere.motion_type = MotionType.KINEMATIC
        control = sphere.velocity_control
        control.controlling_lin_vel = True
        control.linear_velocity = [0.0, 0.0, 1.0]  # 1 m/s along +Z, world frame
        start = np.array(sphere.translation)
        sim.step_physics(1.0)
        moved = np.array(sphere.translation) - start
        print(f"velocity control: the sphere moved {np.round(moved, 3)} in 1 s")
        print(f"world time {sim.get_world_time():.3f} s, {objects.get_num_objects()} objects")


if __name__ == "__main__":
    main()
