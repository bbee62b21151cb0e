"""The physics calls of Habitat's simulator, passed on to rigidsim's physics world.

:class:`SimulatorPhysics` is mixed into :class:`engine.simulator.simulator.Simulator`. Each method
is Habitat-sim's ``Simulator`` method of the same name (``step_physics``, ``get_gravity``,
``cast_ray``, ``get_physics_contact_points``, ``create_rigid_constraint``, ...) and asks the
simulator's :class:`engine.physics.world.PhysicsWorld` (``sim._world``), which integrates
the bodies, finds contacts and solves them (docs/physics.md). The world is built with the
simulator (``Simulator._build``); this class holds no state of its own.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from engine import mn
from engine.physics import PhysicsSimulationLibrary
from engine.physics.world import PhysicsWorld

__all__ = ["SimulatorPhysics"]


class SimulatorPhysics:
    """Habitat's physics methods of the simulator (mixed into ``Simulator``)."""

    config: Any
    _world: PhysicsWorld
    _check_open: Callable[[], None]  # Simulator's: raises once the simulator is closed

    def step_physics(self, dt: float = 1.0 / 60.0) -> None:
        """Advance the world by ``dt`` seconds in whole fixed steps (Habitat's accumulator)."""
        self._check_open()
        self._world.step_physics(dt)

    def step_world(self, dt: float = 1.0 / 60.0) -> None:
        """Habitat's backend call under ``step_physics``: advance the world by ``dt`` seconds.

        habitat-lab calls it directly; in rigidsim it is the same step as :meth:`step_physics`."""
        self.step_physics(dt)

    def get_world_time(self) -> float:
        return self._world.get_world_time()

    def get_physics_time_step(self) -> float:
        return self._world.get_physics_time_step()

    def get_gravity(self) -> mn.Vector3:
        return self._world.get_gravity()

    def set_gravity(self, gravity: Any) -> None:
        self._world.set_gravity(gravity)

    def cast_ray(self, ray: Any, max_distance: float = 100.0):
        return self._world.cast_ray(ray, max_distance)

    def get_physics_contact_points(self) -> list:
        return self._world.get_physics_contact_points()

    def perform_discrete_collision_detection(self) -> None:
        self._world.perform_discrete_collision_detection()

    def get_physics_num_active_contact_points(self) -> int:
        return self._world.get_physics_num_active_contact_points()

    def get_physics_num_active_overlapping_pairs(self) -> int:
        return self._world.get_physics_num_active_overlapping_pairs()

    def get_stage_is_collidable(self) -> bool:
        return self._world.get_stage_is_collidable()

    def set_stage_is_collidable(self, collidable: bool) -> None:
        """Turn the stage's collisions on or off (objects then fall through it)."""
        self._world.set_stage_is_collidable(collidable)

    # -- rigid constraints (engine.physics.objects.constraints) ------------------------------
    def create_rigid_constraint(self, settings) -> int:
        """Hold two objects (or an object and the world) together; returns the constraint id."""
        return self._world.constraints.create(self._world, settings)

    def update_rigid_constraint(self, constraint_id: int, settings) -> None:
        """Replace a constraint's settings (e.g. move its world pivot)."""
        self._world.constraints.update(self._world, constraint_id, settings)

    def remove_rigid_constraint(self, constraint_id: int) -> None:
        self._world.constraints.remove(self._world, constraint_id)

    def get_rigid_constraint_settings(self, constraint_id: int):
        """A copy of the constraint's settings (KeyError for an unknown id)."""
        return self._world.constraints.get_settings(constraint_id)

    def get_physics_simulation_library(self):
        """``PhysicsSimulationLibrary.Bullet`` when ``enable_physics`` (rigidsim's solver
        stands in for Bullet), else ``NoPhysics``, as Habitat reports."""
        if self.config.sim_cfg.enable_physics:
            return PhysicsSimulationLibrary.Bullet
        return PhysicsSimulationLibrary.NoPhysics

    def get_physics_world(self) -> PhysicsWorld:
        """The physics world (rigidsim's; for teaching and the tests)."""
        return self._world
