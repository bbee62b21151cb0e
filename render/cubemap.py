"""Cube maps: six 90-degree pinhole images around a camera, and their resampling.

A wide-angle camera (fisheye, equirectangular panorama) is rendered as Habitat's
``CubeMapSensorBase`` renders it:

1. **Six faces.** Six pinhole cameras at the camera's position, each with a 90-degree field
   of view and ``S x S`` pixels, look along the camera frame's ``+X, -X, +Y, -Y, +Z, -Z``
   axes (Habitat's face order). :func:`face_poses` gives their poses; the caller renders
   them with :func:`render.render_frame` like any other camera.
2. **Resample.** Every output pixel has a ray ``d`` (camera frame) from the camera model
   (:mod:`render.camera_models`). The face it hits is the axis of its largest component
   (``|d_x| >= |d_y|, |d_z|`` -> ``+X`` or ``-X`` by the sign, and so on, the first axis
   winning a tie). In that face's frame, ``d_face = R_face^T d`` points down the face's -Z,
   and the face's pinhole projection gives the texel (``f = S / 2``)::

       px = S/2 + f x_face / (-z_face),   py = S/2 - f y_face / (-z_face)
       col = clamp(floor(px), 0, S - 1),  row = clamp(floor(py), 0, S - 1)

   Depth and semantic ids take that texel (nearest sampling). Depth is the face's z-depth,
   the distance along the axis of the face the ray hits (what a cube map of z-buffers
   holds, as in Habitat).
3. **Bilinear color.** Color is filtered as a GPU's linear texture sampling does (Habitat
   samples its color cube map with linear filtering): with texel centers at ``i + 1/2``,
   ``u = px - 1/2``, ``v = py - 1/2``, ``i = floor(u)``, ``j = floor(v)``, ``a = u - i``,
   ``b = v - j``, the four texels around the point are weighted::

       c = (1-a)(1-b) t[j, i] + a (1-b) t[j, i+1] + (1-a) b t[j+1, i] + a b t[j+1, i+1]

   with indices clamped to the face (no filtering across a face seam), each 8-bit channel
   rounded, ``floor(c + 1/2)``.

:func:`resample` is the vectorized version; :func:`resample_reference` is the same, one
pixel at a time in plain Python (slow; the tests check they agree bit for bit). One switch
selects between them: ``resample(..., reference=True)``; ``bilinear=True`` selects step 3.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "FACE_NAMES",
    "FACE_ROTATIONS",
    "cubemap_size",
    "face_points",
    "face_poses",
    "face_texels",
    "resample",
    "resample_reference",
]

#: the faces in Habitat's order, named by the camera-frame axis they look along
FACE_NAMES = ("+X", "-X", "+Y", "-Y", "+Z", "-Z")

#: ``camera_from_face`` rotations (6, 3, 3): each maps the face camera's -Z onto its axis
#: (yaw -90 / +90 degrees about Y, pitch +90 / -90 about X, yaw 180, identity); entries are
#: 0 or +-1, so rotating a ray is exact
FACE_ROTATIONS = np.array(
    [
        [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],  # +X: R_y(-90 deg)
        [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],  # -X: R_y(+90 deg)
        [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],  # +Y: R_x(+90 deg)
        [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],  # -Y: R_x(-90 deg)
        [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],  # +Z: R_y(180 deg)
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],  # -Z: identity
    ]
)


def cubemap_size(resolution: tuple[int, int], size: int | None = None) -> int:
    """Face size ``S``: ``size`` when given, else ``min(H, W)`` (Habitat's rule)."""
    if size is None:
        return int(min(resolution))
    if isinstance(size, bool) or not isinstance(size, int | np.integer) or size < 1:
        raise ValueError(f"cubemap_size must be a positive int or None, got {size!r}")
    return int(size)


def face_poses(world_from_camera: np.ndarray) -> np.ndarray:
    """The six face cameras' poses ``(6, 4, 4)``: ``world_from_camera @ camera_from_face``."""
    pose = np.asarray(world_from_camera, dtype=np.float64)
    faces = np.repeat(pose[None], 6, axis=0)
    faces[:, :3, :3] = pose[:3, :3] @ FACE_ROTATIONS  # R_world_face = R_world_cam R_cam_face
    return faces


def face_points(rays: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Face index and continuous face image coordinates ``(px, py)`` of each ray
    (vectorized; module docstring, step 2).

    Parameters
    ----------
    rays : (..., 3) float, camera frame, non-zero.
    size : S, the faces' width and height in pixels.

    Returns
    -------
    face : (...) int64; px, py : (...) float64.
    """
    axis = np.argmax(np.abs(rays), axis=-1)  # first axis wins a tie
    component = np.take_along_axis(rays, axis[..., None], axis=-1)[..., 0]
    face = 2 * axis + (component < 0.0)  # +axis is face 2k, -axis is 2k + 1
    # d_face = R^T d: row i of R^T is column i of R
    d_face = np.einsum("...ji,...j->...i", FACE_ROTATIONS[face], rays)
    forward = -d_face[..., 2]  # = |d_axis| > 0
    half = size / 2.0
    px = half + half * d_face[..., 0] / forward  # px = S/2 + f x / z
    py = half - half * d_face[..., 1] / forward  # py = S/2 - f y / z
    return face, px, py


def face_texels(rays: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Face index, row and column hit by each ray (the nearest texel), ``(...)`` int64."""
    face, px, py = face_points(rays, size)
    col = np.clip(np.floor(px), 0, size - 1).astype(np.int64)
    row = np.clip(np.floor(py), 0, size - 1).astype(np.int64)
    return face, row, col


def _bilinear(faces: np.ndarray, face: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Step 3 for points ``(N,)`` of 8-bit color faces ``(6, S, S, C)``: ``(N, C)``."""
    size = faces.shape[1]
    u, v = px - 0.5, py - 0.5
    i, j = np.floor(u), np.floor(v)
    a, b = (u - i)[:, None], (v - j)[:, None]
    i0, j0 = np.clip(i, 0, size - 1).astype(np.int64), np.clip(j, 0, size - 1).astype(np.int64)
    i1, j1 = (
        np.clip(i + 1, 0, size - 1).astype(np.int64),
        np.clip(j + 1, 0, size - 1).astype(np.int64),
    )
    t = faces.astype(np.float64)
    c = (1.0 - a) * (1.0 - b) * t[face, j0, i0]
    c = c + a * (1.0 - b) * t[face, j0, i1]
    c = c + (1.0 - a) * b * t[face, j1, i0]
    c = c + a * b * t[face, j1, i1]
    return np.floor(c + 0.5).astype(faces.dtype)


def resample(
    faces: np.ndarray,
    rays: np.ndarray,
    valid: np.ndarray | None = None,
    background: object = 0,
    reference: bool = False,
    bilinear: bool = False,
) -> np.ndarray:
    """Look every ray up in a cube map (nearest texel, or bilinear for 8-bit color).

    Parameters
    ----------
    faces : (6, S, S, ...) the six faces' buffers (color ``(6, S, S, 4) uint8``, depth
        ``(6, S, S) float32`` z-depth per face, or ids ``(6, S, S) uint32``), Habitat's order.
    rays : (H, W, 3) float64 camera-frame rays of the output image.
    valid : (H, W) bool, the pixels that see anything (None: all).
    background : the value of invalid pixels (broadcast to one texel).
    reference : True: :func:`resample_reference` (plain loops, same result).
    bilinear : True: filter color bilinearly (module docstring, step 3; ``(6, S, S, C)``
        uint8 faces only).

    Returns
    -------
    (H, W, ...) array of ``faces.dtype``.
    """
    if bilinear and (faces.dtype != np.uint8 or faces.ndim != 4):
        raise ValueError(
            f"bilinear resampling needs (6, S, S, C) uint8 color faces, got "
            f"{faces.shape} {faces.dtype}"
        )
    if reference:
        return resample_reference(faces, rays, valid, background, bilinear)
    height, width = rays.shape[:2]
    if valid is None:
        valid = np.ones((height, width), bool)
    out = np.empty((height, width, *faces.shape[3:]), faces.dtype)
    out[...] = background
    safe = np.where(valid[..., None], rays, (0.0, 0.0, -1.0))  # no zero rays
    if bilinear:
        face, px, py = face_points(safe, faces.shape[1])
        out[valid] = _bilinear(faces, face[valid], px[valid], py[valid])
        return out
    face, row, col = face_texels(safe, faces.shape[1])
    out[valid] = faces[face[valid], row[valid], col[valid]]
    return out


def resample_reference(
    faces: np.ndarray,
    rays: np.ndarray,
    valid: np.ndarray | None = None,
    background: object = 0,
    bilinear: bool = False,
) -> np.ndarray:
    """Mirrors :func:`resample`, one pixel at a time with scalar arithmetic."""
    height, width = rays.shape[:2]
    size = faces.shape[1]
    out = np.empty((height, width, *faces.shape[3:]), faces.dtype)
    out[...] = background
    for r in range(height):
        for c in range(width):
            if valid is not None and not valid[r, c]:
                continue
            d = [float(v) for v in rays[r, c]]
            magnitudes = [abs(v) for v in d]
            axis = magnitudes.index(max(magnitudes))  # the first largest component
            face = 2 * axis + (1 if d[axis] < 0.0 else 0)
            rotation = FACE_ROTATIONS[face]
            # d_face_i = sum_j R_ji d_j  (R^T d)
            x, y, z = (sum(float(rotation[j, i]) * d[j] for j in range(3)) for i in range(3))
            half = size / 2.0
            px = half + half * x / -z
            py = half - half * y / -z
            if bilinear:
                out[r, c] = _bilinear_texel(faces[face], px, py)
                continue
            col = min(max(math.floor(px), 0), size - 1)
            row = min(max(math.floor(py), 0), size - 1)
            out[r, c] = faces[face, row, col]
    return out


def _bilinear_texel(texels: np.ndarray, px: float, py: float) -> list[int]:
    """Step 3 for one point of one face ``(S, S, C)``, channel by channel."""
    size = texels.shape[0]
    u, v = px - 0.5, py - 0.5
    i, j = math.floor(u), math.floor(v)
    a, b = u - i, v - j
    i0, i1 = min(max(i, 0), size - 1), min(max(i + 1, 0), size - 1)
    j0, j1 = min(max(j, 0), size - 1), min(max(j + 1, 0), size - 1)
    channels = []
    for k in range(texels.shape[2]):
        c = (1.0 - a) * (1.0 - b) * float(texels[j0, i0, k])
        c = c + a * (1.0 - b) * float(texels[j0, i1, k])
        c = c + (1.0 - a) * b * float(texels[j1, i0, k])
        c = c + a * b * float(texels[j1, i1, k])
        channels.append(math.floor(c + 0.5))
    return channels
