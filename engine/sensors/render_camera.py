"""Habitat's ``RenderCamera`` (``sensor.render_camera``): a camera sensor's matrices.

Programs written for Habitat project points into a sensor's image and cast picking rays
through its pixels with these matrices (OpenGL conventions, as Magnum's ``Camera3D``):

* ``camera_matrix`` = ``camera_from_world``, the inverse of the sensor node's world pose;
* ``projection_matrix`` maps camera-frame points to clip space. For a pinhole camera with
  near-plane width ``w = 2 n tan(hfov / 2)`` and height ``h = w H / W``::

      [[2n/w, 0, 0, 0], [0, 2n/h, 0, 0], [0, 0, (f+n)/(n-f), 2fn/(n-f)], [0, 0, -1, 0]]

  and for an orthographic one, ``1 / ortho_scale`` meters wide (``w``) and ``w H / W`` tall::

      [[2/w, 0, 0, 0], [0, 2/h, 0, 0], [0, 0, 2/(n-f), (f+n)/(n-f)], [0, 0, 0, 1]]

  so ``projection_matrix.transform_point(camera_matrix.transform_point(p))`` gives normalized
  device coordinates in ``[-1, 1]`` (x right, y up);
* ``projection_size()`` = ``(2 / P[0][0], 2 / P[1][1])`` (Magnum's: the view's size at unit
  distance for a pinhole camera), ``viewport`` = ``(W, H)`` pixels;
* ``unproject(pixel)`` is the world ray from the camera through integer pixel ``(x, y)``
  (y down, Habitat does not add the half-pixel): the far-plane point of normalized device
  coordinates ``(2 x / W - 1, 2 (H - y - 1) / H - 1, 1)``, minus the origin, divided by ``far``
  (and normalized unless ``normalized=False``).

Zoom (``sensor.zoom(f)``) is part of the projection, as in Habitat.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from engine import mn
from engine.geo import Ray
from render.camera import Camera

__all__ = ["RenderCamera", "camera_from_key", "projection_matrix"]


def projection_matrix(camera_key: tuple) -> np.ndarray:
    """The OpenGL projection ``(4, 4)`` of a sensor's ``camera_key()`` (module docstring)."""
    (height, width), hfov, near, far, subtype, ortho_scale = camera_key
    matrix = np.zeros((4, 4))
    if subtype.name == "ORTHOGRAPHIC":
        size_w = 1.0 / ortho_scale
        size_h = size_w * height / width
        matrix[0, 0], matrix[1, 1] = 2.0 / size_w, 2.0 / size_h
        matrix[2, 2], matrix[2, 3] = 2.0 / (near - far), (far + near) / (near - far)
        matrix[3, 3] = 1.0
        return matrix
    size_w = 2.0 * near * math.tan(math.radians(hfov) / 2.0)
    size_h = size_w * height / width
    matrix[0, 0], matrix[1, 1] = 2.0 * near / size_w, 2.0 * near / size_h
    matrix[2, 2], matrix[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    matrix[3, 2] = -1.0
    return matrix


def camera_from_key(key: tuple) -> Camera:
    """The :class:`render.camera.Camera` of a sensor's ``camera_key()``: ``((H, W), hfov,
    near, far, subtype, ortho_scale)`` (orthographic for ORTHOGRAPHIC, else pinhole)."""
    (height, width), hfov, near, far, subtype, ortho_scale = key
    kind = "orthographic" if subtype.name == "ORTHOGRAPHIC" else "pinhole"
    return Camera((height, width), hfov, near, far, kind, ortho_scale)


class RenderCamera:
    """The render camera of a camera sensor; every property reads the sensor's current
    spec, zoom and pose."""

    def __init__(self, sensor: Any) -> None:
        self._sensor = sensor

    @property
    def node(self):
        """The sensor's scene node (Habitat's ``render_camera.node``)."""
        return self._sensor.node

    object = node

    @property
    def projection_matrix(self) -> mn.Matrix4:
        return mn.Matrix4(projection_matrix(self._sensor.camera_key()))

    @property
    def camera_matrix(self) -> mn.Matrix4:
        """``camera_from_world``: the inverse of the sensor node's world pose."""
        return mn.Matrix4(np.linalg.inv(self._sensor.world_from_camera()))

    @property
    def viewport(self) -> mn.Vector2i:
        """``(width, height)`` in pixels."""
        height, width = self._sensor.camera_key()[0]
        return mn.Vector2i(width, height)

    def projection_size(self) -> mn.Vector2:
        matrix = projection_matrix(self._sensor.camera_key())
        return mn.Vector2(2.0 / matrix[0, 0], 2.0 / matrix[1, 1])

    def render_camera_model(self):
        """The :class:`render.camera.Camera` the renderer draws this sensor with."""
        return camera_from_key(self._sensor.camera_key())

    def unproject(self, viewport_point: Any, normalized: bool = True) -> Ray:
        """The world ray through pixel ``viewport_point = (x, y)`` (module docstring)."""
        point = np.asarray(viewport_point, dtype=np.float64).reshape(-1)
        if point.shape != (2,) or not np.all(np.isfinite(point)):
            raise ValueError(f"viewport_point must be two finite numbers, got {viewport_point!r}")
        key = self._sensor.camera_key()
        (height, width), far = key[0], key[3]
        ndc = np.array(
            [2.0 * point[0] / width - 1.0, 2.0 * (height - point[1] - 1.0) / height - 1.0, 1.0, 1.0]
        )
        world_from_camera = self._sensor.world_from_camera()
        clip_to_world = world_from_camera @ np.linalg.inv(projection_matrix(key))
        far_point = clip_to_world @ ndc
        origin = world_from_camera[:3, 3]
        direction = (far_point[:3] / far_point[3] - origin) / far
        if normalized:
            direction = direction / np.linalg.norm(direction)
        return Ray(origin, direction)
