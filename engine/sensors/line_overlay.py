"""Debug lines over the sensors' color frames: which frames, which depth, which camera.

``sim.get_debug_line_render()`` (:mod:`engine.sensors.debug_lines`) collects world segments; every
draw of observations (``get_sensor_observations``, ``draw_observation``, and asynchronous
renders) takes them once and draws them, with :func:`render.lines.draw_lines`, into each
COLOR frame, depth-tested against that frame's depth:

* a pinhole or orthographic COLOR sensor: into its frame;
* a fisheye or equirectangular COLOR sensor (:mod:`engine.sensors.cubemap`): into each of
  its six 90-degree cube faces, *before* the faces are resampled through the camera model,
  so a straight world line comes out curved exactly as the geometry around it does.

The depth a line is tested against comes from a hidden DEPTH *twin* of each of those
cameras (:class:`LineDepthTwin`: equal intrinsics and pose, so the renderer shares the
rasterization and the twin costs one extra buffer copy). :class:`LineOverlay` holds the
lines, the twins and each camera's pose as it was when the overlay was made (an
asynchronous render draws the world as it was at ``start``, and so must the lines).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from engine.sensors.cameras import CameraSensor, SensorType
from engine.sensors.cubemap import CubeMapSensorBase
from engine.sensors.render_camera import camera_from_key
from render.lines import draw_lines

__all__ = ["LineDepthTwin", "LineOverlay"]


class _DepthSpec:
    sensor_type = SensorType.DEPTH


class LineDepthTwin:
    """A hidden DEPTH camera equal to ``target`` (a COLOR sensor or a cube face)."""

    def __init__(self, target: Any) -> None:
        self.target = target
        self.uuid = f"{target.uuid}:depth-for-debug-lines"
        self.spec = _DepthSpec()

    def camera_key(self) -> tuple:
        return self.target.camera_key()

    def world_from_camera(self) -> Any:
        return self.target.world_from_camera()


def _twin(target: Any) -> LineDepthTwin:
    """The twin of ``target``, one per target: the renderer keeps group state by identity."""
    twin = getattr(target, "_line_depth", None)
    if twin is None:
        twin = LineDepthTwin(target)
        setattr(target, "_line_depth", twin)  # noqa: B010 - a private cache
    return twin


def line_targets(sensors: list) -> list:
    """The frames lines are drawn into: pinhole/orthographic COLOR sensors, and the six faces
    of each cube-map COLOR sensor."""
    targets: list = []
    for sensor in sensors:
        if getattr(sensor.spec, "sensor_type", None) is not SensorType.COLOR:
            continue
        if isinstance(sensor, CubeMapSensorBase):
            targets.extend(sensor.faces())
        elif isinstance(sensor, CameraSensor):
            targets.append(sensor)
    return targets


class LineOverlay:
    """One draw's debug lines and what they are drawn into (module docstring)."""

    def __init__(self, lines: tuple, sensors: list) -> None:
        self.lines = lines
        self.twins = [_twin(target) for target in line_targets(sensors)]
        # each camera as it is now: (camera model, world_from_camera)
        self._cameras = {
            twin.uuid: (camera_from_key(twin.camera_key()), np.array(twin.world_from_camera()))
            for twin in self.twins
        }

    def draw(self, rendered: dict[str, np.ndarray]) -> None:
        """Draw the lines into every target's frame of ``rendered`` (uuid -> array, the
        twins' depths included), in place."""
        starts, ends, start_colors, end_colors, width = self.lines
        for twin in self.twins:
            camera, world_from_camera = self._cameras[twin.uuid]
            draw_lines(
                rendered[twin.target.uuid], rendered[twin.uuid], camera, world_from_camera,
                starts, ends, start_colors, end_colors, width,
            )  # fmt: skip
