"""``habitat_sim.sim``: the name of Habitat's C++ simulator core, ``SimulatorBackend``.

In Habitat-sim, ``habitat_sim.sim`` exposes the compiled simulator as ``SimulatorBackend`` (the
base class of the Python ``habitat_sim.Simulator``) and its ``SimulatorConfiguration``.
habitat-lab's rearrange simulator calls the backend directly (``SimulatorBackend.reset(self)``,
to reset the world without the Python agents). rigidsim's :class:`engine.Simulator` has no
separate backend layer, so ``SimulatorBackend`` is a placeholder: subclassing and annotating
work, constructing it or calling a method on it raises ``NotImplementedError``.
``SimulatorConfiguration`` is the real :class:`engine.SimulatorConfiguration`.
"""

from __future__ import annotations

from engine.core.placeholder import Placeholder
from engine.simulator.config import SimulatorConfiguration

__all__ = ["SimulatorBackend", "SimulatorConfiguration"]


class SimulatorBackend(Placeholder):
    """Placeholder of Habitat's C++ simulator core (module docstring)."""

    habitat_name = "habitat_sim.sim.SimulatorBackend"
    missing = "rigidsim's Simulator has no separate C++ backend layer"
    instead = "call engine.Simulator's own methods (sim.reset(), sim.step_physics(dt))"
