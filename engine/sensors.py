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
share one rasterization (see :mod:`engine.scene_render`).
"""

from __future__ import annotations

import math
from enum import Enum
from typing import Any

import numpy as np

from engine import mn
from engine.fixed_fields import FixedFields
from engine.scene_node import SceneNode
from render.settings import check_pixel_budget

__all__ = ["CameraSensor", "CameraSensorSpec", "SensorSubType", "SensorType", "euler_xyz_matrix"]


class SensorType(Enum):
    """What a sensor measures (Habitat's ``SensorType``)."""

    NONE = 0
    COLOR = 1
    DEPTH = 2
    NORMAL = 3
    SEMANTIC = 4


class SensorSubType(Enum):
    """The camera model (Habitat's ``SensorSubType``)."""

    NONE = 0
    PINHOLE = 1
    ORTHOGRAPHIC = 2


class CameraSensorSpec(FixedFields):
    """A camera sensor's description, Habitat's defaults (``position`` is ``[0, 1.5, 0]``).

    ``resolution`` is ``[height, width]``; ``hfov`` is the horizontal field of view in degrees;
    ``orientation`` is X, Y, Z Euler angles in radians. A misspelt field raises
    ``AttributeError`` naming the closest one (Habitat's specs are fixed-field structs).
    ``channels``, ``gpu2gpu_transfer``, ``noise_model``, ``noise_model_kwargs`` and
    ``sensor_subtype``-specific Habitat fields are stored for compatibility; rigidsim renders
    COLOR as RGBA whatever ``channels`` says.
    """

    _extra_fields = (
        "uuid",
        "sensor_type",
        "sensor_subtype",
        "resolution",
        "position",
        "orientation",
        "hfov",
        "near",
        "far",
        "ortho_scale",
        "clear_color",
        "channels",
        "gpu2gpu_transfer",
        "noise_model",
        "noise_model_kwargs",
    )

    def __init__(self) -> None:
        self.uuid = ""
        self.sensor_type = SensorType.COLOR
        self.sensor_subtype = SensorSubType.PINHOLE
        self.resolution = [128, 128]
        self.position = [0.0, 1.5, 0.0]
        self.orientation = [0.0, 0.0, 0.0]
        self.hfov = 90.0
        self.near = 0.01
        self.far = 1000.0
        self.ortho_scale = 0.1
        self.clear_color = [0.0, 0.0, 0.0, 1.0]
        self.channels = 4
        self.gpu2gpu_transfer = False
        self.noise_model = "None"
        self.noise_model_kwargs: dict[str, Any] = {}

    def validate(self) -> None:
        """Raise ValueError/TypeError naming the first bad field."""
        if not isinstance(self.uuid, str):
            raise TypeError(f"sensor uuid must be a string, got {self.uuid!r}")
        if not isinstance(self.sensor_type, SensorType):
            raise TypeError(f"sensor_type must be a SensorType, got {self.sensor_type!r}")
        if self.sensor_type not in (SensorType.COLOR, SensorType.DEPTH, SensorType.SEMANTIC):
            raise ValueError(f"sensor {self.uuid!r}: unsupported sensor_type {self.sensor_type}")
        if not isinstance(self.sensor_subtype, SensorSubType):
            raise TypeError(f"sensor_subtype must be a SensorSubType, got {self.sensor_subtype!r}")
        self.pixel_resolution()
        mn.to_vector3(self.position, f"sensor {self.uuid!r} position")
        mn.to_vector3(self.orientation, f"sensor {self.uuid!r} orientation")
        hfov, near, far = (self._number(name) for name in ("hfov", "near", "far"))
        if not 0.0 < hfov < 180.0:
            raise ValueError(f"sensor {self.uuid!r}: hfov must be in (0, 180), got {self.hfov!r}")
        if not 0.0 < near < far:
            raise ValueError(
                f"sensor {self.uuid!r}: need 0 < near < far, got "
                f"near={self.near!r}, far={self.far!r}"
            )
        if self._number("ortho_scale") <= 0.0:
            raise ValueError(
                f"sensor {self.uuid!r}: ortho_scale must be > 0, got {self.ortho_scale!r}"
            )

    def pixel_resolution(self) -> tuple[int, int]:
        """``(height, width)`` as ints: whole, >= 1 and within the render budget
        (``render.settings.MAX_PIXELS``), else ValueError naming the sensor."""
        try:
            resolution = np.asarray(self.resolution, dtype=np.float64)
        except (TypeError, ValueError):
            resolution = None
        if (
            resolution is None
            or resolution.shape != (2,)
            or not np.all(np.isfinite(resolution))
            or np.any(resolution < 1)
            or np.any(resolution != np.round(resolution))
        ):
            raise ValueError(
                f"sensor {self.uuid!r}: resolution must be [height, width], two "
                f"whole numbers >= 1, got {self.resolution!r}"
            )
        height, width = (int(v) for v in resolution)
        check_pixel_budget(height, width, f"sensor {self.uuid!r} resolution")
        return height, width

    def _number(self, name: str) -> float:
        """Field ``name`` as a finite float, else TypeError/ValueError naming it."""
        value = getattr(self, name)
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
            raise TypeError(f"sensor {self.uuid!r}: {name} must be a number, got {value!r}")
        if not math.isfinite(float(value)):
            raise ValueError(f"sensor {self.uuid!r}: {name} must be finite, got {value!r}")
        return float(value)

    def __repr__(self) -> str:
        return (
            f"CameraSensorSpec(uuid={self.uuid!r}, {self.sensor_type.name}, "
            f"resolution={list(self.resolution)}, position={list(self.position)}, "
            f"orientation={list(self.orientation)}, hfov={self.hfov})"
        )


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


class CameraSensor:
    """A sensor instance: its spec and the scene node that carries it (child of the agent)."""

    def __init__(self, spec: CameraSensorSpec, agent_node: SceneNode) -> None:
        spec.validate()
        self.spec = spec
        self.node = SceneNode(agent_node, name=f"sensor:{spec.uuid}")
        self.reset_pose()

    @property
    def uuid(self) -> str:
        return self.spec.uuid

    @property
    def object(self) -> SceneNode:
        """Habitat's name for the node the sensor is attached to (its own node)."""
        return self.node

    def specification(self) -> CameraSensorSpec:
        return self.spec

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

    def set_transformation_from_spec(self) -> None:
        """Habitat's name for :meth:`reset_pose`."""
        self.reset_pose()

    def reset_pose(self) -> None:
        """Put the sensor node back at the spec's position and orientation."""
        self.node.translation = self.spec.position
        self.node.rotation = mn.Quaternion.from_matrix(euler_xyz_matrix(self.spec.orientation))

    def camera_key(self) -> tuple:
        """Intrinsics that decide the rasterization (sensors with equal keys and poses share)."""
        spec = self.spec
        height, width = spec.pixel_resolution()
        return (
            (height, width),
            float(spec.hfov),
            float(spec.near),
            float(spec.far),
            spec.sensor_subtype,
            float(spec.ortho_scale),
        )

    def world_from_camera(self) -> np.ndarray:
        """The camera pose ``(4, 4)``: agent node pose times the sensor's local pose."""
        return self.node.world_matrix()
