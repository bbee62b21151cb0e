"""The simulator facade and its parts; Habitat's ``habitat_sim.simulator`` names."""

from engine.simulator.simulator import (
    Configuration,
    Random,
    Simulator,
    SimulatorConfiguration,
)

__all__ = [
    "Configuration",
    "Random",
    "Simulator",
    "SimulatorConfiguration",
]
