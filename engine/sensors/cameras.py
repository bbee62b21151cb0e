"""Camera sensors: Habitat's ``CameraSensorSpec`` and the sensors that render it.

A sensor is a camera posed on its agent's scene node. Its local pose follows Habitat:
``position`` is a translation relative to the agent node, ``orientation`` holds Euler angles in
**radians** applied X first, then Y, then Z (local rotation ``Rz @ Ry @ Rx``). So the tutorial's
``orientation = [-45.0, 0, 0]`` is a pitch of -45 rad, i.e. -58.3 degrees (mod 360).

Observations follow Habitat's sensor types:

* ``COLOR``: ``uint8 (H, W, 4)`` RGBA, alpha 255;
* ``DEPTH``: ``float32 (H, W)`` z-depth along the camera axis in meters, 0 where nothing is drawn;
* ``SEMANTIC``: ``uint32 (H, W)`` the ``semantic_id`` of the visible object.

The rendering itself is :func:`render.render_frame`; sensors sharing one pose and intrinsics
share one rasterization (see :mod:`engine.sensors.scene_render`). The specs (``CameraSensorSpec``
and its bases, ``SensorType``, ``SensorSubType``) live in :mod:`engine.sensors.sensor_specs` and are
re-exported here.
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np

from engine import mn
from engine.scene.graph import SceneNode
from engine.sensors.render_camera import RenderCamera
from engine.sensors.sensor_specs import (
    CameraSensorSpec,
    SemanticSensorTarget,
    SensorSpec,
    SensorSubType,
    SensorType,
    VisualSensorSpec,
)

__all__ = [
    "CameraSensor",
    "CameraSensorSpec",
    "SemanticSensorTarget",
    "Sensor",
    "SensorSpec",
    "SensorSubType",
    "SensorType",
    "VisualSensor",
    "VisualSensorSpec",
    "euler_xyz_matrix",
]


def euler_xyz_matrix(angles: Any) -> np.ndarray:
    """Rotation applying X, then Y, then Z Euler angles (radians): ``Rz @ Ry @ Rx``."""
    ax, ay, az = (float(a) for a in angles)
    cx, sx, cy, sy, cz, sz = (
        math.cos(ax),
        math.sin(ax),
        math.cos(ay),
        math.sin(ay),
        math.cos(az),
        math.sin(az),
    )
    rot_x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    rot_y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rot_z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rot_z @ rot_y @ rot_x


_CREATION_COUNTER = itertools.count()  # Sensor.creation_order


class Sensor:
    """A sensor object (Habitat's C++ ``Sensor``): its spec and the leaf scene node that
    carries it, a child of the node it was created on (an agent's node, an object's node or
    any static node). The node is registered in ``parent.subtree_sensors`` under the uuid."""

    def __init__(self, spec: SensorSpec, parent_node: SceneNode) -> None:
        spec.validate()
        if not isinstance(parent_node, SceneNode):
            raise TypeError(f"a sensor needs a SceneNode to attach to, got {parent_node!r}")
        self.spec = spec
        #: a global counter: the order sensors were made in (the first of a uuid wins)
        self.creation_order = next(_CREATION_COUNTER)
        self.node = SceneNode(parent_node, name=f"sensor:{spec.uuid}")
        self.node.own_sensors[spec.uuid] = self
        self.set_transformation_from_spec()

    @property
    def uuid(self) -> str:
        return self.spec.uuid

    @property
    def object(self) -> SceneNode:
        """Habitat's alias of ``node``."""
        return self.node

    def specification(self) -> SensorSpec:
        return self.spec

    def is_visual_sensor(self) -> bool:
        return self.spec.is_visual_sensor_spec()

    def set_transformation_from_spec(self) -> None:
        """Put the sensor node back at the spec's position and orientation."""
        self.node.translation = self.spec.position
        self.node.rotation = mn.Quaternion.from_matrix(euler_xyz_matrix(self.spec.orientation))

    reset_pose = set_transformation_from_spec  # rigidsim's older name

    def world_from_camera(self) -> np.ndarray:
        """The sensor pose ``(4, 4)``: its parent chain's pose times its local pose."""
        return self.node.world_matrix()

    def detach(self) -> None:
        """Remove the sensor's leaf node from the scene graph (Habitat's ``delete_sensor``)."""
        self.node.own_sensors.pop(self.uuid, None)
        self.node.parent = None

    @property
    def near(self) -> float:
        return float(self._visual_spec().near)

    @property
    def far(self) -> float:
        return float(self._visual_spec().far)

    @property
    def framebuffer_size(self) -> mn.Vector2i:
        """``(width, height)`` in pixels (Magnum's order)."""
        height, width = self._visual_spec().pixel_resolution()
        return mn.Vector2i(width, height)

    def _visual_spec(self) -> VisualSensorSpec:
        if not isinstance(self.spec, VisualSensorSpec):
            raise AttributeError(f"sensor {self.uuid!r} is not a visual sensor")
        return self.spec


VisualSensor = Sensor  # Habitat's base class of image sensors; every rigidsim sensor is one


class CameraSensor(Sensor):
    """A pinhole or orthographic camera sensor (Habitat's ``CameraSensor``).

    ``hfov`` / ``fov`` (settable, :class:`mn.Deg`), ``near_plane_dist`` / ``far_plane_dist``
    (settable), ``zoom(factor)`` / ``reset_zoom()`` (a factor > 1 narrows the view: the
    focal length, or the orthographic pixels per meter, times ``factor``), ``camera_type``,
    ``set_width`` / ``set_height`` / ``set_projection_params(spec)`` and ``render_camera``
    (:class:`engine.sensors.render_camera.RenderCamera`: projection and camera matrices, unproject).
    Setters write the spec, so the next observation uses them.
    """

    spec: CameraSensorSpec

    def __init__(self, spec: CameraSensorSpec, parent_node: SceneNode) -> None:
        if not isinstance(spec, CameraSensorSpec):
            raise TypeError(f"CameraSensor needs a CameraSensorSpec, got {type(spec).__name__}")
        self._zoom = 1.0
        super().__init__(spec, parent_node)
        self._render_camera: RenderCamera | None = None

    @property
    def hfov(self) -> mn.Deg:
        """Horizontal field of view in degrees (writes go to the spec, used next frame)."""
        return mn.Deg(float(self.spec.hfov))

    @hfov.setter
    def hfov(self, value: Any) -> None:
        # mn.Rad converts; mn.Deg and plain numbers are degrees
        degrees = math.degrees(float(value)) if isinstance(value, mn.Rad) else float(value)
        if not 0.0 < degrees < 180.0:
            raise ValueError(
                f"sensor {self.uuid!r}: hfov must be in (0, 180) degrees, got {value!r}"
            )
        self.spec.hfov = degrees

    fov = hfov  # Habitat's alias

    @property
    def near_plane_dist(self) -> float:
        return float(self.spec.near)

    @near_plane_dist.setter
    def near_plane_dist(self, value: float) -> None:
        self._set_clip("near", value)

    @property
    def far_plane_dist(self) -> float:
        return float(self.spec.far)

    @far_plane_dist.setter
    def far_plane_dist(self, value: float) -> None:
        self._set_clip("far", value)

    def _set_clip(self, name: str, value: Any) -> None:
        near, far = float(self.spec.near), float(self.spec.far)
        near, far = (float(value), far) if name == "near" else (near, float(value))
        if not (math.isfinite(near) and math.isfinite(far) and 0.0 < near < far):
            raise ValueError(
                f"sensor {self.uuid!r}: {name} plane {value!r} leaves near={near}, far={far}; "
                "need 0 < near < far"
            )
        setattr(self.spec, name, float(value))

    @property
    def camera_type(self) -> SensorSubType:
        return self.spec.sensor_subtype

    @camera_type.setter
    def camera_type(self, value: SensorSubType) -> None:
        if value not in (SensorSubType.PINHOLE, SensorSubType.ORTHOGRAPHIC):
            raise ValueError(f"camera_type must be PINHOLE or ORTHOGRAPHIC, got {value!r}")
        self.spec.sensor_subtype = value

    def zoom(self, factor: float) -> None:
        """Multiply the zoom by ``factor`` (> 1 narrows the view, Habitat's ``zoom``)."""
        if isinstance(factor, bool) or not math.isfinite(float(factor)) or float(factor) <= 0:
            raise ValueError(f"sensor {self.uuid!r}: zoom factor must be > 0, got {factor!r}")
        self._zoom *= float(factor)

    def reset_zoom(self) -> None:
        self._zoom = 1.0

    def set_width(self, width: int) -> None:
        self._set_resolution(int(self.spec.resolution[0]), width)

    def set_height(self, height: int) -> None:
        self._set_resolution(height, int(self.spec.resolution[1]))

    def _set_resolution(self, height: Any, width: Any) -> None:
        old = self.spec.resolution
        self.spec.resolution = [height, width]
        try:
            self.spec.pixel_resolution()
        except ValueError:
            self.spec.resolution = old
            raise

    def set_projection_params(self, sensor_spec: CameraSensorSpec) -> None:
        """Take ``sensor_spec``'s resolution and camera type (Habitat's rule)."""
        self._set_resolution(*sensor_spec.resolution)
        self.camera_type = sensor_spec.sensor_subtype

    @property
    def render_camera(self) -> RenderCamera:
        """The camera's projection, view matrix and unprojection (one per sensor)."""
        if self._render_camera is None:
            self._render_camera = RenderCamera(self)
        return self._render_camera

    def camera_key(self) -> tuple:
        """Intrinsics that decide the rasterization (sensors with equal keys and poses share):
        ``((H, W), hfov, near, far, subtype, ortho_scale)`` with the zoom applied
        (``tan(hfov' / 2) = tan(hfov / 2) / zoom``, ``ortho_scale' = ortho_scale * zoom``)."""
        spec = self.spec
        height, width = spec.pixel_resolution()
        hfov = float(spec.hfov)
        if self._zoom != 1.0:
            half = math.atan(math.tan(math.radians(hfov) / 2.0) / self._zoom)
            hfov = math.degrees(2.0 * half)
        return (
            (height, width),
            hfov,
            float(spec.near),
            float(spec.far),
            spec.sensor_subtype,
            float(spec.ortho_scale) * self._zoom,
        )
