"""The simulator facade and its parts; Habitat's ``habitat_sim.simulator`` names."""

from engine.agent import Agent, AgentState  # noqa: F401 - Habitat's simulator module has them
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
