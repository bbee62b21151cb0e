"""The ``Simulator`` facade and its parts: Habitat's ``habitat_sim.simulator``.

``Simulator``, ``Configuration``, ``SimulatorConfiguration`` and ``Sensor`` (the wrapper of
``sim.sensors[uuid]``, :class:`engine.sensors.sensor_wrapper.Sensor`) are importable from here.
What is here, in reading order:

1. :mod:`~engine.simulator.config`: ``SimulatorConfiguration``, ``Configuration`` and the
   seeded ``sim.random``;
2. :mod:`~engine.simulator.simulator`: the facade, what its constructor builds and how a step
   runs;
3. :mod:`~engine.simulator.loading`: what the constructor loads (physics settings, the
   stage, its navmesh, a scene instance's objects);
4. the methods mixed into the facade, one concern each: :mod:`~engine.simulator.physics`
   (``step_physics``, ray casts, constraints), :mod:`~engine.simulator.sensors` (sensor
   API, observations), :mod:`~engine.simulator.queries` (read-only questions),
   :mod:`~engine.simulator.habitat_names` (``renderer`` and the placeholders habitat-lab
   reads: ``get_articulated_object_manager``, ``gfx_replay_manager``).

May import every folder below it: ``engine.nav``, ``engine.agent``, ``engine.sensors``,
``engine.physics``, ``engine.templates``, ``engine.scene`` and the small Habitat modules.
Only ``engine.utils`` and the programs on top (tutorial, envs, viewer) import the simulator.
"""

from engine.agent import Agent, AgentState  # noqa: F401 - Habitat's simulator module has them
from engine.simulator.simulator import (
    Configuration,
    Random,
    Sensor,
    Simulator,
    SimulatorConfiguration,
)

__all__ = [
    "Configuration",
    "Random",
    "Sensor",
    "Simulator",
    "SimulatorConfiguration",
]
