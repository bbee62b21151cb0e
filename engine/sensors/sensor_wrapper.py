"""Habitat's Python sensor wrapper (``habitat_sim.sensors.sensor_wrapper.Sensor``).

``sim.sensors[uuid]`` (and the deprecated ``sim._sensors[uuid]``) is this wrapper; the
sensor itself (a :class:`engine.sensors.cameras.CameraSensor`, or a fisheye / equirectangular
:class:`engine.sensors.cubemap.CubeMapSensorBase`) is its ``sensor_object`` (also
``_sensor_object``, the name code in the wild reads: ``sim._sensors["rgb"]._sensor_object
.render_camera``). ``draw_observation()`` renders the sensor into the wrapper's buffer and
``get_observation()`` returns a fresh copy of it: COLOR ``(H, W, 4) uint8``, DEPTH
``(H, W) float32`` z-depth in meters, SEMANTIC ``(H, W) uint32``.
``render_async()`` / ``get_observation_async()`` are the halves of
``sim.start_async_render_and_step_physics`` (:mod:`engine.sensors.async_render`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from engine.errors import InvalidAttachedObject

if TYPE_CHECKING:
    from engine.sensors.cameras import Sensor as SensorObject

__all__ = ["Sensor"]


class Sensor:
    """The wrapper of one sensor registered with a simulator (module docstring)."""

    def __init__(self, sim: Any, sensor_object: SensorObject) -> None:
        self._sim = sim
        self._sensor_object = sensor_object
        self._spec = sensor_object.specification()
        self._buffer: np.ndarray | None = None

    @property
    def uuid(self) -> str:
        return self._spec.uuid

    @property
    def node(self):
        """The sensor's leaf scene node."""
        return self._sensor_object.node

    @property
    def sensor_object(self) -> SensorObject:
        return self._sensor_object

    @property
    def spec(self):
        return self._spec

    def _check_attached(self) -> None:
        if self._sim is None:
            raise InvalidAttachedObject(f"sensor {self._spec.uuid!r} was removed or closed")
        node = self._sensor_object.node
        if node.parent is None:
            raise InvalidAttachedObject(
                "Sensor observation requested but sensor is invalid. "
                "(has it been detached from a scene node?)"
            )

    def draw_observation(self) -> None:
        """Render this sensor now (its buffer holds the frame until the next draw)."""
        self._check_attached()
        self._sim._draw_sensors([self])

    def get_observation(self) -> np.ndarray:
        """A fresh copy of the last frame drawn (``draw_observation`` first)."""
        if self._buffer is None:
            raise RuntimeError(f"sensor {self.uuid!r}: get_observation before any draw_observation")
        return self._buffer.copy()

    def render_async(self) -> None:
        """Queue this sensor in the simulator's next asynchronous render."""
        self._check_attached()
        self._sim._async_render.enqueue(self)

    def get_observation_async(self) -> np.ndarray:
        """The observation of the finished asynchronous render."""
        return self.get_observation()

    def close(self) -> None:
        """Release the wrapper (further draws raise)."""
        self._sim = None
        self._buffer = None

    def __repr__(self) -> str:
        return f"<Sensor wrapper {self.uuid!r} of {type(self._sensor_object).__name__}>"
