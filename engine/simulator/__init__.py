"""The simulator facade and its parts; Habitat's ``habitat_sim.simulator`` names (``Sensor``
is the wrapper of ``sim.sensors[uuid]``, :class:`engine.sensors.sensor_wrapper.Sensor`)."""

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
