"""The simulator's sensor API (Habitat's ``Simulator`` sensor methods), mixed into
:class:`engine.simulator.simulator.Simulator`.

Sensors live on scene nodes; the simulator keeps a flat registry of wrappers
(:class:`engine.sensors.sensor_wrapper.Sensor`) by uuid:

* ``sim.sensors`` / ``sim._sensors``: every registered sensor (all agents', and those made by
  ``create_sensor`` on any node); ``get_sensor(uuid)``;
* ``create_sensor(spec, scene_node)``: a new sensor on a leaf child of ``scene_node`` (an
  agent's, an object's or a static node), registered; a uuid already registered raises
  ``ValueError``; ``remove_sensor(uuid)`` deletes it (``KeyError`` for an unknown uuid);
* ``add_sensor(spec, agent_id=None)``: ``create_sensor`` on the agent's node, and the spec
  joins the agent's configuration;
* ``get_sensor_observations(agent_ids=0)``: the registered sensors found under each agent's
  node (``agent.scene_node.subtree_sensors``), drawn together (sensors with equal intrinsics
  and pose share one rasterization) then read, ``{uuid: array}`` for one agent id and
  ``{agent_id: {uuid: array}}`` for a list; ``render_sensors(sensors=None)`` the same for a
  list of wrappers (default: all);
* asynchronous rendering: ``start_async_render_and_step_physics(dt, agent_ids=0)`` /
  ``start_async_render(agent_ids=0)`` then ``get_sensor_observations_async_finish()``
  (:mod:`engine.sensors.async_render`).
"""

from __future__ import annotations

from collections import OrderedDict
from typing import Any

from engine.scene.graph import SceneNode
from engine.sensors.async_render import AsyncRender
from engine.sensors.cameras import SensorSpec
from engine.sensors.cubemap import observe_with_cube_maps
from engine.sensors.debug_lines import DebugLineRender
from engine.sensors.factory import SensorFactory
from engine.sensors.line_overlay import LineOverlay
from engine.sensors.observations import Observations
from engine.sensors.sensor_wrapper import Sensor

__all__ = ["SimulatorSensors"]


class SimulatorSensors:
    """Sensor registry, observations and asynchronous rendering (module docstring)."""

    _sensor_registry: dict[str, Sensor]
    _async_render: AsyncRender

    def _register_agent_sensors(self) -> None:
        """Wrap every agent's sensors (called once the agents exist)."""
        self._sensor_registry = {}
        self._wrapper_of: dict[int, Sensor] = {}  # id(sensor object) -> its wrapper
        self._async_render = AsyncRender(self)
        self._debug_lines = DebugLineRender()
        for agent in self.agents:  # type: ignore[attr-defined]
            for spec in agent.agent_config.sensor_specifications:
                self._register(Sensor(self, agent.scene_node.subtree_sensors[spec.uuid]))

    def _register(self, wrapper: Sensor) -> None:
        # agents may reuse a uuid: the flat registry keeps the last one (as Habitat), each
        # agent still observes its own sensor (found by object, _agent_sensors)
        self._sensor_registry[wrapper.uuid] = wrapper
        self._wrapper_of[id(wrapper.sensor_object)] = wrapper

    @property
    def sensors(self) -> dict[str, Sensor]:
        """All sensors registered with this simulator, by uuid."""
        return self._sensor_registry

    @property
    def _sensors(self) -> dict[str, Sensor]:
        # Habitat's deprecated name
        return self._sensor_registry

    def get_sensor(self, uuid: str) -> Sensor:
        if uuid not in self._sensor_registry:
            raise KeyError(f"no sensor {uuid!r}; registered: {sorted(self._sensor_registry)}")
        return self._sensor_registry[uuid]

    def create_sensor(self, spec: SensorSpec, scene_node: SceneNode) -> Sensor:
        """Create a sensor on ``scene_node`` and register it (module docstring)."""
        self._check_open()  # type: ignore[attr-defined]
        if not isinstance(spec, SensorSpec):
            raise TypeError(f"create_sensor needs a SensorSpec, got {spec!r}")
        if spec.uuid in self._sensor_registry:
            raise ValueError(
                f"Sensor '{spec.uuid}' already exists in the registry. "
                "Remove it first with remove_sensor()."
            )
        self._async_render.check_idle("create_sensor")
        sensor_object = SensorFactory.create_sensors(scene_node, [spec])[spec.uuid]
        wrapper = Sensor(self, sensor_object)
        self._register(wrapper)
        return wrapper

    def remove_sensor(self, uuid: str) -> None:
        """Remove and destroy the sensor ``uuid`` (its leaf node leaves the scene graph)."""
        if uuid not in self._sensor_registry:
            raise KeyError(f"Sensor '{uuid}' not found in the registry.")
        self._async_render.check_idle("remove_sensor")
        wrapper = self._sensor_registry.pop(uuid)
        self._wrapper_of.pop(id(wrapper.sensor_object), None)
        SensorFactory.delete_sensor(wrapper.sensor_object)
        for agent in self.agents:  # type: ignore[attr-defined]
            specs = agent.agent_config.sensor_specifications
            specs[:] = [s for s in specs if s is not wrapper.spec]
        wrapper.close()

    def add_sensor(self, sensor_spec: SensorSpec, agent_id: int | None = None) -> None:
        """Give an agent (default: the default agent) a new sensor."""
        agent = self.get_agent(  # type: ignore[attr-defined]
            self._default_agent_id if agent_id is None else agent_id  # type: ignore[attr-defined]
        )
        self.create_sensor(sensor_spec, agent.scene_node)
        if not any(s is sensor_spec for s in agent.agent_config.sensor_specifications):
            agent.agent_config.sensor_specifications.append(sensor_spec)

    # -- observations ------------------------------------------------------------------------
    def _agent_sensors(self, agent_id: int) -> list[Sensor]:
        """The registered sensors under agent ``agent_id``'s node, in scene-graph order."""
        agent = self.get_agent(agent_id)  # type: ignore[attr-defined]
        sensors = agent.scene_node.subtree_sensors.values()
        return [self._wrapper_of[id(s)] for s in sensors if id(s) in self._wrapper_of]

    def _draw_sensors(self, sensors: list[Sensor]) -> None:
        """Render ``sensors`` together into their wrappers' buffers."""
        self._check_open()  # type: ignore[attr-defined]
        self._async_render.check_idle("drawing an observation")
        lines = self.take_debug_lines()
        for batch in _unique_uuid_batches(sensors):  # observations are keyed by uuid
            objects = [sensor.sensor_object for sensor in batch]
            overlay = LineOverlay(lines, objects) if lines is not None else None
            frames = observe_with_cube_maps(self._renderer.observe, objects, overlay)  # type: ignore[attr-defined]
            for sensor in batch:
                sensor._buffer = frames[sensor.uuid]

    def get_debug_line_render(self) -> DebugLineRender:
        """The simulator's debug line renderer (:mod:`engine.sensors.debug_lines`)."""
        return self._debug_lines

    def take_debug_lines(self) -> tuple | None:
        """The debug lines collected since the last draw (None if none), forgotten here:
        each draw of observations takes them once (:mod:`engine.sensors.line_overlay`)."""
        return self._debug_lines.take_lines() if self._debug_lines.has_lines() else None

    def render_sensors(self, sensors: list[Sensor] | None = None) -> dict[str, Any]:
        """Draw ``sensors`` (default: every registered one), then read them by uuid."""
        sensors = list(self._sensor_registry.values()) if sensors is None else list(sensors)
        self._draw_sensors(sensors)
        return {sensor.uuid: sensor.get_observation() for sensor in sensors}

    def get_sensor_observations(self, agent_ids: int | list[int] = 0) -> Any:
        """Render every sensor of the agent(s): a fresh dict keyed by sensor uuid, or
        ``{agent_id: observations}`` for a list of ids (as Habitat)."""
        self._check_open()  # type: ignore[attr-defined]
        single = not isinstance(agent_ids, list | tuple)
        ids: list[int] = list(agent_ids) if isinstance(agent_ids, list | tuple) else [agent_ids]
        per_agent = {agent_id: self._agent_sensors(agent_id) for agent_id in ids}
        self._draw_sensors([s for sensors in per_agent.values() for s in sensors])
        observations: dict[int, dict[str, Any]] = OrderedDict()
        for agent_id, sensors in per_agent.items():
            observations[agent_id] = Observations((s.uuid, s.get_observation()) for s in sensors)
        return next(iter(observations.values())) if single else observations

    # -- asynchronous rendering --------------------------------------------------------------
    def start_async_render_and_step_physics(
        self, dt: float, agent_ids: int | list[int] = 0
    ) -> None:
        """Start rendering the agents' sensors as the world is now, then step the physics by
        ``dt`` while the render runs (:mod:`engine.sensors.async_render`)."""
        self._async_render.start(agent_ids, dt)

    def start_async_render(self, agent_ids: int | list[int] = 0) -> None:
        """Start rendering the agents' sensors as the world is now (no physics step)."""
        self._async_render.start(agent_ids, None)

    def get_sensor_observations_async_finish(self) -> Any:
        """Wait for the render started by ``start_async_render_and_step_physics`` and return
        its observations (shaped as ``get_sensor_observations``)."""
        return self._async_render.finish()


def _unique_uuid_batches(sensors: list[Sensor]) -> list[list[Sensor]]:
    """``sensors`` cut into consecutive batches without a repeated uuid (agents may reuse
    uuids; one renderer call returns one frame per uuid)."""
    batches: list[list[Sensor]] = [[]]
    for sensor in sensors:
        if any(other.uuid == sensor.uuid for other in batches[-1]):
            batches.append([])
        batches[-1].append(sensor)
    return [batch for batch in batches if batch]
