"""Wide-angle camera models: which direction each pixel of the image looks along.

A pinhole camera cannot see more than 180 degrees; a fisheye or a panorama can. rigidsim
(like Habitat's ``CubeMapSensorBase``) renders such a camera in two steps: six 90-degree
pinhole images around the camera (a cube map, :mod:`render.cubemap`), then, for every
output pixel, the direction the camera model assigns to it, looked up in the cube map.
This module holds the second half's geometry: pixel -> unit ray (and, for the tests and the
notebook, ray -> pixel).

Conventions
-----------
* Rays are in the **camera frame** of :mod:`render.camera`: +X right, +Y up, the camera
  looks down **-Z**.
* Pixel ``(row, col)`` has its center at ``(col + 0.5, row + 0.5)``, row 0 at the top.
  Habitat's shaders work in OpenGL window coordinates, whose origin is the **bottom**-left
  corner; with ``u = col + 0.5`` and ``v = H - (row + 0.5)`` the formulas below are
  Habitat's, and the image rows come out top first.

Double-sphere fisheye (Usenko, Demmel and Cremers, "The Double Sphere Camera Model", 3DV
2018; Habitat's ``FisheyeSensorDoubleSphereSpec``). With focal lengths ``(fx, fy)``,
principal point ``(cu, cv)`` (window coordinates), and the model's forward axis
``z_m = -z_camera``, a point ``(x, y, z_m)`` projects to::

    d1 = sqrt(x^2 + y^2 + z_m^2)
    d2 = sqrt(x^2 + y^2 + (xi d1 + z_m)^2)
    u  = cu + fx x / (alpha d2 + (1 - alpha) (xi d1 + z_m))
    v  = cv + fy y / (alpha d2 + (1 - alpha) (xi d1 + z_m))

and a pixel unprojects to the ray (paper, eq. 47-49)::

    m = ((u - cu) / fx, (v - cv) / fy),   r^2 = |m|^2
    m_z = (1 - alpha^2 r^2) / (alpha sqrt(1 - (2 alpha - 1) r^2) + 1 - alpha)
    ray = (m_z xi + sqrt(m_z^2 + (1 - xi^2) r^2)) / (m_z^2 + r^2) * (m_x, m_y, m_z) - (0, 0, xi)

Pixels where a square root is negative (outside the lens circle when alpha > 0.5) see
nothing: Habitat discards them, rigidsim leaves them at the background.

Equirectangular panorama (Habitat's ``EquirectangularSensorSpec``): longitude ``phi`` runs
over the width, colatitude ``theta`` over the height::

    phi = 2 pi u / W,   theta = pi v / H
    ray = (-sin(phi) sin(theta), -cos(theta), cos(phi) sin(theta))

so the image center looks forward (-Z), its left quarter left (-X), the top row straight up.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "double_sphere_project",
    "double_sphere_rays",
    "equirectangular_project",
    "equirectangular_rays",
    "window_coordinates",
]


def window_coordinates(height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """OpenGL window coordinates of every pixel center, each ``(H, W)`` float64.

    ``u = col + 0.5`` (rightwards), ``v = H - (row + 0.5)`` (upwards from the bottom edge).
    """
    u = np.arange(width, dtype=np.float64) + 0.5
    v = height - (np.arange(height, dtype=np.float64) + 0.5)
    return np.broadcast_to(u[None, :], (height, width)), np.broadcast_to(
        v[:, None], (height, width)
    )


def double_sphere_rays(
    resolution: tuple[int, int],
    focal_length: tuple[float, float],
    principal_point: tuple[float, float],
    xi: float,
    alpha: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Unit camera-frame rays of a double-sphere fisheye (module docstring).

    Parameters
    ----------
    resolution : (H, W) pixels.
    focal_length : (fx, fy) pixels.
    principal_point : (cu, cv) window coordinates (Habitat's ``principal_point_offset``).
    xi, alpha : the model's two parameters (alpha in [0, 1]).

    Returns
    -------
    rays : (H, W, 3) float64 unit vectors, camera frame (-Z forward); zero where invalid.
    valid : (H, W) bool, the pixels that see something.
    """
    height, width = resolution
    u, v = window_coordinates(height, width)
    mx = (u - principal_point[0]) / focal_length[0]
    my = (v - principal_point[1]) / focal_length[1]
    r2 = mx * mx + my * my
    sq1 = 1.0 - (2.0 * alpha - 1.0) * r2
    valid = sq1 >= 0.0
    mz = (1.0 - alpha * alpha * r2) / (alpha * np.sqrt(np.maximum(sq1, 0.0)) + 1.0 - alpha)
    sq2 = mz * mz + (1.0 - xi * xi) * r2
    valid &= sq2 >= 0.0
    scale = (mz * xi + np.sqrt(np.maximum(sq2, 0.0))) / (mz * mz + r2)
    # ray = scale * (mx, my, mz) - (0, 0, xi), in the model's frame (z forward)
    rays = np.stack([scale * mx, scale * my, -(scale * mz - xi)], axis=-1)  # z_cam = -z_m
    norm = np.linalg.norm(rays, axis=-1, keepdims=True)
    valid &= norm[..., 0] > 0.0
    rays = np.where(valid[..., None], rays / np.where(norm > 0.0, norm, 1.0), 0.0)
    return rays, valid


def double_sphere_project(
    points_camera: np.ndarray,
    resolution: tuple[int, int],
    focal_length: tuple[float, float],
    principal_point: tuple[float, float],
    xi: float,
    alpha: float,
) -> np.ndarray:
    """Continuous image coordinates ``(px, py)`` (px right, py down from the top) of
    camera-frame points ``(N, 3)`` under the double-sphere model (module docstring)."""
    pts = np.asarray(points_camera, dtype=np.float64).reshape(-1, 3)
    x, y, zm = pts[:, 0], pts[:, 1], -pts[:, 2]
    d1 = np.sqrt(x * x + y * y + zm * zm)
    shifted = xi * d1 + zm
    d2 = np.sqrt(x * x + y * y + shifted * shifted)
    denom = alpha * d2 + (1.0 - alpha) * shifted
    u = principal_point[0] + focal_length[0] * x / denom
    v = principal_point[1] + focal_length[1] * y / denom
    return np.stack([u, resolution[0] - v], axis=1)  # py = H - v


def equirectangular_rays(resolution: tuple[int, int]) -> np.ndarray:
    """Unit camera-frame rays ``(H, W, 3)`` of an equirectangular panorama."""
    height, width = resolution
    u, v = window_coordinates(height, width)
    phi = u * (2.0 * math.pi / width)
    theta = v * (math.pi / height)
    sin_theta = np.sin(theta)
    return np.stack([-np.sin(phi) * sin_theta, -np.cos(theta), np.cos(phi) * sin_theta], axis=-1)


def equirectangular_project(points_camera: np.ndarray, resolution: tuple[int, int]) -> np.ndarray:
    """Continuous image coordinates ``(px, py)`` of camera-frame points ``(N, 3)`` in an
    equirectangular panorama (the inverse of :func:`equirectangular_rays`)."""
    pts = np.asarray(points_camera, dtype=np.float64).reshape(-1, 3)
    height, width = resolution
    ray = pts / np.linalg.norm(pts, axis=1, keepdims=True)
    theta = np.arccos(np.clip(-ray[:, 1], -1.0, 1.0))  # m_y = -cos(theta)
    phi = np.mod(np.arctan2(-ray[:, 0], ray[:, 2]), 2.0 * math.pi)  # (-sin phi, cos phi)
    u = phi * width / (2.0 * math.pi)
    v = theta * height / math.pi
    return np.stack([u, height - v], axis=1)
