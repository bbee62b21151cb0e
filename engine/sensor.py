"""Habitat's ``habitat_sim.sensor``: the sensor specs, the sensor classes and
``SensorFactory`` (defined in :mod:`engine.sensors`)."""

from engine.sensors.cameras import (
    CameraSensor,
    CameraSensorSpec,
    SemanticSensorTarget,
    Sensor,
    SensorSpec,
    SensorSubType,
    SensorType,
    VisualSensor,
    VisualSensorSpec,
)
from engine.sensors.cubemap import (
    CubeMapSensorBase,
    CubeMapSensorBaseSpec,
    EquirectangularSensor,
    EquirectangularSensorSpec,
    FisheyeSensor,
    FisheyeSensorDoubleSphereSpec,
    FisheyeSensorModelType,
    FisheyeSensorSpec,
)
from engine.sensors.factory import SensorFactory

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
