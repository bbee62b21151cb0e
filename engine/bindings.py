"""``habitat_sim.bindings``: the names Habitat code imports from its C++ extension.

In Habitat-sim, ``habitat_sim.bindings`` re-exports the classes of the compiled
``habitat_sim_bindings`` module (``RigidState``, ``Configuration``, ``CameraSensorSpec``,
``SceneNode``, ``PathFinder``, ...) and a few build flags. rigidsim has no extension: every
class here is the pure-Python one defined elsewhere in :mod:`engine` (the same object, so
``engine.bindings.RigidState is engine.RigidState``); names resolve on first use (PEP 562).

The build flags, and what each means in rigidsim:

``built_with_bullet = True``
    Habitat sets it when compiled with Bullet; code reads it to decide whether dynamics
    (gravity, contacts, forces, ``MotionType.DYNAMIC``) exist, and Habitat's tests skip their
    physics cases without it. rigidsim always has dynamics: its own solver
    (:mod:`engine.physics`) stands in for Bullet.
``cuda_enabled = False``
    No GPU code: sensor noise models and observations stay NumPy arrays on the CPU.
``audio_enabled = False``
    No audio sensor (out of rigidsim's scope).
``stage_id = 0``
    The object id of the stage (``RIGID_STAGE_ID``): objects are numbered from 1, and a ray
    or a contact that hits the stage reports 0.
"""

from __future__ import annotations

import importlib
from typing import Any

built_with_bullet: bool = True
cuda_enabled: bool = False
audio_enabled: bool = False
stage_id: int = 0

# public name -> module that defines it
_CLASSES = {
    "Configuration": "engine.templates.user_config",
    "ConfigValType": "engine.templates.user_config",
    "RigidState": "engine.physics",
    "SceneGraph": "engine.scene.graph",
    "SceneNode": "engine.scene.graph",
    "SimulatorConfiguration": "engine.simulator.config",
    "GreedyFollowerCodes": "engine.nav.greedy_geodesic_follower",
    "PathFinder": "engine.nav.pathfinder",
    "ShortestPath": "navmesh",
    "MultiGoalShortestPath": "navmesh",
    "HitRecord": "navmesh",
    "NavMeshSettings": "navmesh",
}
#: sensor classes and specs live in engine.sensors.cameras (whatever it defines is re-exported)
_SENSOR_MODULE = "engine.sensors.cameras"

__all__ = [
    "audio_enabled",
    "built_with_bullet",
    "cuda_enabled",
    "stage_id",
    *sorted(_CLASSES),
]


def __getattr__(name: str) -> Any:
    if name in _CLASSES:
        return getattr(importlib.import_module(_CLASSES[name]), name)
    if name[:1].isupper():
        sensors = importlib.import_module(_SENSOR_MODULE)
        if name in getattr(sensors, "__all__", ()) or (
            name.endswith(("Sensor", "Spec", "Type", "Layout")) and hasattr(sensors, name)
        ):
            return getattr(sensors, name)
    raise AttributeError(f"module 'engine.bindings' has no attribute {name!r}")
