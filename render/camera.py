"""Camera model: intrinsics, the world-to-camera transform and the projection to pixels.

Conventions (the same everywhere in rigidsim)
---------------------------------------------
* Camera frame: right handed, the camera looks down its local **-Z** axis, **+Y** is up and
  **+X** is right. A pose ``world_from_camera`` is a ``(4, 4)`` float64 rigid transform.
* Pixel frame: continuous coordinates ``(px, py)`` in pixels, ``px`` to the right, ``py``
  down, the top-left corner of the image at ``(0, 0)``. Pixel ``(row, col)`` covers
  ``[col, col + 1) x [row, row + 1)`` and its **center** is ``(col + 0.5, row + 0.5)``.
  Row 0 is the top row of the image.
* Depth is the **z-depth** ``z = -z_camera`` (distance along the optical axis, not the ray
  length), in meters.

Pinhole projection (Habitat's ``CameraSensorSpec``: ``hfov`` in degrees, horizontal)::

    fx = fy = (W / 2) / tan(hfov / 2),   cx = W / 2,   cy = H / 2
    a camera-frame point (x, y, -z) with z > 0 lands at
    px = cx + fx * x / z,   py = cy - fy * y / z

(720 x 544 at 90 degrees gives fx = 360 px.)

Orthographic projection (Habitat's ``OrthographicCamera``: the view is ``1 / ortho_scale``
meters wide and ``(H / W) / ortho_scale`` meters tall)::

    s = W * ortho_scale  (pixels per meter)
    px = cx + s * x,   py = cy - s * y,   depth z = -z_camera
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from render.settings import check_pixel_budget

PINHOLE = "pinhole"
ORTHOGRAPHIC = "orthographic"
_SUBTYPES = (PINHOLE, ORTHOGRAPHIC)


def _check_positive_finite(name: str, value: float) -> float:
    """Return ``value`` as a float, raising ValueError naming ``name`` unless finite and > 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return value


def _check_resolution(resolution: tuple[int, int]) -> tuple[int, int]:
    """Validate ``resolution = (H, W)``: two positive integers."""
    try:
        height, width = resolution
    except (TypeError, ValueError):
        raise ValueError(f"resolution must be (height, width), got {resolution!r}") from None
    for name, n in (("height", height), ("width", width)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n <= 0:
            raise ValueError(f"resolution {name} must be a positive int, got {resolution!r}")
    check_pixel_budget(height, width, "camera resolution")
    return int(height), int(width)


def check_pose(pose: np.ndarray, name: str = "world_from_camera") -> np.ndarray:
    """Return ``pose`` as a ``(4, 4)`` float64 array, raising ValueError if malformed.

    The last row must be ``[0, 0, 0, 1]`` (an affine transform) and every entry finite.
    """
    if pose is None:
        raise ValueError(f"{name} must be a (4, 4) matrix, got None")
    arr = np.asarray(pose, dtype=np.float64)
    if arr.shape != (4, 4):
        raise ValueError(f"{name} must have shape (4, 4), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {arr.tolist()}")
    if not np.allclose(arr[3], (0.0, 0.0, 0.0, 1.0), atol=1e-9):
        raise ValueError(f"{name} last row must be [0, 0, 0, 1], got {arr[3].tolist()}")
    return arr


def invert_rigid(world_from_camera: np.ndarray) -> np.ndarray:
    """Invert a rigid (rotation + translation) pose: ``camera_from_world``.

    For ``T = [R t; 0 1]`` the inverse is ``[R^T  -R^T t; 0 1]``. Falls back to a general
    inverse when ``R`` is not orthonormal (a scaled camera node).
    """
    pose = check_pose(world_from_camera)
    rot = pose[:3, :3]
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6):
        return np.linalg.inv(pose)
    inverse = np.eye(4)
    inverse[:3, :3] = rot.T  # R^-1 = R^T
    inverse[:3, 3] = -rot.T @ pose[:3, 3]  # t' = -R^T t
    return inverse


@dataclass(frozen=True)
class Camera:
    """A pinhole or orthographic camera (Habitat's ``CameraSensorSpec`` subset).

    Parameters
    ----------
    resolution : (H, W) ints, image height and width in pixels (Habitat's order).
    hfov : float, horizontal field of view in degrees, in (0, 180). Default 90.
    near, far : float, clip distances in meters along the view axis, 0 < near < far.
    subtype : ``"pinhole"`` or ``"orthographic"``.
    ortho_scale : float > 0, orthographic only: the view is ``1 / ortho_scale`` m wide.
    """

    resolution: tuple[int, int]
    hfov: float = 90.0
    near: float = 0.01
    far: float = 1000.0
    subtype: str = PINHOLE
    ortho_scale: float = 0.1

    def __post_init__(self) -> None:
        object.__setattr__(self, "resolution", _check_resolution(self.resolution))
        hfov = _check_positive_finite("hfov", self.hfov)
        if hfov >= 180.0:
            raise ValueError(f"hfov must be in (0, 180) degrees, got {hfov!r}")
        near = _check_positive_finite("near", self.near)
        far = _check_positive_finite("far", self.far)
        if far <= near:
            raise ValueError(f"far must be > near, got near={near!r}, far={far!r}")
        if self.subtype not in _SUBTYPES:
            raise ValueError(f"subtype must be one of {_SUBTYPES}, got {self.subtype!r}")
        ortho_scale = _check_positive_finite("ortho_scale", self.ortho_scale)
        for name, value in (("hfov", hfov), ("near", near), ("far", far)):
            object.__setattr__(self, name, value)
        object.__setattr__(self, "ortho_scale", ortho_scale)

    @property
    def height(self) -> int:
        """Image height H in pixels."""
        return self.resolution[0]

    @property
    def width(self) -> int:
        """Image width W in pixels."""
        return self.resolution[1]

    @property
    def is_pinhole(self) -> bool:
        """True for a perspective camera, False for an orthographic one."""
        return self.subtype == PINHOLE

    @property
    def fx(self) -> float:
        """Focal length in pixels: (W / 2) / tan(hfov / 2) (pinhole); W * ortho_scale (ortho)."""
        if self.is_pinhole:
            return (self.width / 2.0) / math.tan(math.radians(self.hfov) / 2.0)
        return self.width * self.ortho_scale

    @property
    def fy(self) -> float:
        """Vertical focal length in pixels, equal to fx (square pixels)."""
        return self.fx

    @property
    def cx(self) -> float:
        """Principal point x = W / 2 (pixels)."""
        return self.width / 2.0

    @property
    def cy(self) -> float:
        """Principal point y = H / 2 (pixels)."""
        return self.height / 2.0

    def intrinsics(self) -> np.ndarray:
        """The ``(3, 3)`` matrix K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (pinhole form)."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def project(self, points_camera: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Project camera-frame points to continuous pixel coordinates.

        Parameters
        ----------
        points_camera : (N, 3) float, camera frame (looking down -Z), meters. Pinhole
            points must be in front of the camera (z_camera < 0) to be meaningful.

        Returns
        -------
        pixels : (N, 2) float64, ``(px, py)`` with ``px = cx + fx x / z``,
            ``py = cy - fy y / z`` (pinhole) or ``px = cx + s x``, ``py = cy - s y`` (ortho).
        depth : (N,) float64, z-depth ``z = -z_camera`` in meters.
        """
        pts = np.asarray(points_camera, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(f"points_camera must have shape (N, 3), got {pts.shape}")
        depth = -pts[:, 2]  # z = -z_camera
        if self.is_pinhole:
            with np.errstate(divide="ignore", invalid="ignore"):
                inv_depth = 1.0 / depth
            px = self.cx + self.fx * pts[:, 0] * inv_depth  # px = cx + fx x / z
            py = self.cy - self.fy * pts[:, 1] * inv_depth  # py = cy - fy y / z
        else:
            px = self.cx + self.fx * pts[:, 0]  # px = cx + s x
            py = self.cy - self.fy * pts[:, 1]  # py = cy - s y
        return np.stack([px, py], axis=1), depth

    def pixel_rays(self) -> np.ndarray:
        """Camera-frame ray directions through every pixel center, ``(H, W, 3)``.

        Pinhole: ``((px - cx) / fx, -(py - cy) / fy, -1)`` (unnormalized, z-component -1, so
        a point at z-depth ``d`` on the ray is ``d * ray``). Orthographic: ``(0, 0, -1)``.
        """
        cols = np.arange(self.width) + 0.5
        rows = np.arange(self.height) + 0.5
        rays = np.empty((self.height, self.width, 3))
        if self.is_pinhole:
            rays[..., 0] = ((cols - self.cx) / self.fx)[None, :]  # x / z = (px - cx) / fx
            rays[..., 1] = (-(rows - self.cy) / self.fy)[:, None]  # y / z = -(py - cy) / fy
        else:
            rays[..., :2] = 0.0
        rays[..., 2] = -1.0
        return rays
