"""Rigid constraints (Habitat's ``create_rigid_constraint``): a pendulum keeps its length and
its period, a welded body follows its parent, both solver paths agree."""

from __future__ import annotations

import math

import numpy as np
import pytest

from engine import mn
from engine.physics import MotionType, RigidConstraintSettings, RigidConstraintType
from engine.simulator import Configuration, Simulator, SimulatorConfiguration

PIVOT = np.array([0.0, 2.0, 0.0])
LENGTH = 1.0


def make_sim():
    return Simulator(Configuration(SimulatorConfiguration(scene_id="NONE")))


def add(sim, handle="icosphereSolid_subdivs_1"):
    obj = sim.get_rigid_object_manager().add_object_by_template_handle(handle)
    obj.linear_damping = 0.0
    obj.angular_damping = 0.0
    return obj


def pendulum(sim, angle: float):
    """A 0.1 m ball on a massless 1 m rod from PIVOT, released ``angle`` rad from vertical."""
    ball = add(sim)
    ball.translation = PIVOT + LENGTH * np.array([math.sin(angle), -math.cos(angle), 0.0])
    settings = RigidConstraintSettings()
    settings.object_id_a = ball.object_id
    settings.pivot_a = PIVOT - np.asarray(ball.translation)  # ball frame = world frame here
    settings.object_id_b = -1  # the world
    settings.pivot_b = PIVOT
    return ball, sim.create_rigid_constraint(settings)


def test_pendulum_keeps_its_length_and_swings_with_the_physical_period():
    with make_sim() as sim:
        ball, _ = pendulum(sim, 0.15)
        inertia = float(np.asarray(ball.intertia_diagonal)[2])
        # physical pendulum: T = 2 pi sqrt((I_cm + m L^2) / (m g L)), small amplitude
        period = (
            2 * math.pi * math.sqrt((inertia + ball.mass * LENGTH**2) / (ball.mass * 9.8 * LENGTH))
        )
        dt = sim.get_physics_time_step()
        xs, lengths, times = [], [], []
        while sim.get_world_time() < 3.0 * period:
            sim.step_physics(dt)
            position = np.asarray(ball.translation)
            xs.append(position[0])
            lengths.append(np.linalg.norm(position - PIVOT))
            times.append(sim.get_world_time())
        assert max(abs(np.array(lengths) - LENGTH)) < 0.01 * LENGTH
        xs, times = np.array(xs), np.array(times)
        # downward zero crossings of x (from + to -), interpolated: one per period... half
        crossings = [
            times[i] - xs[i] * (times[i + 1] - times[i]) / (xs[i + 1] - xs[i])
            for i in range(len(xs) - 1)
            if xs[i] > 0 >= xs[i + 1]
        ]
        measured = float(np.mean(np.diff(crossings)))
        assert measured == pytest.approx(period, rel=0.02)
        # the swing keeps its amplitude (no damping, constraint adds little energy loss)
        assert xs[-int(period / dt) :].max() == pytest.approx(LENGTH * math.sin(0.15), rel=0.05)


def test_fixed_constraint_makes_a_body_follow_its_kinematic_parent():
    with make_sim() as sim:
        parent = add(sim, "cubeSolid")
        parent.motion_type = MotionType.KINEMATIC
        parent.translation = [0.0, 2.0, 0.0]
        child = add(sim, "cubeSolid")
        child.translation = [0.0, 1.7, 0.0]
        settings = RigidConstraintSettings()
        settings.constraint_type = RigidConstraintType.Fixed
        settings.object_id_a = child.object_id
        settings.object_id_b = parent.object_id
        settings.pivot_a = [0.0, 0.15, 0.0]  # a point between the two cubes
        settings.pivot_b = [0.0, -0.15, 0.0]
        sim.create_rigid_constraint(settings)
        control = parent.velocity_control
        control.controlling_lin_vel = True
        control.linear_velocity = [0.5, 0.0, 0.0]
        control.controlling_ang_vel = True
        control.angular_velocity = [0.0, 1.0, 0.0]
        for _ in range(120):
            sim.step_physics(1.0 / 60.0)
        offset = parent.rotation.transform_vector([0.0, -0.3, 0.0])
        np.testing.assert_allclose(
            np.asarray(child.translation), np.asarray(parent.translation + offset), atol=0.01
        )
        relative = parent.rotation.inverted() * child.rotation
        assert float(relative.angle()) < 0.02 or float(relative.angle()) > 2 * math.pi - 0.02


def test_both_solver_paths_agree():
    finals = []
    for vectorized in (True, False):
        with make_sim() as sim:
            sim.get_physics_world().settings.use_vectorized = vectorized
            ball, _ = pendulum(sim, 0.4)
            second = add(sim)  # a second ball hanging from the first: a chain of two
            second.translation = np.asarray(ball.translation) + [0.0, -0.5, 0.0]
            settings = RigidConstraintSettings()
            settings.object_id_a = second.object_id
            settings.pivot_a = [0.0, 0.25, 0.0]
            settings.object_id_b = ball.object_id
            settings.pivot_b = [0.0, -0.25, 0.0]
            sim.create_rigid_constraint(settings)
            sim.step_physics(1.0)
            finals.append(np.concatenate([ball.translation, second.translation]))
    np.testing.assert_allclose(finals[0], finals[1], atol=1e-9)


def test_update_remove_and_settings_round_trip():
    with make_sim() as sim:
        ball, constraint_id = pendulum(sim, 0.0)
        settings = sim.get_rigid_constraint_settings(constraint_id)
        assert settings.object_id_b == -1 and settings.pivot_b == mn.Vector3(PIVOT)
        assert settings.constraint_type == RigidConstraintType.PointToPoint
        assert settings.max_impulse == 1000.0  # Habitat's default
        hook = PIVOT + [1.0, 0.0, 0.0]
        settings.pivot_b = hook  # move the hook: the ball is pulled onto the new circle
        sim.update_rigid_constraint(constraint_id, settings)
        distances = []
        for _ in range(120):
            sim.step_physics(1.0 / 60.0)
            distances.append(np.linalg.norm(np.asarray(ball.translation) - hook))
        # Baumgarte: the 0.41 m error shrinks step by step, never overshooting much
        assert distances[0] < math.sqrt(2.0) and max(distances) < math.sqrt(2.0)
        assert np.linalg.norm(np.asarray(ball.translation) - hook) == pytest.approx(
            LENGTH, abs=0.01
        )
        sim.remove_rigid_constraint(constraint_id)
        v0 = ball.linear_velocity.y
        sim.step_physics(0.504)  # 63 whole steps
        assert ball.linear_velocity.y == pytest.approx(v0 - 9.8 * 0.504, abs=1e-6)  # free fall
        with pytest.raises(KeyError):
            sim.get_rigid_constraint_settings(constraint_id)


def test_bad_settings_are_refused():
    with make_sim() as sim:
        settings = RigidConstraintSettings()
        settings.object_id_a = 42
        with pytest.warns(UserWarning, match="object_id_a"):  # Habitat returns -1
            assert sim.create_rigid_constraint(settings) == -1
        with pytest.raises(AttributeError, match="pivot_a"):
            settings.pivot_aa = [0.0, 0.0, 0.0]
        with pytest.raises(ValueError):
            settings.max_impulse = 0.0
        with pytest.raises(ValueError):
            settings.pivot_a = [math.nan, 0.0, 0.0]


def simulate(sim, seconds: float) -> None:
    """Habitat's test helper: step at 60 Hz until ``seconds`` of world time passed."""
    start = sim.get_world_time()
    while sim.get_world_time() < start + seconds:
        sim.step_physics(1.0 / 60.0)


def test_habitats_rigid_constraint_sequence():
    """The rigid-object part of Habitat's ``test_rigid_constraints``, with its tolerances."""
    with make_sim() as sim:
        rom = sim.get_rigid_object_manager()
        viz = rom.add_object_by_template_handle("cubeWireframe")
        viz.collidable = False
        viz.motion_type = MotionType.KINEMATIC
        viz_box = viz.collision_shape_aabb
        cube = rom.add_object_by_template_handle("cubeSolid")

        def world_point(obj, local):
            return np.asarray(obj.root_scene_node.transformation.transform_point(local))

        # dangle the cube from its corner at the origin (object_id_b -1, pivot_b 0 by default)
        settings = RigidConstraintSettings()
        settings.object_id_a = cube.object_id
        settings.pivot_a = cube.collision_shape_aabb.front_top_left
        constraint_id = sim.create_rigid_constraint(settings)
        assert constraint_id >= 0
        simulate(sim, 1.0)
        np.testing.assert_allclose(world_point(cube, settings.pivot_a), 0.0, atol=1e-4)
        settings.pivot_b = viz_box.back_bottom_right  # move the hook
        sim.update_rigid_constraint(constraint_id, settings)
        simulate(sim, 1.0)
        np.testing.assert_allclose(world_point(cube, settings.pivot_a), settings.pivot_b, atol=1e-4)
        settings.pivot_a = cube.collision_shape_aabb.back_bottom_right  # the opposite corner
        sim.update_rigid_constraint(constraint_id, settings)
        simulate(sim, 2.0)
        np.testing.assert_allclose(world_point(cube, settings.pivot_a), settings.pivot_b, atol=1e-4)
        # a second cube hanging from the first
        cube_2 = rom.add_object_by_template_handle("cubeSolid")
        settings_2 = RigidConstraintSettings()
        settings_2.object_id_a = cube_2.object_id
        settings_2.object_id_b = cube.object_id
        settings_2.pivot_a = cube_2.collision_shape_aabb.back_bottom_right
        settings_2.pivot_b = cube.collision_shape_aabb.front_top_left
        constraint_id_2 = sim.create_rigid_constraint(settings_2)
        assert constraint_id_2 >= 0
        simulate(sim, 4.0)
        np.testing.assert_allclose(world_point(cube, settings.pivot_a), settings.pivot_b, atol=1e-3)
        np.testing.assert_allclose(
            world_point(cube_2, settings_2.pivot_a),
            world_point(cube, settings_2.pivot_b),
            atol=5e-3,
        )
        # a weak world constraint lets go
        settings.max_impulse = 0.2
        sim.update_rigid_constraint(constraint_id, settings)
        simulate(sim, 2.0)
        assert not np.allclose(world_point(cube, settings.pivot_a), settings.pivot_b, atol=1e-4)
        queried = sim.get_rigid_constraint_settings(constraint_id)
        assert (queried.pivot_a, queried.pivot_b) == (settings.pivot_a, settings.pivot_b)
        assert queried.max_impulse == settings.max_impulse
        assert cube.translation[1] > -1.0 and cube_2.translation[1] > -1.0
        sim.remove_rigid_constraint(constraint_id)
        sim.remove_rigid_constraint(constraint_id_2)
        simulate(sim, 2.0)
        assert cube.translation[1] < -1.0 and cube_2.translation[1] < -1.0
        assert not np.allclose(
            world_point(cube_2, settings_2.pivot_a), world_point(cube, settings_2.pivot_b), atol=0.5
        )
        # the same settings as Fixed constraints pull both back and lock the orientations
        settings.constraint_type = RigidConstraintType.Fixed
        settings_2.constraint_type = RigidConstraintType.Fixed
        constraint_id = sim.create_rigid_constraint(settings)
        constraint_id_2 = sim.create_rigid_constraint(settings_2)
        simulate(sim, 2.0)
        np.testing.assert_allclose(
            world_point(cube_2, settings_2.pivot_a),
            world_point(cube, settings_2.pivot_b),
            atol=5e-3,
        )
        np.testing.assert_allclose(world_point(cube, settings.pivot_a), settings.pivot_b, atol=1e-3)
        assert mn.math.angle(cube.rotation, mn.Quaternion()) < mn.Rad(0.01)
        assert mn.math.angle(cube_2.rotation, mn.Quaternion()) < mn.Rad(0.01)
        target = mn.Quaternion.rotation(mn.Rad(mn.math.pi / 4.0), mn.Vector3(1.0, 0.0, 0.0))
        settings.frame_b = target.to_matrix()
        sim.update_rigid_constraint(constraint_id, settings)
        settings_2.frame_a = mn.Quaternion.rotation(
            mn.Rad(mn.math.pi / 4.0), mn.Vector3(0.0, 1.0, 0.0)
        ).to_matrix()
        settings_2.frame_b = mn.Quaternion.rotation(
            -mn.Rad(mn.math.pi / 4.0), mn.Vector3(0.0, 1.0, 0.0)
        ).to_matrix()
        sim.update_rigid_constraint(constraint_id_2, settings_2)
        simulate(sim, 2.0)
        assert mn.math.angle(cube.rotation, target) < mn.Rad(0.01)
        relative = mn.math.angle(cube.rotation, cube_2.rotation) - mn.Rad(mn.math.pi / 4.0)
        assert abs(float(relative)) < 0.01
        # removing an object removes its constraints; a constrained body never sleeps
        rom.remove_object_by_id(cube_2.object_id)
        assert cube.awake
        simulate(sim, 1.0)
        assert cube.awake


def test_a_constraint_whose_bodies_cannot_move_is_inert_and_stepping_works():
    """Before: pinning an object to the world and then making it KINEMATIC (or constraining
    two STATIC objects) made every later ``step_physics`` raise an internal ``ValueError:
    cannot reshape array of size 0``."""
    with make_sim() as sim:
        pinned = add(sim, "cubeSolid")
        pinned.translation = [0.0, 2.0, 0.0]
        settings = RigidConstraintSettings()
        settings.object_id_a = pinned.object_id
        settings.pivot_b = [0.0, 2.0, 0.0]  # the world point at its center
        assert sim.create_rigid_constraint(settings) >= 0
        pinned.motion_type = MotionType.KINEMATIC
        first, second = add(sim, "cubeSolid"), add(sim, "cubeSolid")
        first.translation, second.translation = [3.0, 0.0, 0.0], [5.0, 0.0, 0.0]
        pair = RigidConstraintSettings()
        pair.object_id_a, pair.object_id_b = first.object_id, second.object_id
        pair.pivot_a, pair.pivot_b = [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]
        assert sim.create_rigid_constraint(pair) >= 0
        first.motion_type = second.motion_type = MotionType.STATIC
        sim.step_physics(0.5)  # only inert constraints: nothing can move
        assert sim.get_world_time() == pytest.approx(0.5, abs=0.01)
        np.testing.assert_allclose(np.asarray(pinned.translation), [0.0, 2.0, 0.0])
        faller = add(sim, "cubeSolid")
        faller.translation = [-3.0, 2.0, 0.0]
        sim.step_physics(0.5)  # a free body falls as it would without the constraints
        h = sim.get_physics_time_step()
        steps = round((sim.get_world_time() - 0.5) / h)
        # semi-implicit Euler from rest: y = y0 - g h^2 n (n + 1) / 2
        assert faller.translation.y == pytest.approx(2.0 - 9.8 * h**2 * steps * (steps + 1) / 2)
        np.testing.assert_allclose(np.asarray(first.translation), [3.0, 0.0, 0.0])
        pinned.motion_type = MotionType.DYNAMIC  # movable again: the pin holds again
        pinned.translation = [0.0, 1.9, 0.0]
        sim.step_physics(1.0)
        np.testing.assert_allclose(np.asarray(pinned.translation), [0.0, 2.0, 0.0], atol=1e-3)
