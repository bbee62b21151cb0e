"""rigidsim's engine: Habitat-sim's interactive rigid-object API in pure NumPy.

``import engine as habitat_sim`` gives the names a Habitat user expects::

    engine.Simulator, engine.Configuration, engine.SimulatorConfiguration,
    engine.agent.AgentConfiguration, engine.AgentState, engine.CameraSensorSpec,
    engine.SensorType, engine.SensorSubType, engine.RigidState, engine.physics,
    engine.NavMeshSettings, engine.PathFinder, engine.ShortestPath, engine.MultiGoalShortestPath,
    engine.HitRecord, engine.Agent, engine.ActionSpec, engine.ActuationSpec, engine.SceneGraph,
    engine.GreedyGeodesicFollower, engine.registry, engine.errors, engine.nav

and ``from engine import mn`` replaces ``import magnum as mn``. To run unchanged Habitat code
(``import habitat_sim``, ``import magnum``), install the opt-in import alias:
``engine.habitat_compat.alias.install()`` (see ``docs/habitat_lab.md``). Names are resolved lazily
(PEP 562), so ``from engine import mn`` does not load the physics or the renderer.
Like ``import habitat_sim``, importing ``engine`` imports numpy-quaternion, which registers
``np.quaternion`` (Habitat code writes ``np.quaternion(w, x, y, z)`` after ``import numpy``).
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version
from typing import Any

import quaternion  # noqa: F401 - registers np.quaternion, as importing habitat_sim does

from engine import mn

# public name -> module that defines it
_LAZY = {
    "Simulator": "engine.simulator.simulator",
    "Configuration": "engine.simulator.simulator",
    "SimulatorConfiguration": "engine.simulator.simulator",
    "AgentState": "engine.agent",
    "AgentConfiguration": "engine.agent",
    "Agent": "engine.agent",
    "ActionSpec": "engine.agent",
    "ActuationSpec": "engine.agent",
    "SixDOFPose": "engine.agent",
    "SceneNodeControl": "engine.agent",
    "ObjectControls": "engine.agent",
    "PyRobotNoisyActuationSpec": "engine.agent",
    "SceneGraph": "engine.scene.graph",
    "GreedyGeodesicFollower": "engine.nav.greedy_geodesic_follower",
    "GreedyFollowerCodes": "engine.nav.greedy_geodesic_follower",
    "HitRecord": "navmesh",
    "CameraSensorSpec": "engine.sensors.cameras",
    "SensorSpec": "engine.sensors.cameras",
    "VisualSensorSpec": "engine.sensors.cameras",
    "CubeMapSensorBaseSpec": "engine.sensors.cubemap",
    "EquirectangularSensorSpec": "engine.sensors.cubemap",
    "FisheyeSensorSpec": "engine.sensors.cubemap",
    "FisheyeSensorDoubleSphereSpec": "engine.sensors.cubemap",
    "FisheyeSensorModelType": "engine.sensors.cubemap",
    "SensorFactory": "engine.sensors.factory",
    "SensorType": "engine.sensors.cameras",
    "SensorSubType": "engine.sensors.cameras",
    "RigidState": "engine.physics",
    "SceneNode": "engine.scene.graph",
    "NavMeshSettings": "navmesh",
    "PathFinder": "engine.nav.pathfinder",
    "ShortestPath": "navmesh",
    "MultiGoalShortestPath": "navmesh",
    "stage_id": "engine.bindings",
    "built_with_bullet": "engine.bindings",
    "cuda_enabled": "engine.bindings",
    "audio_enabled": "engine.bindings",
    # placeholders: rigidsim has no batch replay renderer (engine.sensors.replay)
    "ReplayRenderer": "engine.sensors.replay",
    "ReplayRendererConfiguration": "engine.sensors.replay",
}
_SUBMODULES = {
    "agent",
    "attributes",
    "attributes_managers",
    "bindings",
    "demo",
    "errors",
    "geo",
    "logging",
    "scene",
    "nav",
    "gfx",
    "habitat_compat",
    "metadata",
    "physics",
    "registry",
    "sensor",
    "sensors",
    "templates",
    "utils",
}

#: Habitat's submodules that rigidsim keeps under another name (engine.habitat_compat)
_RENAMED_SUBMODULES = {
    "sim": "engine.habitat_compat.sim",
    "_ext": "engine.habitat_compat.ext",
}

__all__ = ["mn", *sorted(_LAZY), *sorted(_SUBMODULES), "sim"]

try:
    __version__: str = version("rigidsim")  # the installed distribution's version
except PackageNotFoundError:  # imported from a source tree that was never installed
    __version__ = "0+unknown"


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBMODULES:
        return importlib.import_module(f"engine.{name}")
    if name in _RENAMED_SUBMODULES:
        return importlib.import_module(_RENAMED_SUBMODULES[name])
    raise AttributeError(f"module 'engine' has no attribute {name!r}")
