"""The ``Simulator`` facade: Habitat's entry point, composing physics, rendering and navigation.

``Simulator(Configuration(sim_cfg, [agent_cfg]))`` does what ``habitat_sim.Simulator`` does:

1. reads the physics config and builds the template managers;
2. loads the stage named by ``sim_cfg.scene_id`` (a ``.glb``/``.obj``/``.ply``, or its
   ``*.stage_config.json``; ``"NONE"`` for an empty world) into the scene graph (drawn flat)
   and into the physics world (an exact static triangle mesh);
3. loads ``<stage stem>.navmesh`` beside the stage if present, or builds a navmesh when
   ``sim_cfg.navmesh_settings`` is set;
4. creates the agents and their camera sensors.

It stays thin: physics lives in :class:`engine.physics.world.PhysicsWorld`, rendering in
:class:`engine.scene_render.SceneRenderer` (over :mod:`render`), navigation in
:class:`navmesh.PathFinder`.

rigidsim differs from Habitat where noted in the README: ``enable_physics`` defaults to True,
and bad input raises a clear exception instead of logging.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from engine import mn
from engine.agent import Agent, AgentConfiguration, AgentState
from engine.assets import load_meshes, merge_meshes
from engine.attributes import StageAttributes
from engine.attributes_managers import (
    AssetAttributesManager,
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)
from engine.physics.world import PhysicsWorld
from engine.scene_node import Drawable, SceneNode
from engine.scene_render import SceneRenderer
from navmesh import NavMeshSettings, PathFinder

__all__ = ["Configuration", "Simulator", "SimulatorConfiguration"]


@dataclass
class SimulatorConfiguration:
    """Habitat's ``SimulatorConfiguration`` (``scene_id = "NONE"`` is an empty world)."""

    scene_id: str = "NONE"
    enable_physics: bool = True
    physics_config_file: str = ""
    allow_sliding: bool = True
    random_seed: int = 0
    navmesh_settings: NavMeshSettings | None = None
    scene_light_setup: str = ""
    default_agent_id: int = 0
    load_semantic_mesh: bool = False


@dataclass
class Configuration:
    """A simulator configuration and the agents' configurations."""

    sim_cfg: SimulatorConfiguration = field(default_factory=SimulatorConfiguration)
    agents: list[AgentConfiguration] = field(default_factory=lambda: [AgentConfiguration()])


class Simulator:
    """Habitat's simulator: stage, objects, agents with sensors, physics and navmesh."""

    def __init__(self, config: Configuration) -> None:
        if not isinstance(config, Configuration):
            raise TypeError(f"Simulator needs a Configuration, got {type(config).__name__}")
        self.config = config
        self._closed = False
        sim_cfg = config.sim_cfg
        self._object_template_manager = ObjectAttributesManager()
        self._asset_template_manager = AssetAttributesManager()
        self._stage_template_manager = StageAttributesManager()
        self._physics_template_manager = PhysicsAttributesManager()
        physics_attributes = self._physics_template_manager.load(sim_cfg.physics_config_file)
        stage_attributes, stage_meshes = self._load_stage(sim_cfg.scene_id)

        self.root_node = SceneNode(name="root")
        self._stage_node = SceneNode(self.root_node, name="stage")
        self._stage_node.drawables = [Drawable(m, lit=False, semantic_id=0) for m in stage_meshes]
        self._stage_meshes = stage_meshes
        self._stage_attributes = stage_attributes
        self._world = PhysicsWorld(physics_attributes, self.root_node,
                                   self._object_template_manager,
                                   self._asset_template_manager)
        self._world.set_stage(stage_meshes or None, stage_attributes)
        self._renderer = SceneRenderer(self.root_node)

        self.pathfinder = PathFinder()
        self._load_navmesh(sim_cfg)
        self.agents: list[Agent] = []
        for agent_config in config.agents:
            node = SceneNode(self.root_node, name=f"agent:{len(self.agents)}")
            self.agents.append(Agent(node, agent_config, self.step_filter))

    # ------------------------------------------------------------------------------------------
    # loading
    # ------------------------------------------------------------------------------------------
    def _load_stage(self, scene_id: str) -> tuple[StageAttributes | None, list]:
        """The stage's template and its meshes in the world frame (none for ``"NONE"``)."""
        if not isinstance(scene_id, str):
            raise TypeError(f"scene_id must be a string, got {scene_id!r}")
        if scene_id in ("NONE", ""):
            return None, []
        stage = self._stage_template_manager.create_template_for_asset(scene_id)
        self._stage_template_manager.register_template(stage)
        scale = np.asarray(stage.scale) * 1.0
        meshes = load_meshes(stage.render_asset_handle, up=stage.orient_up,
                             front=stage.orient_front, scale=scale,
                             units_to_meters=stage.units_to_meters)
        return stage, meshes

    def _stage_triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """The stage's triangles in the world frame, merged: ``(V, 3)``, ``(F, 3)``."""
        if not self._stage_meshes:
            return np.zeros((0, 3)), np.zeros((0, 3), np.int64)
        merged = merge_meshes(self._stage_meshes)
        return merged.vertices, merged.faces

    def _load_navmesh(self, sim_cfg: SimulatorConfiguration) -> None:
        """Load ``<stage stem>.navmesh`` beside the stage asset, or build from settings."""
        if sim_cfg.navmesh_settings is not None:
            self.recompute_navmesh(self.pathfinder, sim_cfg.navmesh_settings)
            return
        if self._stage_attributes is None:
            return
        asset = Path(self._stage_attributes.render_asset_handle)
        navmesh_file = asset.with_name(asset.name.split(".")[0] + ".navmesh")
        if navmesh_file.is_file():
            self.pathfinder.load_nav_mesh(str(navmesh_file))

    # ------------------------------------------------------------------------------------------
    # managers
    # ------------------------------------------------------------------------------------------
    def get_object_template_manager(self) -> ObjectAttributesManager:
        return self._object_template_manager

    def get_asset_template_manager(self) -> AssetAttributesManager:
        return self._asset_template_manager

    def get_stage_template_manager(self) -> StageAttributesManager:
        return self._stage_template_manager

    def get_physics_template_manager(self) -> PhysicsAttributesManager:
        return self._physics_template_manager

    def get_rigid_object_manager(self):
        return self._world.rigid_object_manager

    def get_active_scene_graph(self) -> SceneNode:
        return self.root_node

    # ------------------------------------------------------------------------------------------
    # physics
    # ------------------------------------------------------------------------------------------
    def step_physics(self, dt: float = 1.0 / 60.0) -> None:
        """Advance the world by ``dt`` seconds in whole fixed steps (Habitat's accumulator)."""
        self._check_open()
        self._world.step_physics(dt)

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

    def get_physics_world(self) -> PhysicsWorld:
        """The physics world (rigidsim's; for teaching and the tests)."""
        return self._world

    # ------------------------------------------------------------------------------------------
    # agents and sensors
    # ------------------------------------------------------------------------------------------
    def initialize_agent(self, agent_id: int, initial_state: AgentState | None = None) -> Agent:
        """Put agent ``agent_id`` in ``initial_state`` (kept for ``reset``) and return it."""
        agent = self.get_agent(agent_id)
        if initial_state is not None:
            agent.set_state(initial_state)
        agent.initial_state = agent.get_state()
        return agent

    def get_agent(self, agent_id: int) -> Agent:
        if isinstance(agent_id, bool) or not isinstance(agent_id, int | np.integer):
            raise TypeError(f"agent_id must be an int, got {agent_id!r}")
        if not 0 <= agent_id < len(self.agents):
            raise KeyError(f"no agent with id {agent_id}; the simulator has {len(self.agents)}")
        return self.agents[agent_id]

    def get_sensor_observations(self, agent_ids: int | list[int] = 0) -> Any:
        """Render every sensor of the agent(s): a fresh dict keyed by sensor uuid.

        With a list of agent ids, a dict ``{agent_id: observations}`` (as Habitat).
        """
        self._check_open()
        if isinstance(agent_ids, list | tuple):
            return {i: self._renderer.observe(self.get_agent(i).sensors) for i in agent_ids}
        return self._renderer.observe(self.get_agent(agent_ids).sensors)

    # ------------------------------------------------------------------------------------------
    # navigation
    # ------------------------------------------------------------------------------------------
    def recompute_navmesh(self, pathfinder: PathFinder, navmesh_settings: NavMeshSettings) -> bool:
        """Build ``pathfinder``'s navmesh from the stage (and STATIC objects if asked)."""
        if not isinstance(navmesh_settings, NavMeshSettings):
            raise TypeError(f"navmesh_settings must be NavMeshSettings, got {navmesh_settings!r}")
        vertices, faces = self._stage_triangles()
        if navmesh_settings.include_static_objects:
            parts = [(vertices, faces), *self._world.static_meshes_world()]
            offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
            vertices = np.concatenate([v for v, _ in parts])
            faces = np.concatenate([f + o for (_, f), o in zip(parts, offsets, strict=True)])
        if len(faces) == 0:
            raise ValueError("cannot build a navmesh: the scene has no triangles")
        return bool(pathfinder.build(vertices, faces, navmesh_settings))

    def step_filter(self, start_pos: Any, end_pos: Any) -> mn.Vector3:
        """Filter a step on the navmesh: sliding along walls when ``allow_sliding`` (read now)."""
        start = np.asarray(mn.to_vector3(start_pos, "start_pos"))
        end = np.asarray(mn.to_vector3(end_pos, "end_pos"))
        if not self.pathfinder.is_loaded:
            return mn.Vector3(end)
        if self.config.sim_cfg.allow_sliding:
            return mn.Vector3(self.pathfinder.try_step(start, end))
        return mn.Vector3(self.pathfinder.try_step_no_sliding(start, end))

    # ------------------------------------------------------------------------------------------
    # lifetime
    # ------------------------------------------------------------------------------------------
    def reset(self) -> None:
        """World time to 0, objects to their creation poses, agents to their initial states."""
        self._check_open()
        self._world.reset()
        for agent in self.agents:
            agent.set_state(agent.initial_state)

    def close(self) -> None:
        """Release the world; further use raises RuntimeError. Safe to call twice."""
        if not self._closed:
            self._world.rigid_object_manager.remove_all_objects()
            self._closed = True

    def _check_open(self) -> None:
        if self._closed:
            raise RuntimeError("the simulator is closed")

    def __enter__(self) -> Simulator:
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return (f"<Simulator scene_id={self.config.sim_cfg.scene_id!r} "
                f"time={self.get_world_time():.3f}s agents={len(self.agents)}>")
