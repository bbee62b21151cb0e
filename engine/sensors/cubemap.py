"""Wide-angle sensors: Habitat's fisheye (double sphere) and equirectangular cameras.

Both are cube-map sensors (Habitat's ``CubeMapSensorBase``): each observation is six
90-degree pinhole renders around the sensor (``S x S`` pixels, ``S = cubemap_size`` or
``min(H, W)``), resampled through the camera model. The renderer sees the six faces as six
ordinary pinhole cameras (:class:`CubeFace`), so a COLOR, a DEPTH and a SEMANTIC fisheye at
the same pose share one rasterization per face, like any sensors with equal intrinsics and
pose. The geometry is in :mod:`render.camera_models` (pixel -> ray) and
:mod:`render.cubemap` (ray -> face texel).

Specs and defaults as Habitat's: ``CubeMapSensorBaseSpec`` (``cubemap_size`` None),
``FisheyeSensorSpec`` (uuid ``"fisheye"``, ``focal_length`` ``[0, 0]``, which must be set,
``principal_point_offset`` None = ``resolution / 2``, ``sensor_model_type`` DOUBLE_SPHERE),
``FisheyeSensorDoubleSphereSpec`` (``alpha`` 0.59, ``xi`` -0.18) and
``EquirectangularSensorSpec`` (uuid ``"equirectangular"``).

As in Habitat, the default principal point is ``resolution * 0.5`` read as ``(u, v)`` although
``resolution`` is ``[height, width]``: the image center only for square images.
DEPTH is the z-depth along the axis of the cube face the ray hits (what Habitat's cube map of
depth buffers holds); pixels outside the fisheye's image circle read 0 (black, id 0). COLOR
is filtered bilinearly within a face, DEPTH and SEMANTIC take the nearest texel
(:mod:`render.cubemap`).
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from typing import Any

import numpy as np

from engine import mn
from engine.scene.graph import SceneNode
from engine.sensors.cameras import Sensor, SensorSubType, SensorType, VisualSensorSpec
from render import camera_models, cubemap

__all__ = [
    "CubeFace",
    "CubeMapSensorBase",
    "CubeMapSensorBaseSpec",
    "EquirectangularSensor",
    "EquirectangularSensorSpec",
    "FisheyeSensor",
    "FisheyeSensorDoubleSphereSpec",
    "FisheyeSensorModelType",
    "FisheyeSensorSpec",
    "observe_later_with_cube_maps",
    "observe_with_cube_maps",
]


class FisheyeSensorModelType(Enum):
    """Habitat's fisheye models (only the double sphere exists)."""

    DOUBLE_SPHERE = 0


class CubeMapSensorBaseSpec(VisualSensorSpec):
    """A sensor rendered through a cube map; ``cubemap_size`` None: ``min(H, W)``."""

    _extra_fields = (*VisualSensorSpec._extra_fields, "cubemap_size")
    _compared = (*VisualSensorSpec._compared, "cubemap_size")

    def __init__(self) -> None:
        super().__init__()
        self.uuid = "cubemap_sensor_base"
        self.sensor_subtype = SensorSubType.NONE
        self.cubemap_size: int | None = None

    def validate(self) -> None:
        super().validate()
        size = cubemap.cubemap_size(self.pixel_resolution(), self.cubemap_size)
        if size > 4096:
            raise ValueError(f"sensor {self.uuid!r}: cubemap_size {size} exceeds 4096")


class EquirectangularSensorSpec(CubeMapSensorBaseSpec):
    """A 360 x 180 degree panorama (Habitat's ``EquirectangularSensorSpec``)."""

    def __init__(self) -> None:
        super().__init__()
        self.uuid = "equirectangular"
        self.sensor_subtype = SensorSubType.EQUIRECTANGULAR

    def validate(self) -> None:
        super().validate()
        if self.sensor_subtype is not SensorSubType.EQUIRECTANGULAR:
            raise ValueError(
                f"sensor {self.uuid!r}: sensor_subtype must be EQUIRECTANGULAR, "
                f"got {self.sensor_subtype}"
            )


class FisheyeSensorSpec(CubeMapSensorBaseSpec):
    """A fisheye camera (Habitat's ``FisheyeSensorSpec``): ``focal_length`` ``(fx, fy)`` in
    pixels (> 0, no default), ``principal_point_offset`` ``(cu, cv)`` or None."""

    _extra_fields = (
        *CubeMapSensorBaseSpec._extra_fields,
        "focal_length",
        "principal_point_offset",
        "sensor_model_type",
    )
    _compared = (
        *CubeMapSensorBaseSpec._compared,
        "sensor_model_type",
        "focal_length",
        "principal_point_offset",
    )

    def __init__(self) -> None:
        super().__init__()
        self.uuid = "fisheye"
        self.sensor_subtype = SensorSubType.FISHEYE
        self.focal_length: Any = mn.Vector2(0.0, 0.0)
        self.principal_point_offset: Any = None
        self.sensor_model_type = FisheyeSensorModelType.DOUBLE_SPHERE

    def validate(self) -> None:
        super().validate()
        if self.sensor_subtype is not SensorSubType.FISHEYE:
            raise ValueError(
                f"sensor {self.uuid!r}: sensor_subtype must be FISHEYE, got {self.sensor_subtype}"
            )
        focal = _pair(self.focal_length, f"sensor {self.uuid!r} focal_length")
        if min(focal) <= 0.0:
            raise ValueError(
                f"sensor {self.uuid!r}: focal_length must be > 0, got {self.focal_length!r}"
            )
        if self.principal_point_offset is not None:
            _pair(self.principal_point_offset, f"sensor {self.uuid!r} principal_point_offset")

    def principal_point(self) -> tuple[float, float]:
        """``principal_point_offset``, or Habitat's default ``resolution * 0.5``."""
        if self.principal_point_offset is not None:
            return _pair(self.principal_point_offset, "principal_point_offset")
        return (float(self.resolution[0]) * 0.5, float(self.resolution[1]) * 0.5)


class FisheyeSensorDoubleSphereSpec(FisheyeSensorSpec):
    """The double-sphere fisheye (Usenko et al. 2018): ``alpha`` in [0, 1] (0.59), ``xi``
    (-0.18), Habitat's defaults."""

    _extra_fields = (*FisheyeSensorSpec._extra_fields, "alpha", "xi")
    _compared = (*FisheyeSensorSpec._compared, "alpha", "xi")

    def __init__(self) -> None:
        super().__init__()
        self.alpha = 0.59
        self.xi = -0.18

    def validate(self) -> None:
        super().validate()
        if not 0.0 <= self._number("alpha") <= 1.0:
            raise ValueError(f"sensor {self.uuid!r}: alpha must be in [0, 1], got {self.alpha!r}")
        self._number("xi")


def _pair(value: Any, name: str) -> tuple[float, float]:
    """Two finite floats, else ValueError naming ``name``."""
    try:
        array = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        array = np.zeros(0)
    if array.shape != (2,) or not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be two finite numbers, got {value!r}")
    return float(array[0]), float(array[1])


class CubeFace:
    """One face of a cube-map sensor, seen by the renderer as a 90-degree pinhole camera."""

    def __init__(self, owner: CubeMapSensorBase, index: int) -> None:
        self.owner = owner
        self.index = index
        self.uuid = f"{owner.uuid}:cube{cubemap.FACE_NAMES[index]}"
        self.spec = owner.spec

    def camera_key(self) -> tuple:
        size = self.owner.face_size()
        spec = self.spec
        return ((size, size), 90.0, float(spec.near), float(spec.far), SensorSubType.PINHOLE, 0.1)

    def world_from_camera(self) -> np.ndarray:
        return cubemap.face_poses(self.owner.world_from_camera())[self.index]


class CubeMapSensorBase(Sensor):
    """A sensor observed through a cube map (module docstring); subclasses give the rays."""

    spec: CubeMapSensorBaseSpec
    #: True: resample with the plain per-pixel loop (:func:`render.cubemap.resample_reference`)
    reference_resampling = False

    def __init__(self, spec: CubeMapSensorBaseSpec, parent_node: SceneNode) -> None:
        super().__init__(spec, parent_node)
        self._faces = [CubeFace(self, index) for index in range(6)]  # stable: the renderer
        # keeps per-camera state (static layers) keyed by these objects
        self._rays_key: tuple | None = None
        self._rays: tuple[np.ndarray, np.ndarray | None] = (np.zeros((0, 0, 3)), None)

    def face_size(self) -> int:
        return cubemap.cubemap_size(self.spec.pixel_resolution(), self.spec.cubemap_size)

    def faces(self) -> list[CubeFace]:
        return self._faces

    def model_key(self) -> tuple:
        """Everything the rays depend on (they are recomputed when it changes)."""
        return (self.spec.pixel_resolution(),)

    def compute_rays(self) -> tuple[np.ndarray, np.ndarray | None]:
        raise NotImplementedError

    def rays(self) -> tuple[np.ndarray, np.ndarray | None]:
        """``(H, W, 3)`` camera-frame rays and the valid mask (None: all), cached."""
        key = self.model_key()
        if key != self._rays_key:
            self._rays, self._rays_key = self.compute_rays(), key
        return self._rays

    def resample(self, face_observations: list[np.ndarray]) -> np.ndarray:
        """This sensor's observation from its six faces' observations (Habitat's order):
        COLOR filtered bilinearly, DEPTH and SEMANTIC from the nearest texel."""
        rays, valid = self.rays()
        faces = np.stack(face_observations)
        bilinear = self.spec.sensor_type is SensorType.COLOR
        return cubemap.resample(
            faces, rays, valid, 0, reference=self.reference_resampling, bilinear=bilinear
        )


class FisheyeSensor(CubeMapSensorBase):
    """Habitat's ``FisheyeSensor`` with the double-sphere model."""

    spec: FisheyeSensorDoubleSphereSpec

    def __init__(self, spec: FisheyeSensorSpec, parent_node: SceneNode) -> None:
        if not isinstance(spec, FisheyeSensorDoubleSphereSpec):
            raise TypeError(
                "FisheyeSensor needs a FisheyeSensorDoubleSphereSpec (the only fisheye model), "
                f"got {type(spec).__name__}"
            )
        super().__init__(spec, parent_node)

    def model_key(self) -> tuple:
        spec = self.spec
        focal = _pair(spec.focal_length, "focal_length")
        return (spec.pixel_resolution(), focal, spec.principal_point(), spec.xi, spec.alpha)

    def compute_rays(self) -> tuple[np.ndarray, np.ndarray | None]:
        resolution, focal, principal, xi, alpha = self.model_key()
        return camera_models.double_sphere_rays(
            resolution, focal, principal, float(xi), float(alpha)
        )


class EquirectangularSensor(CubeMapSensorBase):
    """Habitat's ``EquirectangularSensor``: the whole sphere of directions."""

    def compute_rays(self) -> tuple[np.ndarray, np.ndarray | None]:
        return camera_models.equirectangular_rays(self.spec.pixel_resolution()), None


def observe_with_cube_maps(
    observe: Callable[[list], dict[str, np.ndarray]], sensors: list, overlay: Any = None
) -> dict[str, np.ndarray]:
    """Observations of ``sensors`` (uuid -> array): cube-map sensors are expanded into their
    six faces, rendered in the same ``observe`` call as the other sensors, then resampled.

    ``overlay`` (an :class:`engine.sensors.line_overlay.LineOverlay`, or None): its ``twins`` are
    rendered too and it draws into the frames (the faces included) before the resampling.
    """
    return observe_later_with_cube_maps(lambda flat: lambda: observe(flat), sensors, overlay)()


def observe_later_with_cube_maps(
    observe_later: Callable[[list], Callable[[], dict[str, np.ndarray]]],
    sensors: list,
    overlay: Any = None,
) -> Callable[[], dict[str, np.ndarray]]:
    """:func:`observe_with_cube_maps` in two halves (``SceneRenderer.observe_later`` or
    ``observe_in_worker``; None when the latter declines)."""
    twins = list(overlay.twins) if overlay is not None else []
    render = observe_later(_with_faces(sensors) + twins)
    if render is None:
        return None  # type: ignore[return-value]

    def finish() -> dict[str, np.ndarray]:
        rendered = render()
        if overlay is not None:
            overlay.draw(rendered)
        return _resample_cube_maps(sensors, rendered)

    return finish


def _with_faces(sensors: list) -> list:
    """``sensors`` with each cube-map sensor replaced by its six faces."""
    flat: list = []
    for sensor in sensors:
        flat.extend(sensor.faces() if isinstance(sensor, CubeMapSensorBase) else [sensor])
    return flat


def _resample_cube_maps(sensors: list, rendered: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    observations = {}
    for sensor in sensors:
        if isinstance(sensor, CubeMapSensorBase):
            faces = [rendered[face.uuid] for face in sensor.faces()]
            observations[sensor.uuid] = sensor.resample(faces)
        else:
            observations[sensor.uuid] = rendered[sensor.uuid]
    return observations
