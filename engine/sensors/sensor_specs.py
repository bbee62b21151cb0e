"""Habitat's sensor specs: what a sensor is asked to be, checked before anything is built.

``SensorType`` (COLOR, DEPTH, SEMANTIC ...), ``SensorSubType`` (PINHOLE, ORTHOGRAPHIC,
FISHEYE, EQUIRECTANGULAR), ``SemanticSensorTarget`` and the spec value classes
``SensorSpec`` (uuid, type, local ``position`` and ``orientation``: Euler angles in radians,
X then Y then Z), ``VisualSensorSpec`` (resolution ``[height, width]``, clear colour, near
and far planes) and ``CameraSensorSpec`` (``hfov`` in degrees, orthographic scale), following
``habitat_sim.sensor``'s fields and defaults. Specs compare field by field (arrays by value);
a bad field raises a clear exception naming it when the spec is checked. The sensors built
from specs are in :mod:`engine.sensors.cameras`, which re-exports these names.
"""

from __future__ import annotations

import math
from enum import Enum
from typing import Any

import numpy as np

from engine import mn
from engine.core.fixed_fields import FixedFields
from render.settings import check_pixel_budget

__all__ = [
    "CameraSensorSpec",
    "SemanticSensorTarget",
    "SensorSpec",
    "SensorSubType",
    "SensorType",
    "VisualSensorSpec",
]


class SensorType(Enum):
    """What a sensor measures (Habitat's ``SensorType``)."""

    NONE = 0
    COLOR = 1
    DEPTH = 2
    NORMAL = 3
    SEMANTIC = 4
    CUSTOM = 5
    AUDIO = 6


class SensorSubType(Enum):
    """The camera model (Habitat's ``SensorSubType``): pinhole and orthographic cameras are
    :class:`CameraSensorSpec` s; fisheye and equirectangular ones are cube-map sensors
    (:mod:`engine.sensors.cubemap`)."""

    NONE = 0
    PINHOLE = 1
    ORTHOGRAPHIC = 2
    FISHEYE = 3
    EQUIRECTANGULAR = 4
    CUSTOM = 5
    IMPULSERESPONSE = 6


class SemanticSensorTarget(Enum):
    """What a SEMANTIC sensor writes (Habitat's ``SensorSemanticTarget``); rigidsim writes
    each drawable's ``semantic_id`` for every value."""

    DRAWABLE_ID = 0
    SEMANTIC_ID = 1
    OBJECT_ID = 2


_VISUAL_TYPES = (SensorType.COLOR, SensorType.DEPTH, SensorType.SEMANTIC)


class SensorSpec(FixedFields):
    """Habitat's ``SensorSpec``: what every sensor has (uuid, type, pose on its node).

    Defaults as Habitat's: ``uuid`` ``""``, ``sensor_type`` and ``sensor_subtype`` NONE,
    ``position`` ``[0, 1.5, 0]``, ``orientation`` ``[0, 0, 0]`` (X, Y, Z Euler angles in
    radians), ``noise_model`` ``"None"``. A misspelt field raises ``AttributeError`` naming the
    closest one (Habitat's specs are fixed-field structs).
    """

    _extra_fields: tuple[str, ...] = (
        "uuid",
        "sensor_type",
        "sensor_subtype",
        "position",
        "orientation",
        "noise_model",
        "noise_model_kwargs",
    )
    #: the spec fields compared by ``==`` (Habitat's ``operator==``)
    _compared: tuple[str, ...] = (
        "uuid",
        "sensor_type",
        "sensor_subtype",
        "position",
        "orientation",
        "noise_model",
    )

    def __init__(self) -> None:
        self.uuid = ""
        self.sensor_type = SensorType.NONE
        self.sensor_subtype = SensorSubType.NONE
        self.position = [0.0, 1.5, 0.0]
        self.orientation = [0.0, 0.0, 0.0]
        self.noise_model = "None"
        self.noise_model_kwargs: dict[str, Any] = {}

    def is_visual_sensor_spec(self) -> bool:
        return False

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return all(_same(getattr(self, k), getattr(other, k)) for k in self._compared)

    __hash__ = object.__hash__  # specs are mutable structs, hashed by identity

    def validate(self) -> None:
        """Raise ValueError/TypeError naming the first bad field."""
        if not isinstance(self.uuid, str):
            raise TypeError(f"sensor uuid must be a string, got {self.uuid!r}")
        if not isinstance(self.sensor_type, SensorType):
            raise TypeError(f"sensor_type must be a SensorType, got {self.sensor_type!r}")
        if not isinstance(self.sensor_subtype, SensorSubType):
            raise TypeError(f"sensor_subtype must be a SensorSubType, got {self.sensor_subtype!r}")
        mn.to_vector3(self.position, f"sensor {self.uuid!r} position")
        mn.to_vector3(self.orientation, f"sensor {self.uuid!r} orientation")

    def _number(self, name: str) -> float:
        """Field ``name`` as a finite float, else TypeError/ValueError naming it."""
        value = getattr(self, name)
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
            raise TypeError(f"sensor {self.uuid!r}: {name} must be a number, got {value!r}")
        if not math.isfinite(float(value)):
            raise ValueError(f"sensor {self.uuid!r}: {name} must be finite, got {value!r}")
        return float(value)


def _same(a: Any, b: Any) -> bool:
    """Field equality for specs: sequences compare element-wise."""
    if isinstance(a, str | Enum | dict) or isinstance(b, str | Enum | dict) or a is None:
        return bool(a == b)
    try:
        return bool(np.array_equal(np.asarray(a, dtype=np.float64), np.asarray(b, np.float64)))
    except (TypeError, ValueError):
        return bool(a == b)


class VisualSensorSpec(SensorSpec):
    """Habitat's ``VisualSensorSpec``: an image sensor (``sensor_type`` COLOR by default).

    ``resolution`` is ``[height, width]`` (default ``[128, 128]``), ``near`` 0.01 and ``far``
    1000 m, ``channels`` 4, ``clear_color`` opaque black, ``semantic_target``
    SEMANTIC_ID. ``channels``, ``gpu2gpu_transfer`` and ``semantic_target`` are stored for
    compatibility; rigidsim renders COLOR as RGBA whatever ``channels`` says.
    """

    _extra_fields = (
        *SensorSpec._extra_fields,
        "resolution",
        "near",
        "far",
        "channels",
        "gpu2gpu_transfer",
        "semantic_target",
        "clear_color",
    )
    _compared = (
        *SensorSpec._compared,
        "resolution",
        "channels",
        "gpu2gpu_transfer",
        "far",
        "near",
        "clear_color",
    )

    def __init__(self) -> None:
        super().__init__()
        self.sensor_type = SensorType.COLOR
        self.resolution = [128, 128]
        self.near = 0.01
        self.far = 1000.0
        self.channels = 4
        self.gpu2gpu_transfer = False
        self.semantic_target = SemanticSensorTarget.SEMANTIC_ID
        self.clear_color = [0.0, 0.0, 0.0, 1.0]

    def is_visual_sensor_spec(self) -> bool:
        return True

    def validate(self) -> None:
        super().validate()
        if self.sensor_type not in _VISUAL_TYPES:
            raise ValueError(f"sensor {self.uuid!r}: unsupported sensor_type {self.sensor_type}")
        self.pixel_resolution()
        near, far = self._number("near"), self._number("far")
        if not 0.0 < near < far:
            raise ValueError(
                f"sensor {self.uuid!r}: need 0 < near < far, got "
                f"near={self.near!r}, far={self.far!r}"
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


class CameraSensorSpec(VisualSensorSpec):
    """A pinhole or orthographic camera, Habitat's defaults: ``uuid`` ``"rgba_camera"``,
    ``sensor_subtype`` PINHOLE, ``hfov`` 90 (horizontal, degrees), ``ortho_scale`` 0.1, and
    :class:`VisualSensorSpec`'s (``resolution`` ``[128, 128]``, ``position`` ``[0, 1.5, 0]``).
    """

    _extra_fields = (*VisualSensorSpec._extra_fields, "hfov", "ortho_scale")
    _compared = (*VisualSensorSpec._compared, "ortho_scale", "hfov")

    def __init__(self) -> None:
        super().__init__()
        self.uuid = "rgba_camera"
        self.sensor_subtype = SensorSubType.PINHOLE
        self.hfov = 90.0
        self.ortho_scale = 0.1

    def validate(self) -> None:
        """Raise ValueError/TypeError naming the first bad field."""
        super().validate()
        if self.sensor_subtype not in (SensorSubType.PINHOLE, SensorSubType.ORTHOGRAPHIC):
            raise ValueError(
                f"sensor {self.uuid!r}: a CameraSensorSpec is PINHOLE or ORTHOGRAPHIC, got "
                f"{self.sensor_subtype}; use FisheyeSensorDoubleSphereSpec or "
                "EquirectangularSensorSpec for the wide-angle models"
            )
        hfov = self._number("hfov")
        if not 0.0 < hfov < 180.0:
            raise ValueError(f"sensor {self.uuid!r}: hfov must be in (0, 180), got {self.hfov!r}")
        if self._number("ortho_scale") <= 0.0:
            raise ValueError(
                f"sensor {self.uuid!r}: ortho_scale must be > 0, got {self.ortho_scale!r}"
            )

    def __repr__(self) -> str:
        return (
            f"CameraSensorSpec(uuid={self.uuid!r}, {self.sensor_type.name}, "
            f"resolution={list(self.resolution)}, position={list(self.position)}, "
            f"orientation={list(self.orientation)}, hfov={self.hfov})"
        )
