"""Habitat's ``SensorFactory``, which attaches sensors to scene nodes (the sensor specs and
classes are in :mod:`engine.sensors.cameras` and :mod:`engine.sensors.cubemap`; the face
:mod:`engine.sensor` gathers them at Habitat's path ``habitat_sim.sensor``).

``SensorFactory.create_sensors(node, [spec, ...])`` creates, per spec, a leaf child of
``node`` carrying the sensor the spec's subtype asks for (PINHOLE / ORTHOGRAPHIC ->
:class:`CameraSensor`, FISHEYE -> :class:`FisheyeSensor`, EQUIRECTANGULAR ->
:class:`EquirectangularSensor`) and returns ``node.node_sensors``; ``delete_sensor(sensor)``
removes a sensor's leaf node, ``delete_subtree_sensor(node, uuid)`` the one below ``node`` with
that uuid (a missing uuid is logged, not raised, as in Habitat). A node's sensors are
``node.node_sensors`` (its leaf children's), those of everything under it
``node.subtree_sensors``; both are read from the graph, so an agent's ``sensors``
(``scene_node.subtree_sensors``) follows sensors added or removed anywhere below it.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable

from engine.scene.graph import SceneNode
from engine.sensors.cameras import CameraSensor, Sensor, SensorSpec, SensorSubType
from engine.sensors.cubemap import EquirectangularSensor, FisheyeSensor

__all__ = ["SensorFactory"]

logger = logging.getLogger(__name__)

_SENSOR_OF_SUBTYPE: dict[SensorSubType, type[Sensor]] = {
    SensorSubType.PINHOLE: CameraSensor,
    SensorSubType.ORTHOGRAPHIC: CameraSensor,
    SensorSubType.FISHEYE: FisheyeSensor,
    SensorSubType.EQUIRECTANGULAR: EquirectangularSensor,
}


class SensorFactory:
    """Creates and deletes sensors on scene nodes (Habitat's static ``SensorFactory``)."""

    @staticmethod
    def create_sensors(node: SceneNode, specs: Iterable[SensorSpec]) -> dict[str, Sensor]:
        """One sensor per spec on a new leaf child of ``node``; all specs are checked before
        any sensor is made. Returns ``node.node_sensors`` (as Habitat: every sensor of the
        node by uuid, the new ones included; a uuid given twice keeps the first sensor)."""
        if not isinstance(node, SceneNode):
            raise TypeError(f"create_sensors needs a SceneNode, got {node!r}")
        specs = list(specs)
        for spec in specs:
            if not isinstance(spec, SensorSpec):
                raise TypeError(f"create_sensors needs SensorSpecs, got {spec!r}")
            spec.validate()
            if spec.sensor_subtype not in _SENSOR_OF_SUBTYPE:
                raise ValueError(
                    f"sensor {spec.uuid!r}: no sensor for sensor_subtype {spec.sensor_subtype}"
                )
        for spec in specs:
            _SENSOR_OF_SUBTYPE[spec.sensor_subtype](spec, node)  # type: ignore[arg-type]
        return node.node_sensors

    @staticmethod
    def delete_sensor(sensor: Sensor) -> None:
        """Remove ``sensor`` and its leaf node from the scene graph."""
        sensor.detach()

    @staticmethod
    def delete_subtree_sensor(node: SceneNode, uuid: str) -> None:
        """Remove the sensor ``uuid`` found on ``node`` or below it; when there is none, log
        it and change nothing (as Habitat, which only logs)."""
        sensors = node.subtree_sensors
        if uuid not in sensors:
            logger.debug("no sensor %r under node %r (it has %s)", uuid, node.name, sorted(sensors))
            return
        sensors[uuid].detach()
