"""Sensors and the bridge to ``render``; Habitat's ``habitat_sim.sensors`` package
(``engine.sensors.sensor_wrapper``) and rigidsim's camera sensor names."""

from engine.sensors.cameras import (
    CameraSensor,
    CameraSensorSpec,
    SemanticSensorTarget,
    Sensor,
    SensorSpec,
    SensorSubType,
    SensorType,
    VisualSensorSpec,
    euler_xyz_matrix,
)

__all__ = [
    "CameraSensor",
    "CameraSensorSpec",
    "SemanticSensorTarget",
    "Sensor",
    "SensorSpec",
    "SensorSubType",
    "SensorType",
    "VisualSensorSpec",
    "euler_xyz_matrix",
]
