"""Simulator names habitat-lab reads that rigidsim spells differently or has no feature behind.

Mixed into :class:`engine.Simulator`:

- ``sim.renderer``: Habitat's property for the simulator's renderer; here the same object as
  ``sim.get_renderer()`` (rigidsim's :class:`engine.sensors.scene_render.SceneRenderer`);
- ``sim.get_articulated_object_manager()``: raises ``NotImplementedError`` (rigidsim has no
  articulated objects, :mod:`engine.physics.objects.articulated`);
- ``sim.gfx_replay_manager``: an object whose every method raises ``NotImplementedError``
  (no gfx-replay keyframes, :mod:`engine.sensors.replay`).

(``sim.step_world(dt)``, the backend's physics step, is real:
:meth:`engine.simulator.physics.SimulatorPhysics.step_world`.)
"""

from __future__ import annotations

from typing import NoReturn

from engine.physics.objects.articulated import ArticulatedObjectManager
from engine.sensors.replay import GfxReplayManager
from engine.sensors.scene_render import SceneRenderer

__all__ = ["SimulatorHabitatNames"]


class SimulatorHabitatNames:
    """The module docstring's three simulator names (mixed into ``Simulator``)."""

    _renderer: SceneRenderer

    @property
    def renderer(self) -> SceneRenderer:
        """Habitat's ``sim.renderer``: the sensors' renderer, as ``sim.get_renderer()``."""
        return self._renderer

    def get_articulated_object_manager(self) -> NoReturn:
        """Placeholder: rigidsim has no articulated objects; raises ``NotImplementedError``."""
        raise ArticulatedObjectManager._error(" (sim.get_articulated_object_manager())")

    @property
    def gfx_replay_manager(self) -> GfxReplayManager:
        """Placeholder: an object whose every method raises ``NotImplementedError``."""
        return GfxReplayManager()
