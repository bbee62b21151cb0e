"""The ``Simulator`` facade: Habitat's entry point, composing physics, rendering and navigation.

``Simulator(Configuration(sim_cfg, [agent_cfg]))`` does what ``habitat_sim.Simulator`` does:

1. reads the physics config and builds the template managers;
2. loads the scene named by ``sim_cfg.scene_id``: a scene instance of the dataset
   (:mod:`engine.scene.instance`: its stage, then its objects placed), else the stage it
   names (a ``.glb``/``.obj``/``.ply``, or its ``*.stage_config.json``; ``"NONE"`` for an
   empty world) into the scene graph (drawn flat) and into the physics world (an exact
   static triangle mesh);
3. loads ``<stage stem>.navmesh`` beside the stage if present, or builds a navmesh when
   ``sim_cfg.navmesh_settings`` is set;
4. creates the agents and their camera sensors.

It stays thin: the configuration classes live in :mod:`engine.simulator.config`, steps 1 to
3 in :mod:`engine.simulator.loading`, physics in :class:`engine.physics.world.PhysicsWorld`,
rendering in :class:`engine.sensors.scene_render.SceneRenderer` (over :mod:`render`), light setups
in :class:`engine.gfx.LightSetups`, navigation in :class:`navmesh.PathFinder`.

The agent loop is Habitat's: ``sim.step(action)`` (or ``{agent_id: action}``) acts, steps
the physics by ``dt`` and returns the observations with ``collided``; ``sim.reset()`` puts
objects and agents back and returns observations; ``initialize_agent(i)`` without a state
puts the agent at a random navigable point with a random yaw (drawn from ``sim.random``,
seeded by ``sim.seed(n)`` / ``random_seed``).

rigidsim differs from Habitat where noted in the README: ``enable_physics`` defaults to True,
and bad input raises a clear exception instead of logging.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from engine import mn
from engine.agent import Agent, AgentState
from engine.agent.agent import numpy_quaternion
from engine.agent.controls.pyrobot_noisy_controls import seed_noise
from engine.gfx import DEFAULT_LIGHTING_KEY, LightInfo, LightSetups
from engine.nav.pathfinder import PathFinder
from engine.physics.objects.rigid_object_manager import MotionType
from engine.physics.world import PhysicsWorld
from engine.scene.graph import Drawable, SceneGraph, SceneNode
from engine.scene.instance import SceneInstanceAttributes, find_scene_instance, read_scene_instance
from engine.sensors.scene_render import SceneRenderer
from engine.sensors.sensor_wrapper import Sensor
from engine.simulator.config import Configuration, Random, SimulatorConfiguration
from engine.simulator.habitat_names import SimulatorHabitatNames
from engine.simulator.loading import (
    append_triangles,
    load_navmesh_beside_stage,
    load_physics_config,
    load_stage,
    place_scene_objects,
    stage_triangles,
)
from engine.simulator.physics import SimulatorPhysics
from engine.simulator.queries import SimulatorQueries
from engine.simulator.sensors import SimulatorSensors
from engine.templates.managers import (
    AssetAttributesManager,
    ObjectAttributesManager,
    PhysicsAttributesManager,
    StageAttributesManager,
)
from engine.templates.metadata import MetadataMediator
from navmesh import NavMeshSettings

# Sensor: Habitat's habitat_sim.simulator.Sensor, the wrapper of sim.sensors[uuid]
__all__ = ["Configuration", "Random", "Sensor", "Simulator", "SimulatorConfiguration"]


#: why ``copy.copy``, ``copy.deepcopy`` and ``pickle`` refuse a simulator (Habitat's C++
#: simulator cannot be copied either): its renderer, asset caches and physics world are
#: shared, live resources.
_NO_COPY = (
    "a Simulator cannot be copied or pickled (it owns a renderer, loaded assets and a "
    "physics world); create another Simulator from the same Configuration, and carry "
    "object states across with get/set of translation, rotation and velocities"
)


class Simulator(SimulatorSensors, SimulatorQueries, SimulatorPhysics, SimulatorHabitatNames):
    """Habitat's simulator: stage, objects, agents with sensors, physics and navmesh.

    The sensor API (``sensors``, ``create_sensor``, ``get_sensor_observations``,
    asynchronous rendering) is :class:`engine.simulator.sensors.SimulatorSensors`; the
    scene queries are :class:`engine.simulator.queries.SimulatorQueries`; the physics calls
    (stepping, gravity, rays, contacts, rigid constraints) are
    :class:`engine.simulator.physics.SimulatorPhysics`.
    """

    def __init__(self, config: Configuration) -> None:
        if not isinstance(config, Configuration):
            raise TypeError(f"Simulator needs a Configuration, got {type(config).__name__}")
        self._build(config)

    def _build(self, config: Configuration) -> None:
        """Build everything from ``config`` (the module docstring's steps 1 to 4)."""
        self.config = config
        self._closed = False
        sim_cfg = config.sim_cfg
        # template managers: those of the active scene dataset (engine.templates.metadata)
        if config.metadata_mediator is None:
            config.metadata_mediator = MetadataMediator(sim_cfg)
        self.metadata_mediator = config.metadata_mediator
        self._object_template_manager = self.metadata_mediator.object_template_manager
        self._asset_template_manager = self.metadata_mediator.asset_template_manager
        self._stage_template_manager = self.metadata_mediator.stage_template_manager
        self._physics_template_manager = self.metadata_mediator.physics_template_manager
        physics_attributes = load_physics_config(
            self._physics_template_manager, sim_cfg.physics_config_file
        )
        # a scene instance (stage + placed objects, engine.scene.instance), else a stage
        scene_file = find_scene_instance(
            self.metadata_mediator.get_scene_handles(), sim_cfg.scene_id
        )
        self._scene_instance = read_scene_instance(scene_file) if scene_file else None
        stage_name, stage_scale = sim_cfg.scene_id, None
        if self._scene_instance is not None:
            stage_name = self._scene_instance.stage_instance.handle
            stage_scale = self._scene_instance.stage_instance.scale
        stage_attributes, stage_meshes = load_stage(
            self._stage_template_manager, stage_name, stage_scale
        )
        self._stage_attributes = stage_attributes
        self._semantic_scene = None

        self.root_node = SceneNode(name="root")
        self._scene_graph = SceneGraph(self.root_node)
        self.random = Random(sim_cfg.random_seed)
        self._stage_node = SceneNode(self.root_node, name="stage")
        self._lights = LightSetups()
        self._stage_node.drawables = [
            Drawable(m, semantic_id=0, light_setup_key=sim_cfg.scene_light_setup)
            for m in stage_meshes
        ]
        self._stage_meshes = stage_meshes
        self._world = PhysicsWorld(
            physics_attributes,
            self.root_node,
            self._object_template_manager,
            self._asset_template_manager,
        )
        self._world.set_stage(stage_meshes or None, stage_attributes)
        if self._scene_instance is not None:
            self._warn_unloaded_scene_parts(self._scene_instance)
            place_scene_objects(
                self._scene_instance,
                self._world.rigid_object_manager,
                self._object_template_manager,
                sim_cfg.scene_light_setup,
            )
        self._renderer = SceneRenderer(
            self.root_node, self._static_drawable_ids, lights_for=self._lights.render_lights
        )
        # Habitat draws the navmesh wireframe when True; rigidsim stores the flag only
        self.navmesh_visualization = False

        self.pathfinder = PathFinder()
        if sim_cfg.navmesh_settings is not None:
            self.recompute_navmesh(self.pathfinder, sim_cfg.navmesh_settings)
        else:  # as Habitat: a scene without triangles warns and has no navmesh
            load_navmesh_beside_stage(self.pathfinder, stage_attributes)
        self.pathfinder.seed(sim_cfg.random_seed)
        seed_noise(int(sim_cfg.random_seed))
        if not config.agents:
            raise ValueError("Config has no agents specified; give at least 1 agent")
        self._default_agent_id = int(sim_cfg.default_agent_id)
        self.agents: list[Agent] = []
        for agent_config in config.agents:
            node = self.root_node.create_child(name=f"agent:{len(self.agents)}")
            agent = Agent(node, agent_config)
            agent.controls.move_filter_fn = self.step_filter
            self.agents.append(agent)
        self._register_agent_sensors()
        self._last_states: dict[int, AgentState] = {}
        for agent_id in range(len(self.agents)):
            self.initialize_agent(agent_id)

    @staticmethod
    def _warn_unloaded_scene_parts(scene: SceneInstanceAttributes) -> None:
        """Warn about what a scene instance lists that rigidsim does not load."""
        if scene.num_articulated_instances:
            warnings.warn(
                f"scene instance {scene.handle}: its {scene.num_articulated_instances} "
                f"articulated object instances are not loaded (rigidsim has no articulated "
                f"objects)",
                stacklevel=4,
            )

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

    def get_active_scene_graph(self) -> SceneGraph:
        """The simulator's scene graph (``.get_root_node()`` is ``sim.root_node``)."""
        return self._scene_graph

    def get_renderer(self) -> SceneRenderer:
        """The sensors' renderer (switches ``static_layer``, ``processes``, ``threads``)."""
        return self._renderer

    def _static_drawable_ids(self) -> set[int]:
        """``id`` s of the drawables that do not move: the stage's and STATIC objects'."""
        ids = {id(d) for d in self._stage_node.drawables}
        for obj in self._world.rigid_object_manager._objects.values():
            if obj.motion_type == MotionType.STATIC:
                ids.update(id(d) for d in obj.visual_drawables())
        return ids

    # ------------------------------------------------------------------------------------------
    # agents and sensors
    # ------------------------------------------------------------------------------------------
    def seed(self, new_seed: int) -> None:
        """Seed the simulator's random source, the pathfinder's point sampler and the noise of
        the noisy PyRobot controls."""
        if isinstance(new_seed, bool) or not isinstance(new_seed, int | np.integer):
            raise TypeError(f"seed must be an int, got {new_seed!r}")
        self.random.seed(new_seed)
        self.pathfinder.seed(new_seed)
        seed_noise(int(new_seed))  # the noisy PyRobot controls' samples

    def initialize_agent(self, agent_id: int, initial_state: AgentState | None = None) -> Agent:
        """Put agent ``agent_id`` in ``initial_state`` (kept for ``reset``) and return it.

        Without a state (Habitat's rule): a random navigable point and a random yaw when a
        navmesh is loaded, else the origin with the identity rotation.
        """
        agent = self.get_agent(agent_id)
        if initial_state is None:
            initial_state = AgentState()
            if self.pathfinder.is_loaded:
                try:
                    initial_state.position = self.pathfinder.get_random_navigable_point()
                except RuntimeError as error:  # a navmesh without navigable area
                    warnings.warn(
                        f"initialize_agent({agent_id}): {error}; the agent starts at the origin",
                        stacklevel=2,
                    )
                yaw = self.random.uniform_float(0.0, 2.0 * np.pi)
                initial_state.rotation = numpy_quaternion(
                    mn.Quaternion.rotation(mn.Rad(yaw), [0.0, 1.0, 0.0])
                )
        agent.set_state(initial_state, is_initial=True)
        self._last_states[agent_id] = agent.get_state()
        return agent

    def reset_agent(self, agent_id: int) -> None:
        """Put agent ``agent_id`` back in its initial state."""
        agent = self.get_agent(agent_id)
        if agent.initial_state is None:
            raise RuntimeError("reset called before agent was given an initial state")
        self.initialize_agent(agent_id, agent.initial_state)

    def get_agent(self, agent_id: int) -> Agent:
        if isinstance(agent_id, bool) or not isinstance(agent_id, int | np.integer):
            raise TypeError(f"agent_id must be an int, got {agent_id!r}")
        if not 0 <= agent_id < len(self.agents):
            raise KeyError(f"no agent with id {agent_id}; the simulator has {len(self.agents)}")
        return self.agents[agent_id]

    @property
    def _default_agent(self) -> Agent:
        return self.get_agent(self._default_agent_id)

    def last_state(self, agent_id: int | None = None) -> AgentState:
        """The agent's state after its last ``step`` (or initialization)."""
        return self._last_states[self._default_agent_id if agent_id is None else agent_id]

    def step(self, action: Any, dt: float = 1.0 / 60.0) -> dict:
        """Act, step the world by ``dt`` and observe (Habitat's agent loop).

        ``action`` is an action id of the default agent's action space, or a mapping
        ``{agent_id: action_id}``. Returns the observations with ``"collided"`` (bool), or
        ``{agent_id: observations}`` for a mapping. Unknown ids raise before anything moves.
        """
        self._check_open()
        actions = dict(action) if isinstance(action, Mapping) else {self._default_agent_id: action}
        for agent_id, action_id in actions.items():
            if action_id not in self.get_agent(agent_id).agent_config.action_space:
                self.get_agent(agent_id).act(action_id)  # raises UnknownActionError
        collided = {}
        for agent_id, action_id in actions.items():
            agent = self.get_agent(agent_id)
            collided[agent_id] = agent.act(action_id)
            self._last_states[agent_id] = agent.get_state()
        step_start = time.time()
        self._world.step_physics(dt)
        self._previous_step_time = time.time() - step_start
        observations = self.get_sensor_observations(agent_ids=list(actions))
        for agent_id, agent_observations in observations.items():
            agent_observations["collided"] = collided[agent_id]
        if isinstance(action, Mapping):
            return observations
        return observations[self._default_agent_id]

    def make_greedy_follower(
        self,
        agent_id: int | None = None,
        goal_radius: float | None = None,
        *,
        stop_key: Any = None,
        forward_key: Any = None,
        left_key: Any = None,
        right_key: Any = None,
        fix_thrashing: bool = True,
        thrashing_threshold: int = 16,
    ):
        """A :class:`engine.nav.GreedyGeodesicFollower` for an agent on this navmesh."""
        from engine.nav.greedy_geodesic_follower import GreedyGeodesicFollower

        agent = self.get_agent(self._default_agent_id if agent_id is None else agent_id)
        return GreedyGeodesicFollower(
            self.pathfinder,
            agent,
            goal_radius,
            stop_key=stop_key,
            forward_key=forward_key,
            left_key=left_key,
            right_key=right_key,
            fix_thrashing=fix_thrashing,
            thrashing_threshold=thrashing_threshold,
        )

    # ------------------------------------------------------------------------------------------
    # lights (engine.gfx)
    # ------------------------------------------------------------------------------------------
    def set_light_setup(
        self, light_setup: list[LightInfo], key: str = DEFAULT_LIGHTING_KEY
    ) -> None:
        """Store a copy of ``light_setup`` (a list of ``LightInfo``) under ``key``; every
        drawable naming that key is lit by it from the next observation on."""
        self._lights.set(light_setup, key)

    def get_light_setup(self, key: str = DEFAULT_LIGHTING_KEY) -> list[LightInfo]:
        """A copy of the setup under ``key`` (an unknown key is an empty setup, as Habitat)."""
        return self._lights.get(key)

    # ------------------------------------------------------------------------------------------
    # navigation
    # ------------------------------------------------------------------------------------------
    def recompute_navmesh(
        self,
        pathfinder: PathFinder,
        navmesh_settings: NavMeshSettings,
        include_static_objects: bool | None = None,
    ) -> bool:
        """Build ``pathfinder``'s navmesh from the stage (and STATIC objects if asked).

        ``include_static_objects`` (Habitat's older third argument) overrides the settings'
        field when given. A scene without triangles builds nothing: a warning and False.
        """
        if not isinstance(navmesh_settings, NavMeshSettings):
            raise TypeError(f"navmesh_settings must be NavMeshSettings, got {navmesh_settings!r}")
        vertices, faces = stage_triangles(self._stage_meshes)
        with_statics = (
            navmesh_settings.include_static_objects
            if include_static_objects is None
            else bool(include_static_objects)
        )
        if with_statics:
            vertices, faces = append_triangles(vertices, faces, self._world.static_meshes_world())
        if len(faces) == 0:
            warnings.warn(
                "recompute_navmesh: the scene has no triangles; no navmesh is built "
                "and no collision checking will be done",
                stacklevel=2,
            )
            return False
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
    def reset(self, agent_ids: int | list[int] | None = None) -> dict:
        """World time to 0, objects to their creation poses, agents to their initial states.

        Returns the observations of the default agent (``agent_ids`` None or an int), or
        ``{agent_id: observations}`` for a list, as Habitat does.
        """
        self._check_open()
        self._world.reset()
        for agent_id in range(len(self.agents)):
            self.reset_agent(agent_id)
        if agent_ids is None:
            agent_ids = self._default_agent_id
        return self.get_sensor_observations(agent_ids=agent_ids)

    def reconfigure(self, config: Configuration) -> None:
        """Rebuild the simulator from ``config`` (stage, navmesh, agents), in place."""
        if not isinstance(config, Configuration):
            raise TypeError(f"reconfigure needs a Configuration, got {type(config).__name__}")
        if config is self.config and not self._closed:
            return
        self.close()
        self._build(config)

    def close(self, destroy: bool = True) -> None:
        """Release the world; further use raises RuntimeError. Safe to call twice.

        ``destroy`` is Habitat's (its GL context); rigidsim has none to release.
        """
        if not self._closed:
            self._async_render.close()
            for sensor in self._wrapper_of.values():
                sensor.close()
            self._sensor_registry.clear()
            self._wrapper_of.clear()
            self._world.rigid_object_manager.remove_all_objects()
            self._renderer.close()
            self._closed = True

    def _check_open(self) -> None:
        if self._closed:
            raise RuntimeError("the simulator is closed")

    def __enter__(self) -> Simulator:
        return self

    def __copy__(self) -> Simulator:
        raise TypeError(_NO_COPY)

    def __deepcopy__(self, memo: dict) -> Simulator:
        raise TypeError(_NO_COPY)

    def __reduce_ex__(self, protocol: Any) -> Any:
        raise TypeError(_NO_COPY)

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return (
            f"<Simulator scene_id={self.config.sim_cfg.scene_id!r} "
            f"time={self.get_world_time():.3f}s agents={len(self.agents)}>"
        )
