"""Habitat's replay renderer and gfx-replay keyframes: placeholders.

Habitat-sim can record a simulation as "gfx-replay" keyframes (``sim.gfx_replay_manager``:
``save_keyframe``, ``extract_keyframe``, ``write_saved_keyframes_to_string``) and draw many
environments from such keyframes at once with a batch renderer (``habitat_sim.ReplayRenderer``,
configured by ``ReplayRendererConfiguration``); habitat-lab uses both only when its config asks
for them (``enable_gfx_replay_save``, ``enable_batch_renderer``). rigidsim has neither: it
renders each simulator's sensors itself (:mod:`render`) and runs many simulators through
:mod:`engine.batch`. The names exist so habitat-lab imports; using them raises
``NotImplementedError``.
"""

from __future__ import annotations

from engine.core.placeholder import Placeholder, PlaceholderObject

__all__ = ["GfxReplayManager", "ReplayRenderer", "ReplayRendererConfiguration"]

_BATCH_MISSING = "the batch replay renderer (drawing many environments from gfx-replay keyframes)"
_BATCH_INSTEAD = (
    "each simulator renders its own sensors; run many simulators with engine.batch, "
    "or habitat-lab's VectorEnv"
)


class ReplayRendererConfiguration(Placeholder):
    """Placeholder of the batch replay renderer's configuration (module docstring)."""

    habitat_name = "habitat_sim.ReplayRendererConfiguration"
    missing = _BATCH_MISSING
    instead = _BATCH_INSTEAD


class ReplayRenderer(Placeholder):
    """Placeholder of Habitat's batch replay renderer (module docstring)."""

    habitat_name = "habitat_sim.ReplayRenderer"
    missing = _BATCH_MISSING
    instead = _BATCH_INSTEAD


class GfxReplayManager(PlaceholderObject):
    """What ``sim.gfx_replay_manager`` returns: every method raises (module docstring)."""

    habitat_name = "habitat_sim.Simulator.gfx_replay_manager"
    missing = "gfx-replay keyframes (recording a simulation for later rendering) are not recorded"
    instead = (
        "record observations or object states yourself (sim.get_sensor_observations(), "
        "obj.translation / obj.rotation), or replay in the browser with engine.viewer"
    )
