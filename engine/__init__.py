"""rigidsim's engine: Habitat-sim's interactive rigid-object API in pure NumPy.

``import engine as habitat_sim`` gives the names a Habitat user expects::

    engine.Simulator, engine.Configuration, engine.SimulatorConfiguration,
    engine.agent.AgentConfiguration, engine.AgentState, engine.CameraSensorSpec,
    engine.SensorType, engine.SensorSubType, engine.RigidState, engine.physics,
    engine.NavMeshSettings, engine.PathFinder, engine.ShortestPath, engine.MultiGoalShortestPath,
    engine.HitRecord, engine.Agent, engine.ActionSpec, engine.ActuationSpec, engine.SceneGraph,
    engine.GreedyGeodesicFollower, engine.registry, engine.errors, engine.nav

and ``from engine import mn`` replaces ``import magnum as mn``. Names are resolved lazily
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
    "metadata",
    "physics",
    "registry",
    "sensor",
    "sensors",
    "templates",
    "utils",
}

__all__ = ["mn", *sorted(_LAZY), *sorted(_SUBMODULES)]

try:
    __version__: str = version("rigidsim")  # the installed distribution's version
except PackageNotFoundError:  # imported from a source tree that was never installed
    __version__ = "0+unknown"


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBMODULES:
        return importlib.import_module(f"engine.{name}")
    raise AttributeError(f"module 'engine' has no attribute {name!r}")
