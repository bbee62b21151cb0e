"""Habitat's ``habitat_sim.sensor``: the sensor specs, the sensor classes and
``SensorFactory`` (defined in :mod:`engine.sensors`)."""

from engine.sensors.factory import (
    CameraSensor,
    CameraSensorSpec,
    CubeMapSensorBase,
    CubeMapSensorBaseSpec,
    EquirectangularSensor,
    EquirectangularSensorSpec,
    FisheyeSensor,
    FisheyeSensorDoubleSphereSpec,
    FisheyeSensorModelType,
    FisheyeSensorSpec,
    SemanticSensorTarget,
    Sensor,
    SensorFactory,
    SensorSpec,
    SensorSubType,
    SensorType,
    VisualSensor,
    VisualSensorSpec,
)

__all__ = [
    "CameraSensor",
    "CameraSensorSpec",
    "CubeMapSensorBase",
    "CubeMapSensorBaseSpec",
    "EquirectangularSensor",
    "EquirectangularSensorSpec",
    "FisheyeSensor",
    "FisheyeSensorDoubleSphereSpec",
    "FisheyeSensorModelType",
    "FisheyeSensorSpec",
    "SemanticSensorTarget",
    "Sensor",
    "SensorFactory",
    "SensorSpec",
    "SensorSubType",
    "SensorType",
    "VisualSensor",
    "VisualSensorSpec",
]
